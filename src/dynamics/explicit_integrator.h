#pragma once
// Private to msm_sim's World: the explicit integrator's substep stages 1-4 (docs/physics.md §7's
// position Verlet), run on the node shares of a body's force loops, and the substep that also
// runs the contact stage and the last drift there (SubstepInOnePass).

#include <functional>
#include <vector>

#include <Eigen/Geometry>

#include "dynamics/collider_contacts.h"
#include "dynamics/world_state.h"

namespace msm_sim::core::internal {

/// Explicit kicks and drifts of a WorldState's bodies.
class ExplicitIntegrator {
 public:
  /// The fewest substeps in a Step for ColliderContacts::CutNodeSharesAtContacts to cut at the
  /// contacts.
  static constexpr int kSubstepsToCutAtContacts = 4;

  ExplicitIntegrator(WorldState* world, ColliderContacts* contacts)
      : world_(*world), contacts_(*contacts) {}

  /// 1-4: each node share of the body's force loops drifts, places its kinematic nodes and
  /// applies its pending restitution, then, once its forces are set, adds its pushes and kicks,
  /// all on the share's thread (internal::NodeStages). `finish(share, begin, end)`, if
  /// given, runs on each share right after its kick. `drifted`: stages 1-2 were already taken
  /// (drifted_ahead; only without kinematic groups, whose nodes it would not place), and the
  /// nodes rounded for the float loops if `rounded`. `rounds_ahead`: `finish` rounds every node
  /// for the next substep (internal::NodeStages::rounds_ahead).
  void DriftForceAndKick(Body* body, double h, double t0,
                         const std::function<void(int, int, int)>* finish = nullptr,
                         bool drifted = false, bool rounded = false, bool rounds_ahead = false);
  /// Whether a substep may run stages 5-7 inside the force loops' node shares
  /// (SubstepInOnePass): one body in an explicit world, without kinematic groups or
  /// self-collision, so that nothing between its kick and its last drift needs the whole body
  /// (driving a group's nodes, contacts between nodes).
  bool SubstepsInOnePass() const;
  /// The substep for that body: the colliders at mid-substep first (stages 1-4 do not read
  /// them), then each node share drifts, kicks, collides its border nodes and drifts again on
  /// its own thread: two hand-overs between threads fewer per substep than stage by stage.
  /// Within a Step, a share's last drift also takes the next substep's first (DriftShare),
  /// applies the rebounds its contacts left and rounds its nodes for the next float loops: one
  /// pass over the nodes and one more hand-over fewer. The same arithmetic in the same order per
  /// node, and the same records in the same order, as the substep stage by stage.
  /// Precondition: the colliders at their mid-substep poses.
  void SubstepInOnePass(Body* body, double h, double t0);

 private:
  /// 4. v += h (F / m + g) for nodes [begin, end). Precondition: their forces of this substep.
  void Kick(Body* body, double h, int begin, int end) const;

  WorldState& world_;
  ColliderContacts& contacts_;
};

}  // namespace msm_sim::core::internal
