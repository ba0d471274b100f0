#pragma once
// Private to msm_sim's World: one body and its state (model, nodes, kinematic groups, pushes,
// what a Step records and saves), and the records its contact stages write into.

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "msm_sim/dynamics/border_nodes.h"
#include "msm_sim/dynamics/contact_point.h"
#include "msm_sim/dynamics/contact_wrench.h"
#include "msm_sim/dynamics/kinematic_group.h"
#include "msm_sim/dynamics/world_options.h"
#include "msm_sim/mechanics/force_evaluator.h"
#include "msm_sim/model/model.h"
#include "msm_sim/model/state.h"

namespace msm_sim::core::internal {

/// A force applied with World::ApplyForce or ApplyWrench, shared by the nodes it reaches.
struct Push {
  std::vector<NodeIndex> nodes;
  std::vector<Eigen::Vector3d> forces;  // per node
  double remaining;                     // s; <= 0 after its one step
  double force_sum = 0.0;               // N, the sum of |forces|
};

/// Appends `push` to a body's pending `pushes`, first dropping the oldest until the count and
/// the force sum stay within options' max_pending_pushes and max_pending_force (a lone push
/// above the force bound stays); returns how many were dropped.
int AddPush(Push push, const WorldOptions& options, std::vector<Push>* pushes);

/// A kinematic group as the World keeps it.
struct Group {
  KinematicGroup spec;
  Eigen::Matrix3Xd local;          // node offsets in the group frame
  Eigen::Isometry3d initial_pose;  // for a fixed group
};

/// The restitution part of a contact response, due at step 2 of the next substep.
struct PendingResponse {
  NodeIndex node;
  Eigen::Vector3d delta_v;
};

/// Impulses a body gave one collider or group during a Step, turned into a wrench at its end.
struct ImpulseSum {
  Eigen::Vector3d impulse = Eigen::Vector3d::Zero();  // on the collider, N s
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();   // about its frame origin, N m s
  Eigen::Vector3d weighted_point = Eigen::Vector3d::Zero();
  double weight = 0.0;
  int count = 0;
  Eigen::Vector3d normal_impulses = Eigen::Vector3d::Zero();  // sum of j_n n (colliders)
  double normal_impulse = 0.0;                                // sum of j_n, N s
  double area_time = 0.0;  // m^2 s, touching nodes' surface shares times their substeps
  /// Adds one impulse on the collider at `point`, its moment about `origin`. Inline: the
  /// contact stage calls it once per microcollision, on the thread whose share holds the
  /// ground contacts (docs/design/speed-against-bullet.md).
  void Add(const Eigen::Vector3d& point, const Eigen::Vector3d& origin,
           const Eigen::Vector3d& on_collider) {
    // Tested on the square: the branch then need not wait for the square root.
    const double magnitude_sq = on_collider.squaredNorm();
    if (magnitude_sq == 0.0) return;
    const double magnitude = std::sqrt(magnitude_sq);
    impulse += on_collider;
    moment += (point - origin).cross(on_collider);
    weighted_point += magnitude * point;
    weight += magnitude;
    ++count;
  }
  /// Adds another sum's parts (a node share's, ColliderContacts::EndContactStage).
  void Merge(const ImpulseSum& other);
};

/// Where the contact stage records what it does, for the colliders' wrenches, the next substep
/// and the contact points: a body's own records, or a node share's.
struct ContactRecords {
  std::vector<ImpulseSum>* impulses;      // colliders, then groups
  std::vector<PendingResponse>* pending;  // rebounds for the next substep
  std::vector<ContactPoint>* points;      // if recorded
  int microcollisions = 0;
};

/// A node share's records beyond the first share, added to the body's in share order.
struct ShareRecords {
  std::vector<ImpulseSum> impulses;
  std::vector<PendingResponse> pending;
  std::vector<ContactPoint> points;
};

/// One MSM body: its immutable Model, its State and everything the World's stages keep for it.
struct Body {
  /// At rest, with everything derived from the model: border, stable step (for the World's
  /// safety factor), the self-contact distance; the evaluator gets the World's thread count.
  Body(const std::string& body_name, std::shared_ptr<const Model> body_model,
       const BodyOptions& body_options, const WorldOptions& world_options);
  /// stable_step for the model without the constrained nodes (StableTimeStepOptions::
  /// fixed_nodes): called again whenever the constrained nodes change.
  void UpdateStableStep(const WorldOptions& world_options);
  std::vector<NodeIndex> ConstrainedNodes() const;
  /// The body's own contact records.
  ContactRecords Records() { return {&impulses, &pending, &contact_points}; }

  std::string name;
  std::shared_ptr<const Model> model;
  BodyOptions options;
  State state;
  ForceEvaluator evaluator;
  BorderNodes border;
  std::vector<Group> groups;
  std::vector<char> constrained;  // per node
  std::vector<Push> pushes;
  std::vector<PendingResponse> pending;
  // The rebounds the first node share's contacts leave while `pending` is still being applied
  // (ExplicitIntegrator::SubstepInOnePass), moved into it once it has been.
  std::vector<PendingResponse> next_pending;
  // Node 0's position at the start of the current Step: the explicit force loops of all its
  // substeps round positions relative to it (NodeStages::origin), so that a substep can
  // round the next one's nodes ahead (SubstepInOnePass).
  Eigen::Vector3d float_origin = Eigen::Vector3d::Zero();
  std::vector<double> pair_friction;           // per collider; < 0: default
  double stable_step = 0.0;                    // without the constrained nodes (UpdateStableStep)
  double self_contact_rest_distance_sq = 0.0;  // m^2
  Eigen::VectorXd inverse_masses;
  // During the current Step, noted only when a node breaks max_speed or a value is not
  // finite (then infinite): the fastest node's speed squared, and which node.
  double fastest_speed_sq = 0.0;
  int fastest_node = 0;
  Eigen::Matrix3Xd saved_positions, saved_velocities;  // to restore a rejected Step
  std::vector<PendingResponse> saved_pending;
  Eigen::Matrix3Xd forces;
  Eigen::Matrix3Xd implicit_dv, saved_implicit_dv;  // last implicit kick: the next one's start
  // Per node, the Coulomb impulse of the last implicit kick's sliding contact (0: stuck, or no
  // contact): the next kick starts that contact sliding with it (docs/physics.md §7.1).
  Eigen::Matrix3Xd sliding_friction, saved_sliding_friction;
  std::vector<ImpulseSum> impulses;          // colliders, then groups (during a Step)
  std::vector<ContactWrench> wrenches;       // colliders, then groups (of the last Step)
  std::vector<ContactPoint> contact_points;  // of the last Step, if recorded
  std::vector<char> near_collider;           // per border node, this substep: within reach of one
  // While BodyEntries presses the body back into one it was found inside (docs/physics.md
  // §7.2): its pair contacts see its nodes moved by contact_offset (m), which moves at
  // contact_offset_velocity (m/s); both zero otherwise and outside a Step's substeps.
  Eigen::Vector3d contact_offset = Eigen::Vector3d::Zero();
  Eigen::Vector3d contact_offset_velocity = Eigen::Vector3d::Zero();
  std::vector<ShareRecords> share_records;  // the contact stage's shares after the first
};

/// The group's frame at time t (s): its pose function's, or the pose it was added with.
Eigen::Isometry3d GroupPose(const Group& group, double t);
/// The body's groups' frames at time t (s), in group order.
std::vector<Eigen::Isometry3d> GroupPoses(const Body& body, double t);
/// Puts the body's kinematic nodes in [begin, end) where `poses` (GroupPoses) put them; calls
/// no pose function, so node shares may run it on their threads.
void PlaceGroupNodes(Body* body, const std::vector<Eigen::Isometry3d>& poses, int begin, int end);
/// Puts a body's kinematic nodes where their frames are at time t.
void PlaceGroups(Body* body, double t);

}  // namespace msm_sim::core::internal
