// World's API and bookkeeping: bodies, colliders, kinematic groups, pushes, states, energies.
#include "msm_sim/dynamics/world.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "dynamics/implicit_integrator.h"
#include "dynamics/step_loop.h"
#include "dynamics/world_internal.h"
#include "dynamics/world_state.h"

namespace msm_sim::core {
namespace {

using internal::Body;
using internal::Finite;
using internal::Group;
using internal::PendingResponse;
using internal::Push;
using internal::Require;

}  // namespace

World::World(const WorldOptions& options)
    : state_(std::make_unique<internal::WorldState>(options)),
      step_loop_(std::make_unique<internal::StepLoop>(state_.get())) {
  Require(options.gravity.allFinite(), "gravity must be finite");
  Require(options.time_step_safety > 0.0 && options.time_step_safety <= 1.0,
          "time step safety must lie in (0, 1]");
  Require(options.max_speed > 0.0, "max speed must be > 0");
  Require(options.max_substep_refinement >= 1 &&
              (options.max_substep_refinement & (options.max_substep_refinement - 1)) == 0,
          "max substep refinement must be a power of 2 (1 turns it off)");
  Require(options.contact_iterations >= 1, "contact iterations must be >= 1");
  Require(options.max_pending_pushes >= 1, "max pending pushes must be >= 1");
  Require(options.max_pending_force > 0.0 && Finite(options.max_pending_force),
          "max pending force must be finite and > 0");
  Require(options.implicit_max_substep > 0.0 && Finite(options.implicit_max_substep),
          "implicit max substep must be finite and > 0");
  Require(options.implicit_tolerance > 0.0 && options.implicit_tolerance < 1.0,
          "implicit tolerance must lie in (0, 1)");
  Require(options.implicit_early_tolerance >= options.implicit_tolerance &&
              options.implicit_early_tolerance < 1.0,
          "implicit early tolerance must lie in [implicit tolerance, 1)");
  Require(options.implicit_energy_tolerance >= 0.0 && options.implicit_energy_tolerance < 1.0,
          "implicit energy tolerance must lie in [0, 1)");
  Require(options.implicit_max_iterations >= 1, "implicit max iterations must be >= 1");
  Require(options.threads >= 1, "threads must be >= 1");
  Require(options.penetration_recovery_time > 0.0 && Finite(options.penetration_recovery_time),
          "penetration recovery time must be finite and > 0");
  Require(options.penetration_max_speed >= 0.0 && Finite(options.penetration_max_speed),
          "penetration max speed must be finite and >= 0");
}

static void ValidateBodyOptions(const std::string& name, const BodyOptions& options) {
  Require(options.damping_beta >= 0.0 && Finite(options.damping_beta),
          "body '" + name + "': damping must be finite and >= 0");
  Require(options.friction >= 0.0 && Finite(options.friction),
          "body '" + name + "': friction must be finite and >= 0");
  Require(options.restitution >= 0.0 && options.restitution <= 1.0,
          "body '" + name + "': restitution must lie in [0, 1]");
  Require(options.orientation_threshold == 0.0 ||
              (options.orientation_threshold > 0.0 && options.orientation_threshold < 1.0),
          "body '" + name + "': orientation threshold must be 0 (off) or lie in (0, 1)");
  Require(options.orientation_modulus >= 0.0 && Finite(options.orientation_modulus),
          "body '" + name + "': orientation modulus must be finite and >= 0");
}

int World::AddBody(const std::string& name, std::shared_ptr<const Model> model,
                   const BodyOptions& options) {
  Require(model != nullptr, "body '" + name + "' has no model");
  ValidateBodyOptions(name, options);
  Body body(name, model, options, state_->options);
  body.pair_friction.assign(state_->colliders.size(), -1.0);
  body.wrenches.assign(state_->colliders.size(), ContactWrench{});
  state_->bodies.push_back(std::move(body));
  return static_cast<int>(state_->bodies.size()) - 1;
}

int World::AddCollider(const Collider& collider) {
  Require(collider.pose.matrix().allFinite() && collider.linear_velocity.allFinite() &&
              collider.angular_velocity.allFinite(),
          "collider '" + collider.name + "': pose and twist must be finite");
  Require(collider.friction >= 0.0 && Finite(collider.friction),
          "collider '" + collider.name + "': friction must be finite and >= 0");
  Require(collider.restitution >= 0.0 && collider.restitution <= 1.0,
          "collider '" + collider.name + "': restitution must lie in [0, 1]");
  state_->colliders.push_back(collider);
  for (Body& body : state_->bodies) {
    body.pair_friction.push_back(-1.0);
    // Wrenches are colliders first, then groups.
    body.wrenches.insert(body.wrenches.begin() + state_->colliders.size() - 1, ContactWrench{});
  }
  return static_cast<int>(state_->colliders.size()) - 1;
}

int World::AddKinematicGroup(int body_index, const KinematicGroup& group) {
  Require(body_index >= 0 && body_index < num_bodies(), "no body " + std::to_string(body_index));
  Body& body = state_->bodies[body_index];
  Require(!group.nodes.empty(), "kinematic group '" + group.name + "' has no nodes");
  Group added{group, Eigen::Matrix3Xd(3, group.nodes.size()), Eigen::Isometry3d::Identity()};
  const Eigen::Isometry3d pose = group.pose ? group.pose(state_->time) : added.initial_pose;
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
  // Fixed and driven nodes are not integrated: they no longer limit the step (face anchors'
  // token masses would).
  body.UpdateStableStep(state_->options);
  return static_cast<int>(body.groups.size()) - 1;
}

int World::ApplyForce(int body_index, const Eigen::Vector3d& point, const Eigen::Vector3d& force,
                      double radius, double duration) {
  return ApplyWrench(body_index, point, force, Eigen::Vector3d::Zero(), radius, duration);
}

int World::ApplyWrench(int body_index, const Eigen::Vector3d& point, const Eigen::Vector3d& force,
                       const Eigen::Vector3d& torque, double radius, double duration) {
  Require(body_index >= 0 && body_index < num_bodies(), "no body " + std::to_string(body_index));
  Require(point.allFinite() && force.allFinite() && torque.allFinite(),
          "force, torque and point must be finite");
  Require(radius >= 0.0 && Finite(radius), "force radius must be finite and >= 0");
  Require(duration >= 0.0 && Finite(duration), "force duration must be finite and >= 0");
  const Body& body = state_->bodies[body_index];
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
    push.force_sum += node_force.norm();
  }
  return internal::AddPush(std::move(push), state_->options, &state_->bodies[body_index].pushes);
}

void World::ReplaceModel(int body_index, std::shared_ptr<const Model> model,
                         const BodyOptions& options) {
  Require(body_index >= 0 && body_index < num_bodies(), "no body " + std::to_string(body_index));
  Require(model != nullptr, "no model");
  Body& old = state_->bodies[body_index];
  ValidateBodyOptions(old.name, options);
  Require(model->num_nodes() == old.model->num_nodes(),
          "the new model has " + std::to_string(model->num_nodes()) + " nodes, the body " +
              std::to_string(old.model->num_nodes()));
  Body body(old.name, model, options, state_->options);
  body.state = old.state;
  body.groups = old.groups;
  body.constrained = old.constrained;
  body.pushes = old.pushes;
  body.pending = old.pending;
  body.pair_friction = old.pair_friction;
  body.wrenches = old.wrenches;
  if (!body.groups.empty()) body.UpdateStableStep(state_->options);
  state_->bodies[body_index] = std::move(body);
}

void World::SetPairFriction(int body, int collider, double friction) {
  Require(body >= 0 && body < num_bodies() && collider >= 0 && collider < num_colliders(),
          "no such body or collider");
  Require(friction >= 0.0 && Finite(friction), "friction must be finite and >= 0");
  state_->bodies[body].pair_friction[collider] = friction;
}

void World::SetThreads(int threads) {
  Require(threads >= 1, "threads must be >= 1");
  state_->options.threads = threads;
  for (Body& body : state_->bodies) body.evaluator.set_max_threads(threads);
}

void World::SetState(int body_index, const State& state) {
  Require(body_index >= 0 && body_index < num_bodies(), "no body " + std::to_string(body_index));
  Body& body = state_->bodies[body_index];
  Require(state.positions.cols() == body.model->num_nodes() &&
              state.velocities.cols() == body.model->num_nodes(),
          "state size does not match the model");
  Require(state.positions.allFinite() && state.velocities.allFinite(), "state must be finite");
  body.state = state;
  body.pending.clear();
  body.sliding_friction.resize(3, 0);  // a node put somewhere new has not been sliding
}

Energies World::ComputeEnergies(int body_index) const {
  const Body& body = state_->bodies.at(body_index);
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
      -(state_->options.gravity.transpose() * body.state.positions).dot(m.transpose());
  return energies;
}

void World::Reset() {
  for (Body& body : state_->bodies) {
    body.state = State::AtRest(*body.model);
    body.pending.clear();
    body.pushes.clear();
    body.implicit_dv.resize(3, 0);  // no warm start from before the reset
    body.sliding_friction.resize(3, 0);
    internal::PlaceGroups(&body, 0.0);
    std::fill(body.wrenches.begin(), body.wrenches.end(), ContactWrench{});
    body.contact_points.clear();
  }
  state_->time = 0.0;
  state_->substep_refinement = 1;  // the rest shape's stable step holds again
}

World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

StepReport World::Step(double dt) { return step_loop_->Step(dt); }
double World::time() const { return state_->time; }
int World::num_bodies() const { return static_cast<int>(state_->bodies.size()); }
int World::num_colliders() const { return static_cast<int>(state_->colliders.size()); }
const std::string& World::body_name(int body) const { return state_->bodies.at(body).name; }
const Model& World::model(int body) const { return *state_->bodies.at(body).model; }
const State& World::state(int body) const { return state_->bodies.at(body).state; }
Collider& World::collider(int index) { return state_->colliders.at(index); }
const Collider& World::collider(int index) const { return state_->colliders.at(index); }
const BorderNodes& World::border(int body) const { return state_->bodies.at(body).border; }
std::vector<NodeIndex> World::constrained_nodes(int body) const {
  return state_->bodies.at(body).ConstrainedNodes();
}
double World::stable_time_step() const { return state_->StableTimeStep(); }
int World::substep_refinement() const { return state_->substep_refinement; }
const std::vector<ContactWrench>& World::wrenches(int body) const {
  return state_->bodies.at(body).wrenches;
}
const std::vector<ContactPoint>& World::contact_points(int body) const {
  return state_->bodies.at(body).contact_points;
}

}  // namespace msm_sim::core
