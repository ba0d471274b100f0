#include "msm_sim/dynamics/world.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "geometry/spatial_hash_grid.h"
#include "msm_sim/mechanics/stable_time_step.h"

namespace msm_sim::core {
namespace {

void Require(bool condition, const std::string& message) {
  if (!condition) throw std::invalid_argument(message);
}

bool Finite(double value) { return std::isfinite(value); }

// Nodes of one body collide only if they were at least this many longest springs apart at rest.
constexpr double kSelfContactRestDistance = 2.5;

// The collider pose after moving for tau seconds with its (constant) twist.
Eigen::Isometry3d Advance(const Eigen::Isometry3d& pose, const Collider& collider, double tau) {
  Eigen::Isometry3d moved = pose;
  moved.translation() += tau * collider.linear_velocity;
  const double angle = collider.angular_velocity.norm() * tau;
  if (angle > 0.0) {
    moved.linear() =
        Eigen::AngleAxisd(angle, collider.angular_velocity.normalized()).toRotationMatrix() *
        pose.linear();
  }
  return moved;
}

// A contact of one node with one collider during the detection of a substep.
struct NodeContact {
  int collider;
  Eigen::Vector3d normal;    // unit, out of the collider
  Eigen::Vector3d point;     // on the collider's surface
  Eigen::Vector3d velocity;  // of the collider's material there
  double stopped = 0.0;      // normal velocity change that stopped the approach (>= 0)
};

}  // namespace

World::Body::Body(const std::string& body_name, std::shared_ptr<const Model> body_model,
                  const BodyOptions& body_options, double time_step_safety)
    : name(body_name),
      model(std::move(body_model)),
      options(body_options),
      state(State::AtRest(*model)),
      evaluator(*model, body_options.dispersion),
      border(FindBorderNodes(*model)),
      constrained(model->num_nodes(), 0),
      inverse_masses(model->masses().cwiseInverse()),
      forces(Eigen::Matrix3Xd::Zero(3, model->num_nodes())) {
  const double longest = model->num_springs() > 0
                             ? *std::max_element(model->spring_rest_length().begin(),
                                                 model->spring_rest_length().end())
                             : model->characteristic_length();
  self_contact_rest_distance_sq = std::pow(kSelfContactRestDistance * longest, 2);
  StableTimeStepOptions step;
  step.damping_beta = body_options.damping_beta;
  step.safety = time_step_safety;
  stable_step = StableTimeStep(*model, step);
}

void World::ImpulseSum::Add(const Eigen::Vector3d& point, const Eigen::Vector3d& origin,
                            const Eigen::Vector3d& on_collider) {
  const double magnitude = on_collider.norm();
  if (magnitude == 0.0) return;
  impulse += on_collider;
  moment += (point - origin).cross(on_collider);
  weighted_point += magnitude * point;
  weight += magnitude;
  ++count;
}

World::World(const WorldOptions& options) : options_(options) {
  Require(options.gravity.allFinite(), "gravity must be finite");
  Require(options.time_step_safety > 0.0 && options.time_step_safety <= 1.0,
          "time step safety must lie in (0, 1]");
  Require(options.max_speed > 0.0, "max speed must be > 0");
  Require(options.contact_iterations >= 1, "contact iterations must be >= 1");
}

static void ValidateBodyOptions(const std::string& name, const BodyOptions& options) {
  Require(options.damping_beta >= 0.0 && Finite(options.damping_beta),
          "body '" + name + "': damping must be finite and >= 0");
  Require(options.friction >= 0.0 && Finite(options.friction),
          "body '" + name + "': friction must be finite and >= 0");
  Require(options.restitution >= 0.0 && options.restitution <= 1.0,
          "body '" + name + "': restitution must lie in [0, 1]");
}

int World::AddBody(const std::string& name, std::shared_ptr<const Model> model,
                   const BodyOptions& options) {
  Require(model != nullptr, "body '" + name + "' has no model");
  ValidateBodyOptions(name, options);
  Body body(name, model, options, options_.time_step_safety);
  body.pair_friction.assign(colliders_.size(), -1.0);
  body.wrenches.assign(colliders_.size(), ContactWrench{});
  bodies_.push_back(std::move(body));
  return static_cast<int>(bodies_.size()) - 1;
}

int World::AddCollider(const Collider& collider) {
  Require(collider.pose.matrix().allFinite() && collider.linear_velocity.allFinite() &&
              collider.angular_velocity.allFinite(),
          "collider '" + collider.name + "': pose and twist must be finite");
  Require(collider.friction >= 0.0 && Finite(collider.friction),
          "collider '" + collider.name + "': friction must be finite and >= 0");
  Require(collider.restitution >= 0.0 && collider.restitution <= 1.0,
          "collider '" + collider.name + "': restitution must lie in [0, 1]");
  colliders_.push_back(collider);
  for (Body& body : bodies_) {
    body.pair_friction.push_back(-1.0);
    // Wrenches are colliders first, then groups.
    body.wrenches.insert(body.wrenches.begin() + colliders_.size() - 1, ContactWrench{});
  }
  return static_cast<int>(colliders_.size()) - 1;
}

int World::AddKinematicGroup(int body_index, const KinematicGroup& group) {
  Require(body_index >= 0 && body_index < num_bodies(), "no body " + std::to_string(body_index));
  Body& body = bodies_[body_index];
  Require(!group.nodes.empty(), "kinematic group '" + group.name + "' has no nodes");
  Group added{group, Eigen::Matrix3Xd(3, group.nodes.size()), Eigen::Isometry3d::Identity()};
  const Eigen::Isometry3d pose = group.pose ? group.pose(time_) : added.initial_pose;
  Require(pose.matrix().allFinite(), "kinematic group '" + group.name + "': pose not finite");
  // Check every index before changing anything.
  for (const NodeIndex node : group.nodes) {
    Require(node >= 0 && node < body.model->num_nodes(),
            "kinematic group '" + group.name + "': no node " + std::to_string(node));
  }
  const Eigen::Isometry3d inverse = pose.inverse();
  for (std::size_t k = 0; k < group.nodes.size(); ++k) {
    const NodeIndex node = group.nodes[k];
    added.local.col(k) = inverse * Eigen::Vector3d(body.state.positions.col(node));
    body.constrained[node] = 1;
    body.state.velocities.col(node).setZero();
  }
  added.initial_pose = pose;
  body.groups.push_back(std::move(added));
  body.wrenches.push_back(ContactWrench{});
  return static_cast<int>(body.groups.size()) - 1;
}

void World::ApplyForce(int body_index, const Eigen::Vector3d& point, const Eigen::Vector3d& force,
                       double radius, double duration) {
  ApplyWrench(body_index, point, force, Eigen::Vector3d::Zero(), radius, duration);
}

void World::ApplyWrench(int body_index, const Eigen::Vector3d& point, const Eigen::Vector3d& force,
                        const Eigen::Vector3d& torque, double radius, double duration) {
  Require(body_index >= 0 && body_index < num_bodies(), "no body " + std::to_string(body_index));
  Require(point.allFinite() && force.allFinite() && torque.allFinite(),
          "force, torque and point must be finite");
  Require(radius >= 0.0 && Finite(radius), "force radius must be finite and >= 0");
  Require(duration >= 0.0 && Finite(duration), "force duration must be finite and >= 0");
  const Body& body = bodies_[body_index];
  const Eigen::Matrix3Xd& x = body.state.positions;
  const Eigen::VectorXd& m = body.model->masses();
  Push push{{}, {}, duration};
  NodeIndex nearest = 0;
  double nearest_distance = std::numeric_limits<double>::infinity();
  double total_mass = 0.0;
  for (NodeIndex i = 0; i < body.model->num_nodes(); ++i) {
    const double distance = (x.col(i) - point).norm();
    if (distance < nearest_distance) {
      nearest_distance = distance;
      nearest = i;
    }
    if (distance <= radius) {
      push.nodes.push_back(i);
      total_mass += m[i];
    }
  }
  if (push.nodes.empty()) {
    push.nodes.push_back(nearest);
    total_mass = m[nearest];
  }
  double lever_sq = 0.0;
  for (const NodeIndex i : push.nodes) lever_sq += (x.col(i) - point).squaredNorm();
  for (const NodeIndex i : push.nodes) {
    Eigen::Vector3d node_force = force * (m[i] / total_mass);
    if (lever_sq > 0.0) node_force += torque.cross(x.col(i) - point) / lever_sq;
    push.forces.push_back(node_force);
  }
  bodies_[body_index].pushes.push_back(std::move(push));
}

void World::ReplaceModel(int body_index, std::shared_ptr<const Model> model,
                         const BodyOptions& options) {
  Require(body_index >= 0 && body_index < num_bodies(), "no body " + std::to_string(body_index));
  Require(model != nullptr, "no model");
  Body& old = bodies_[body_index];
  ValidateBodyOptions(old.name, options);
  Require(model->num_nodes() == old.model->num_nodes(),
          "the new model has " + std::to_string(model->num_nodes()) + " nodes, the body " +
              std::to_string(old.model->num_nodes()));
  Body body(old.name, model, options, options_.time_step_safety);
  body.state = old.state;
  body.groups = old.groups;
  body.constrained = old.constrained;
  body.pushes = old.pushes;
  body.pending = old.pending;
  body.pair_friction = old.pair_friction;
  body.wrenches = old.wrenches;
  bodies_[body_index] = std::move(body);
}

void World::SetPairFriction(int body, int collider, double friction) {
  Require(body >= 0 && body < num_bodies() && collider >= 0 && collider < num_colliders(),
          "no such body or collider");
  Require(friction >= 0.0 && Finite(friction), "friction must be finite and >= 0");
  bodies_[body].pair_friction[collider] = friction;
}

void World::SetState(int body_index, const State& state) {
  Require(body_index >= 0 && body_index < num_bodies(), "no body " + std::to_string(body_index));
  Body& body = bodies_[body_index];
  Require(state.positions.cols() == body.model->num_nodes() &&
              state.velocities.cols() == body.model->num_nodes(),
          "state size does not match the model");
  Require(state.positions.allFinite() && state.velocities.allFinite(), "state must be finite");
  body.state = state;
  body.pending.clear();
}

double World::Friction(const Body& body, int collider) const {
  const double pair = body.pair_friction[collider];
  return pair >= 0.0 ? pair : std::sqrt(body.options.friction * colliders_[collider].friction);
}

double World::stable_time_step() const {
  double step = std::numeric_limits<double>::infinity();
  for (const Body& body : bodies_) step = std::min(step, body.stable_step);
  return step;
}

Eigen::Isometry3d World::GroupPose(const Group& group, double t) const {
  return group.spec.pose ? group.spec.pose(t) : group.initial_pose;
}

void World::PlaceGroups(Body* body, double t) const {
  for (const Group& group : body->groups) {
    const Eigen::Isometry3d pose = GroupPose(group, t);
    for (std::size_t k = 0; k < group.spec.nodes.size(); ++k) {
      body->state.positions.col(group.spec.nodes[k]) = pose * Eigen::Vector3d(group.local.col(k));
    }
  }
}

Energies World::ComputeEnergies(int body_index) const {
  const Body& body = bodies_.at(body_index);
  const Eigen::VectorXd& m = body.model->masses();
  Energies energies;
  // The pending restitution is part of the nodes' motion: between substeps a node that just hit
  // a surface is momentarily stopped and carries its rebound there.
  Eigen::Matrix3Xd velocities = body.state.velocities;
  for (const PendingResponse& response : body.pending) {
    velocities.col(response.node) += response.delta_v;
  }
  energies.kinetic = 0.5 * velocities.colwise().squaredNorm().dot(m.transpose());
  energies.elastic = body.evaluator.ElasticEnergy(body.state.positions);
  energies.gravitational =
      -(options_.gravity.transpose() * body.state.positions).dot(m.transpose());
  return energies;
}

void World::Reset() {
  for (Body& body : bodies_) {
    body.state = State::AtRest(*body.model);
    body.pending.clear();
    body.pushes.clear();
    PlaceGroups(&body, 0.0);
    std::fill(body.wrenches.begin(), body.wrenches.end(), ContactWrench{});
  }
  time_ = 0.0;
}

std::string World::CheckSane() const {
  for (const Body& body : bodies_) {
    const double speed = std::sqrt(body.fastest_speed_sq);
    if (!std::isfinite(speed)) {
      return "body '" + body.name + "': a node position or velocity became non-finite (node " +
             std::to_string(body.fastest_node) + ")";
    }
    if (speed > options_.max_speed) {
      std::ostringstream reason;
      reason << "body '" << body.name << "': node " << body.fastest_node << " would move at "
             << speed << " m/s, above the " << options_.max_speed
             << " m/s limit (an absurd force, or a diverging simulation)";
      return reason.str();
    }
  }
  return {};
}

StepReport World::Step(double dt) {
  Require(dt > 0.0 && Finite(dt), "step must be finite and > 0");
  StepReport report;
  // Everything a rejected step must give back (into buffers kept between steps: a fresh 300 kB
  // allocation per step is an mmap and page faults, a tenth of a 12k-node step).
  std::vector<Eigen::Isometry3d> poses;
  for (Body& body : bodies_) {
    body.saved_positions = body.state.positions;
    body.saved_velocities = body.state.velocities;
    body.saved_pending = body.pending;
  }
  for (const Collider& collider : colliders_) poses.push_back(collider.pose);
  const double start_time = time_;

  const double stable = stable_time_step();
  report.substeps = std::isfinite(stable) ? static_cast<int>(std::ceil(dt / stable - 1e-9)) : 1;
  report.substeps = std::max(report.substeps, 1);
  report.substep = dt / report.substeps;
  for (Body& body : bodies_) {
    body.impulses.assign(colliders_.size() + body.groups.size(), ImpulseSum{});
  }
  microcollisions_ = 0;
  for (Body& body : bodies_) body.fastest_speed_sq = 0.0;
  for (int k = 0; k < report.substeps; ++k) {
    Substep(report.substep, poses, k * report.substep);
    const std::string problem = CheckSane();
    if (!problem.empty()) {
      for (Body& body : bodies_) {
        body.state.positions = body.saved_positions;
        body.state.velocities = body.saved_velocities;
        body.pending = body.saved_pending;
      }
      for (std::size_t c = 0; c < colliders_.size(); ++c) colliders_[c].pose = poses[c];
      time_ = start_time;
      // An absurd push is what usually makes a step fail; keeping it would fail every step.
      bool dropped = false;
      for (Body& body : bodies_) {
        dropped = dropped || !body.pushes.empty();
        body.pushes.clear();
      }
      report.accepted = false;
      report.reason = problem + (dropped ? "; the step's applied forces were dropped" : "");
      return report;
    }
  }
  time_ = start_time + dt;
  for (std::size_t c = 0; c < colliders_.size(); ++c) {
    colliders_[c].pose = Advance(poses[c], colliders_[c], dt);
  }
  for (Body& body : bodies_) {
    // Pushes for "one step" are done; timed ones count down.
    for (Push& push : body.pushes) push.remaining -= dt;
    body.pushes.erase(std::remove_if(body.pushes.begin(), body.pushes.end(),
                                     [](const Push& push) { return push.remaining <= 1e-12; }),
                      body.pushes.end());
    body.wrenches.resize(body.impulses.size());
    for (std::size_t w = 0; w < body.impulses.size(); ++w) {
      const ImpulseSum& sum = body.impulses[w];
      ContactWrench& wrench = body.wrenches[w];
      wrench.force = sum.impulse / dt;
      wrench.torque = sum.moment / dt;
      wrench.centroid = sum.weight > 0.0 ? Eigen::Vector3d(sum.weighted_point / sum.weight)
                                         : Eigen::Vector3d::Zero();
      wrench.microcollisions = sum.count;
    }
  }
  report.microcollisions = microcollisions_;
  return report;
}

void World::Substep(double h, const std::vector<Eigen::Isometry3d>& start_poses, double step_time) {
  const double t0 = time_ + step_time;  // time_ stays at the step's start until it ends
  // 1. Half a drift; kinematic nodes go where their frame is at mid-substep.
  for (Body& body : bodies_) {
    body.state.positions += (0.5 * h) * body.state.velocities;
    PlaceGroups(&body, t0 + 0.5 * h);
    // 2. The rest of last substep's contact response.
    for (const PendingResponse& response : body.pending) {
      body.state.velocities.col(response.node) += response.delta_v;
    }
    body.pending.clear();
    // 3. Forces.
    body.forces.setZero();
    body.evaluator.AccumulateForces(body.state.positions, body.state.velocities,
                                    body.options.damping_beta, &body.forces);
    const Eigen::VectorXd& m = body.model->masses();
    for (const Push& push : body.pushes) {
      for (std::size_t k = 0; k < push.nodes.size(); ++k) {
        body.forces.col(push.nodes[k]) += push.forces[k];
      }
    }
    // 4. Kick, with gravity (one pass over the nodes: this loop and the drifts are a third of a
    // 12k-node step besides the force evaluation).
    {
      const double* __restrict f = body.forces.data();
      const double* __restrict inverse_mass = body.inverse_masses.data();
      double* __restrict v = body.state.velocities.data();
      const double g[3] = {h * options_.gravity.x(), h * options_.gravity.y(),
                           h * options_.gravity.z()};
      const int n = body.model->num_nodes();
      for (int i = 0; i < n; ++i) {
        const double scale = h * inverse_mass[i];
        for (int d = 0; d < 3; ++d) v[3 * i + d] += scale * f[3 * i + d] + g[d];
      }
    }
    for (std::size_t g = 0; g < body.groups.size(); ++g) {
      const Group& group = body.groups[g];
      const Eigen::Isometry3d from = GroupPose(group, t0);
      const Eigen::Isometry3d to = GroupPose(group, t0 + h);
      const Eigen::Isometry3d mid = GroupPose(group, t0 + 0.5 * h);
      ImpulseSum& reaction = body.impulses[colliders_.size() + g];
      for (std::size_t k = 0; k < group.spec.nodes.size(); ++k) {
        const NodeIndex node = group.spec.nodes[k];
        const Eigen::Vector3d local = group.local.col(k);
        const Eigen::Vector3d prescribed = (to * local - from * local) / h;
        // The group gave the node m (v_prescribed - v_free); the node pushed back.
        const Eigen::Vector3d on_group =
            -m[node] * (prescribed - Eigen::Vector3d(body.state.velocities.col(node)));
        reaction.Add(body.state.positions.col(node), mid.translation(), on_group);
        body.state.velocities.col(node) = prescribed;
      }
    }
  }
  // 5-6. Contacts at mid-substep positions, colliders at their mid-substep poses.
  for (std::size_t c = 0; c < colliders_.size(); ++c) {
    colliders_[c].pose = Advance(start_poses[c], colliders_[c], step_time + 0.5 * h);
  }
  for (Body& body : bodies_) CollideWithColliders(&body, &microcollisions_);
  CollideNodes(&microcollisions_);
  // 7. The other half drift, noting the fastest node for the sanity check.
  for (Body& body : bodies_) {
    const double* __restrict v = body.state.velocities.data();
    double* __restrict x = body.state.positions.data();
    const int n = body.model->num_nodes();
    double fastest = 0.0;
    int fastest_node = 0;
    double position_sum = 0.0;  // non-finite if any position is
    for (int i = 0; i < n; ++i) {
      double speed_sq = 0.0;
      for (int d = 0; d < 3; ++d) {
        x[3 * i + d] += 0.5 * h * v[3 * i + d];
        speed_sq += v[3 * i + d] * v[3 * i + d];
        position_sum += x[3 * i + d];
      }
      // Also catches NaN: the comparison is false, and NaN is "not <=" any bound.
      if (!(speed_sq <= fastest)) {
        fastest = std::isnan(speed_sq) ? std::numeric_limits<double>::infinity() : speed_sq;
        fastest_node = i;
      }
    }
    if (!std::isfinite(position_sum)) fastest = std::numeric_limits<double>::infinity();
    if (fastest > body.fastest_speed_sq) {
      body.fastest_speed_sq = fastest;
      body.fastest_node = fastest_node;
    }
    PlaceGroups(&body, t0 + h);
  }
}

void World::CollideWithColliders(Body* body, int* microcollisions) {
  if (colliders_.empty()) return;
  const Eigen::VectorXd& m = body->model->masses();
  // Each collider's bounds in its frame (planes are unbounded).
  std::vector<char> bounded(colliders_.size());
  std::vector<Eigen::Vector3d> lo(colliders_.size()), hi(colliders_.size());
  std::vector<Eigen::Isometry3d> inverse(colliders_.size());
  for (std::size_t c = 0; c < colliders_.size(); ++c) {
    bounded[c] = colliders_[c].shape.Bounds(&lo[c], &hi[c]);
    inverse[c] = colliders_[c].pose.inverse();
  }
  std::vector<NodeContact> contacts;
  for (std::size_t k = 0; k < body->border.nodes.size(); ++k) {
    const NodeIndex node = body->border.nodes[k];
    if (body->constrained[node]) continue;
    const double radius = body->border.radii[k];
    const Eigen::Vector3d x = body->state.positions.col(node);
    contacts.clear();
    for (std::size_t c = 0; c < colliders_.size(); ++c) {
      if (!colliders_[c].enabled) continue;
      const Eigen::Vector3d local = inverse[c] * x;
      if (bounded[c] && ((local.array() < lo[c].array() - radius).any() ||
                         (local.array() > hi[c].array() + radius).any())) {
        continue;
      }
      Eigen::Vector3d normal, closest;
      if (colliders_[c].shape.SignedDistance(local, &normal, &closest) >= radius) continue;
      const Eigen::Vector3d point = colliders_[c].pose * closest;
      contacts.push_back({static_cast<int>(c), colliders_[c].pose.linear() * normal, point,
                          colliders_[c].VelocityAt(point)});
    }
    if (contacts.empty()) continue;
    Eigen::Vector3d v = body->state.velocities.col(node);
    // Stop every approach (Gauss-Seidel over this node's contacts).
    for (int sweep = 0; sweep < options_.contact_iterations; ++sweep) {
      bool approaching = false;
      for (NodeContact& contact : contacts) {
        const double vn = (v - contact.velocity).dot(contact.normal);
        if (vn < 0.0) {
          v -= vn * contact.normal;
          contact.stopped -= vn;
          approaching = true;
        }
      }
      if (!approaching) break;
    }
    for (NodeContact& contact : contacts) {
      if (contact.stopped <= 0.0) continue;
      const Collider& collider = colliders_[contact.collider];
      const double e = std::min(collider.restitution, body->options.restitution);
      // Friction: up to mu times this contact's normal velocity change, against the sliding
      // velocity, never reversing it.
      const Eigen::Vector3d relative = v - contact.velocity;
      const Eigen::Vector3d sliding = relative - relative.dot(contact.normal) * contact.normal;
      const double slide_speed = sliding.norm();
      Eigen::Vector3d friction = Eigen::Vector3d::Zero();
      if (slide_speed > 0.0) {
        const double limit = Friction(*body, contact.collider) * (1.0 + e) * contact.stopped;
        friction = -std::min(limit, slide_speed) / slide_speed * sliding;
        v += friction;
      }
      if (e > 0.0) body->pending.push_back({node, e * contact.stopped * contact.normal});
      const Eigen::Vector3d on_node =
          m[node] * ((1.0 + e) * contact.stopped * contact.normal + friction);
      body->impulses[contact.collider].Add(contact.point, collider.pose.translation(), -on_node);
      ++*microcollisions;
    }
    body->state.velocities.col(node) = v;
  }
}

void World::CollideNodes(int* microcollisions) {
  struct Entry {
    int body;
    NodeIndex node;
    double radius;
  };
  std::vector<Entry> entries;
  double max_radius = 0.0;
  bool any_self = false;
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    any_self = any_self || bodies_[b].options.self_collision;
    for (std::size_t k = 0; k < bodies_[b].border.nodes.size(); ++k) {
      entries.push_back(
          {static_cast<int>(b), bodies_[b].border.nodes[k], bodies_[b].border.radii[k]});
      max_radius = std::max(max_radius, bodies_[b].border.radii[k]);
    }
  }
  if (entries.empty() || (bodies_.size() < 2 && !any_self)) return;
  SpatialHashGrid grid(2.0 * max_radius);
  for (std::size_t e = 0; e < entries.size(); ++e) {
    grid.Insert(static_cast<int>(e), bodies_[entries[e].body].state.positions.col(entries[e].node));
  }
  // Contacts first, then Gauss-Seidel sweeps over all of them: a node resting on several nodes
  // below it must end approaching none of them (a single pass left some approach, and a block
  // stacked on another sank into it within a second).
  struct PairContact {
    Body* body_i;
    NodeIndex i;
    Body* body_j;
    NodeIndex j;
    Eigen::Vector3d normal;  // from j to i
    double inverse_mass_i, inverse_mass_j, reduced_mass, restitution, friction;
    double stopped = 0.0;  // normal impulse that stopped the approach
  };
  std::vector<PairContact> pairs;
  for (std::size_t e = 0; e < entries.size(); ++e) {
    const Entry& first = entries[e];
    Body& body_i = bodies_[first.body];
    const Eigen::Vector3d xi = body_i.state.positions.col(first.node);
    grid.ForEachWithin(xi, first.radius + max_radius, [&](int other, const Eigen::Vector3d& xj) {
      if (other <= static_cast<int>(e)) return;  // each pair once
      const Entry& second = entries[other];
      Body& body_j = bodies_[second.body];
      if (first.body == second.body) {
        // Self-contact is a fold bringing together parts of the body that were apart at rest.
        // Nodes near each other at rest (every spring-connected pair among them) only get close
        // by compressing the material between them, which the springs already resist; treating
        // that as contact made a squashed ball chatter and blow up.
        if (!body_i.options.self_collision) return;
        const Eigen::Matrix3Xd& rest = body_i.model->rest_positions();
        if ((rest.col(first.node) - rest.col(second.node)).squaredNorm() <
            body_i.self_contact_rest_distance_sq) {
          return;
        }
      }
      const Eigen::Vector3d d = xi - xj;
      const double distance = d.norm();
      if (distance >= first.radius + second.radius || distance == 0.0) return;
      // A constrained node acts as an infinite mass.
      const double inv_i =
          body_i.constrained[first.node] ? 0.0 : 1.0 / body_i.model->masses()[first.node];
      const double inv_j =
          body_j.constrained[second.node] ? 0.0 : 1.0 / body_j.model->masses()[second.node];
      if (inv_i + inv_j == 0.0) return;
      pairs.push_back({&body_i, first.node, &body_j, second.node, d / distance, inv_i, inv_j,
                       1.0 / (inv_i + inv_j),
                       std::min(body_i.options.restitution, body_j.options.restitution),
                       std::sqrt(body_i.options.friction * body_j.options.friction)});
    });
  }
  if (pairs.empty()) return;
  for (int sweep = 0; sweep < options_.contact_iterations; ++sweep) {
    bool approaching = false;
    for (PairContact& pair : pairs) {
      auto vi = pair.body_i->state.velocities.col(pair.i);
      auto vj = pair.body_j->state.velocities.col(pair.j);
      const double vn = (vi - vj).dot(pair.normal);
      if (vn >= 0.0) continue;
      const double impulse = -vn * pair.reduced_mass;
      vi += impulse * pair.inverse_mass_i * pair.normal;
      vj -= impulse * pair.inverse_mass_j * pair.normal;
      pair.stopped += impulse;
      approaching = true;
    }
    if (!approaching) break;
  }
  for (PairContact& pair : pairs) {
    if (pair.stopped <= 0.0) continue;
    auto vi = pair.body_i->state.velocities.col(pair.i);
    auto vj = pair.body_j->state.velocities.col(pair.j);
    // Friction up to mu times the pair's normal impulse, never reversing the sliding.
    const Eigen::Vector3d relative = vi - vj;
    const Eigen::Vector3d sliding = relative - relative.dot(pair.normal) * pair.normal;
    const double slide_speed = sliding.norm();
    if (slide_speed > 0.0) {
      const double tangential = std::min(pair.friction * (1.0 + pair.restitution) * pair.stopped,
                                         pair.reduced_mass * slide_speed);
      vi -= tangential * pair.inverse_mass_i / slide_speed * sliding;
      vj += tangential * pair.inverse_mass_j / slide_speed * sliding;
    }
    if (pair.restitution > 0.0) {
      const Eigen::Vector3d rebound = pair.restitution * pair.stopped * pair.normal;
      pair.body_i->pending.push_back({pair.i, pair.inverse_mass_i * rebound});
      pair.body_j->pending.push_back({pair.j, -pair.inverse_mass_j * rebound});
    }
    ++*microcollisions;
  }
}

}  // namespace msm_sim::core
