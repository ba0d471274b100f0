// Stages 5-6 of the substep between border nodes (of two bodies, or of a folded one):
// detect the touching pairs, stop every approach, leave the rebound pending, recover overlaps.
#include "dynamics/pair_contacts.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "dynamics/recovery_speed.h"
#include "geometry/spatial_hash_grid.h"

namespace msm_sim::core::internal {
namespace {

// As for the colliders (collider_contacts.cpp): the fraction of the pair's reach left overlapping,
// and the overlap beyond which the pair is being recovered and is frictionless.
constexpr double kPairRecoverySlop = 0.01;
constexpr double kPairFrictionlessOverlap = 0.1;
// The candidates' skin as a fraction of the largest collision radius: pairs within their reach
// plus the skin are tested each substep, found again once a border node has moved half the skin.
// Resting and slowly pressed contacts move far less than that in many steps.
constexpr double kCandidateSkin = 0.5;

// Where the pair contacts see a node: at its position moved by its body's entry offset
// (BodyEntries, docs/physics.md §7.2; zero unless the body is being pressed back in).
Eigen::Vector3d Seen(const Body& body, NodeIndex node) {
  return body.state.positions.col(node) + body.contact_offset;
}

// A deep pair whose nodes have passed each other (each centre behind the other's surface, on
// the inner side of its star) is turned to face the way out of both bodies, as a collider's
// surface normal does for a node inside it: its centre-to-centre normal would push the two
// layers further into each other. Its overlap is then counted along that normal.
void FaceTheWayOut(PairContact* pair) {
  const Eigen::Vector3d xi = Seen(*pair->body_i, pair->i);
  const Eigen::Vector3d xj = Seen(*pair->body_j, pair->j);
  const Eigen::Vector3d star_i = NodeStar(*pair->body_i, pair->i);
  const Eigen::Vector3d star_j = NodeStar(*pair->body_j, pair->j);
  if (!((xj - xi).dot(star_i) > 0.0 && (xi - xj).dot(star_j) > 0.0)) return;
  const Eigen::Vector3d out = star_i - star_j;  // i leaves j's body, j leaves i's
  const double norm = out.norm();
  if (!(norm > 0.0)) return;
  pair->normal = out / norm;
  pair->overlap = pair->reach - (xi - xj).dot(pair->normal);
}

}  // namespace

Eigen::Vector3d NodeStar(const Body& body, NodeIndex node) {
  const Model& model = *body.model;
  const Eigen::Matrix3Xd& x = body.state.positions;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::int32_t k = model.incidence_offsets()[node]; k < model.incidence_offsets()[node + 1];
       ++k) {
    const SpringIndex s = model.incident_springs()[k];
    const NodeIndex other =
        model.spring_node_a()[s] == node ? model.spring_node_b()[s] : model.spring_node_a()[s];
    const Eigen::Vector3d d = x.col(other) - x.col(node);
    const double length = d.norm();
    if (length > 0.0) sum += d / length;
  }
  return sum;
}

void PairContacts::CollideNodes(int* microcollisions) {
  // Contacts first, then Gauss-Seidel sweeps over all of them: a node resting on several nodes
  // below it must end approaching none of them (a single pass left some approach, and a block
  // stacked on another sank into it within a second).
  std::vector<PairContact> pairs = FindTouchingPairs();
  if (pairs.empty()) return;
  StopPairApproaches(&pairs);
  for (const PairContact& pair : pairs) {
    if (pair.stopped <= 0.0) continue;
    RespondToPairContact(pair);
    ++*microcollisions;
  }
  RecoverFromPairs(pairs);
}

bool PairContacts::MayHaveTouchingPairs() const {
  // Most scenes hold one body, or bodies apart: nothing is tested, hashed or kept when nothing
  // can touch (docs/design/speed-against-bullet.md).
  for (const Body& body : world_.bodies) {
    if (body.options.self_collision) return true;
  }
  if (world_.bodies.size() < 2) return false;
  std::vector<Eigen::AlignedBox3d> boxes;
  for (const Body& body : world_.bodies) {
    Eigen::AlignedBox3d box;
    double reach = 0.0;
    for (std::size_t k = 0; k < body.border.nodes.size(); ++k) {
      box.extend(Seen(body, body.border.nodes[k]));
      reach = std::max(reach, body.border.radii[k]);
    }
    if (box.isEmpty()) continue;
    box.min().array() -= reach;
    box.max().array() += reach;
    for (const Eigen::AlignedBox3d& other : boxes) {
      if (box.intersects(other)) return true;
    }
    boxes.push_back(box);
  }
  return false;
}

std::vector<PairContact> PairContacts::FindTouchingPairs() {
  // Each substep tests the candidates only, a few per border node near another body: finding
  // them hashes those nodes, which a substep costs far more than the contacts it resolves
  // (docs/design/soft-contact-cost.md). Resting contacts keep their candidates for many steps.
  if (!MayHaveTouchingPairs()) return {};
  if (!CandidatesHold()) FindCandidates();
  std::vector<PairContact> pairs;
  for (const Candidate& candidate : candidates_) {
    Body& body_i = world_.bodies[candidate.body_i];
    Body& body_j = world_.bodies[candidate.body_j];
    const std::size_t before = pairs.size();
    AddPairIfTouching(&body_i, candidate.i, &body_j, candidate.j,
                      Seen(body_i, candidate.i) - Seen(body_j, candidate.j), candidate.reach,
                      &pairs);
    if (pairs.size() > before &&
        pairs.back().overlap > kPairFrictionlessOverlap * candidate.reach) {
      FaceTheWayOut(&pairs.back());
    }
  }
  return pairs;
}

bool PairContacts::CandidatesHold() const {
  if (found_models_.size() != world_.bodies.size()) return false;
  // Two nodes that have each moved at most skin / 2 are at most skin closer: a pair that was
  // not a candidate is still out of reach.
  const double limit_sq = 0.25 * skin_ * skin_;
  for (std::size_t b = 0; b < world_.bodies.size(); ++b) {
    const Body& body = world_.bodies[b];
    const std::vector<NodeIndex>& nodes = body.border.nodes;
    if (body.model.get() != found_models_[b] ||
        static_cast<Eigen::Index>(nodes.size()) != found_at_[b].cols()) {
      return false;
    }
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      const Eigen::Index column = static_cast<Eigen::Index>(k);
      if ((Seen(body, nodes[k]) - found_at_[b].col(column)).squaredNorm() > limit_sq) {
        return false;
      }
    }
  }
  return true;
}

void PairContacts::FindCandidates() {
  candidates_.clear();
  found_at_.assign(world_.bodies.size(), Eigen::Matrix3Xd());
  found_models_.clear();
  double max_radius = 0.0;
  for (std::size_t b = 0; b < world_.bodies.size(); ++b) {
    const Body& body = world_.bodies[b];
    found_models_.push_back(body.model.get());
    found_at_[b].resize(3, static_cast<Eigen::Index>(body.border.nodes.size()));
    for (std::size_t k = 0; k < body.border.nodes.size(); ++k) {
      found_at_[b].col(static_cast<Eigen::Index>(k)) = Seen(body, body.border.nodes[k]);
      max_radius = std::max(max_radius, body.border.radii[k]);
    }
  }
  skin_ = kCandidateSkin * max_radius;
  const std::vector<BorderEntry> entries = NodesNearOtherBodies(2.0 * max_radius + skin_);
  if (entries.empty()) return;
  const double search = 2.0 * max_radius + skin_;
  SpatialHashGrid grid(search);
  for (std::size_t e = 0; e < entries.size(); ++e) {
    grid.Insert(static_cast<int>(e), Seen(world_.bodies[entries[e].body], entries[e].node));
  }
  std::vector<std::pair<int, int>> found;
  for (std::size_t e = 0; e < entries.size(); ++e) {
    const BorderEntry& first = entries[e];
    const Body& body_i = world_.bodies[first.body];
    const Eigen::Vector3d xi = Seen(body_i, first.node);
    grid.ForEachWithin(xi, search, [&](int other, const Eigen::Vector3d& xj) {
      if (other <= static_cast<int>(e)) return;  // each pair once
      const BorderEntry& second = entries[other];
      if (first.body == second.body && !MayTouchItself(body_i, first.node, second.node)) return;
      if ((xi - xj).norm() < first.radius + second.radius + skin_) found.emplace_back(e, other);
    });
  }
  // The order of the bodies and border nodes, whichever cells the hash put them in: the
  // Gauss-Seidel sweeps take the pairs in this order.
  std::sort(found.begin(), found.end());
  for (const auto& [first, second] : found) {
    candidates_.push_back({entries[first].body, entries[first].node, entries[second].body,
                           entries[second].node, entries[first].radius + entries[second].radius});
  }
}

std::vector<PairContacts::BorderEntry> PairContacts::NodesNearOtherBodies(double margin) const {
  std::vector<Eigen::AlignedBox3d> boxes(world_.bodies.size());
  for (std::size_t b = 0; b < world_.bodies.size(); ++b) {
    const Body& body = world_.bodies[b];
    for (const NodeIndex node : body.border.nodes) boxes[b].extend(Seen(body, node));
    if (!boxes[b].isEmpty()) {
      boxes[b].min().array() -= margin;
      boxes[b].max().array() += margin;
    }
  }
  std::vector<BorderEntry> entries;
  for (std::size_t b = 0; b < world_.bodies.size(); ++b) {
    const Body& body = world_.bodies[b];
    for (std::size_t k = 0; k < body.border.nodes.size(); ++k) {
      const Eigen::Vector3d x = Seen(body, body.border.nodes[k]);
      bool near = body.options.self_collision;
      for (std::size_t other = 0; other < boxes.size() && !near; ++other) {
        near = other != b && boxes[other].contains(x);
      }
      if (near)
        entries.push_back({static_cast<int>(b), body.border.nodes[k], body.border.radii[k]});
    }
  }
  return entries;
}

bool PairContacts::MayTouchItself(const Body& body, NodeIndex i, NodeIndex j) {
  // Self-contact is a fold bringing together parts of the body that were apart at rest. Nodes
  // near each other at rest (every spring-connected pair among them) only get close by
  // compressing the material between them, which the springs already resist; treating that as
  // contact made a squashed ball chatter and blow up.
  if (!body.options.self_collision) return false;
  const Eigen::Matrix3Xd& rest = body.model->rest_positions();
  return (rest.col(i) - rest.col(j)).squaredNorm() >= body.self_contact_rest_distance_sq;
}

void PairContacts::AddPairIfTouching(Body* body_i, NodeIndex i, Body* body_j, NodeIndex j,
                                     const Eigen::Vector3d& d, double reach,
                                     std::vector<PairContact>* pairs) {
  const double distance = d.norm();
  if (distance >= reach) return;
  Eigen::Vector3d normal;
  if (distance > 0.0) {
    normal = d / distance;
  } else {
    // Coincident centres have no line between them: the way out of both bodies, as for a pair
    // that passed (FaceTheWayOut); none if the stars cancel (BodyEntries resolves those).
    normal = NodeStar(*body_i, i) - NodeStar(*body_j, j);
    if (!(normal.norm() > 0.0)) return;
    normal.normalize();
  }
  // A constrained node acts as an infinite mass.
  const double inv_i = body_i->constrained[i] ? 0.0 : 1.0 / body_i->model->masses()[i];
  const double inv_j = body_j->constrained[j] ? 0.0 : 1.0 / body_j->model->masses()[j];
  if (inv_i + inv_j == 0.0) return;
  // A pair overlapping deeper than a resting one would is being recovered: frictionless, as
  // for the colliders (an overlap has no sliding history).
  const double overlap = reach - distance;
  const double friction = overlap > kPairFrictionlessOverlap * reach
                              ? 0.0
                              : std::sqrt(body_i->options.friction * body_j->options.friction);
  pairs->push_back({body_i, i, body_j, j, normal, inv_i, inv_j, 1.0 / (inv_i + inv_j),
                    std::min(body_i->options.restitution, body_j->options.restitution), friction,
                    overlap, reach});
}

void PairContacts::StopPairApproaches(std::vector<PairContact>* pairs) const {
  for (int sweep = 0; sweep < world_.options.contact_iterations; ++sweep) {
    bool approaching = false;
    for (PairContact& pair : *pairs) {
      auto vi = pair.body_i->state.velocities.col(pair.i);
      auto vj = pair.body_j->state.velocities.col(pair.j);
      // The entry's press moves the nodes where the contacts see them (BodyEntries).
      const double vn =
          (vi - vj + pair.body_i->contact_offset_velocity - pair.body_j->contact_offset_velocity)
              .dot(pair.normal);
      if (vn >= 0.0) continue;
      const double impulse = -vn * pair.reduced_mass;
      vi += impulse * pair.inverse_mass_i * pair.normal;
      vj -= impulse * pair.inverse_mass_j * pair.normal;
      pair.stopped += impulse;
      approaching = true;
    }
    if (!approaching) break;
  }
}

void PairContacts::RespondToPairContact(const PairContact& pair) {
  auto vi = pair.body_i->state.velocities.col(pair.i);
  auto vj = pair.body_j->state.velocities.col(pair.j);
  // Friction up to mu times the pair's normal impulse, never reversing the sliding.
  const Eigen::Vector3d relative =
      vi - vj + pair.body_i->contact_offset_velocity - pair.body_j->contact_offset_velocity;
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
}

// Penetration recovery between nodes (docs/physics.md §7.2): the collider's position-level
// correction, the pair's shift shared by inverse masses.
void PairContacts::RecoverFromPairs(const std::vector<PairContact>& pairs) {
  // Summed per node first, then capped at the recovery's speed: a node pushed into another
  // body's lattice overlaps several of its nodes, and their shifts add up (applied pair by pair
  // they carried nodes out at several times the speed, and steps were rejected).
  // Only the pairs' nodes are visited: the sums wait in shifts_, zero elsewhere, and each node's
  // is applied and cleared at its first pair in the second pass.
  shifts_.resize(world_.bodies.size());
  bool any = false;
  for (const PairContact& pair : pairs) {
    const double target =
        RecoverySpeed(world_.options, pair.overlap - kPairRecoverySlop * pair.reach);
    const auto vi = pair.body_i->state.velocities.col(pair.i);
    const auto vj = pair.body_j->state.velocities.col(pair.j);
    const double separating =
        (vi - vj + pair.body_i->contact_offset_velocity - pair.body_j->contact_offset_velocity)
            .dot(pair.normal);
    if (!(target > separating)) continue;
    const double per_inverse_mass =
        (target - separating) * world_.substep / (pair.inverse_mass_i + pair.inverse_mass_j);
    ShiftOf(pair.body_i).col(pair.i) += per_inverse_mass * pair.inverse_mass_i * pair.normal;
    ShiftOf(pair.body_j).col(pair.j) -= per_inverse_mass * pair.inverse_mass_j * pair.normal;
    any = true;
  }
  if (!any) return;
  const double cap = world_.options.penetration_max_speed * world_.substep;
  const auto apply = [cap](Body* body, NodeIndex node, Eigen::Matrix3Xd& shifts) {
    auto shift = shifts.col(node);
    if (shift.isZero(0.0)) return;  // none, or applied at an earlier pair
    const double length = shift.norm();
    if (length > cap) shift *= cap / length;
    body->state.positions.col(node) += shift;
    shift.setZero();
  };
  for (const PairContact& pair : pairs) {
    apply(pair.body_i, pair.i, ShiftOf(pair.body_i));
    apply(pair.body_j, pair.j, ShiftOf(pair.body_j));
  }
}

Eigen::Matrix3Xd& PairContacts::ShiftOf(const Body* body) {
  Eigen::Matrix3Xd& shift = shifts_[static_cast<std::size_t>(body - world_.bodies.data())];
  if (shift.cols() != body->state.positions.cols()) shift.setZero(3, body->state.positions.cols());
  return shift;
}

}  // namespace msm_sim::core::internal
