#pragma once
// Private to msm_sim's World: the per-node stages of the substep (world.h's class comment) that
// both integrators share: the drifts (1, 7), the pending restitution (2), the pushes (3), the
// kinematic groups driven (4) and the fastest node noted for the sanity check.

#include <cstddef>
#include <vector>

#include <Eigen/Geometry>

#include "dynamics/world_body.h"

namespace msm_sim::core::internal {

/// 1. x += h/2 v for nodes [begin, end); their kinematic nodes go where `poses` (GroupPoses
/// at t0 + h/2) put them. `save`: first copies the nodes' positions and velocities into the
/// saved ones, for a rejected step (the explicit integrator's first drift of a step).
void DriftHalf(Body* body, double h, const std::vector<Eigen::Isometry3d>& poses, int begin,
               int end, bool save = false);
/// 2. v += the restitution left over from the last substep's contacts (then none pending).
void ApplyPendingRestitution(Body* body);
/// The same for the nodes [begin, end) from `rebounds` (body->pending, or a node share's
/// rebounds applied ahead by SubstepInOnePass), leaving the list as it is.
void ApplyPendingRestitution(Body* body, const std::vector<PendingResponse>& rebounds, int begin,
                             int end);
/// 3. Springs, dampers and pushes into body->forces (gravity comes with the kick).
void ComputeForces(Body* body);
/// 3. Adds the pushes on nodes [begin, end) to body->forces.
void AddPushes(Body* body, int begin, int end);
/// 4. Kinematic nodes take their frames' velocities over [t0, t0 + h]; the change is the
/// groups' reaction, recorded in body->impulses after the `num_colliders` colliders' sums.
void DriveKinematicGroups(Body* body, std::size_t num_colliders, double h, double t0);
/// 7. x += h/2 v, noting the fastest node (above max_speed, m/s); kinematic nodes at their
/// frames at t0 + h.
void DriftHalfNotingFastest(Body* body, double h, double t0, double max_speed);
/// 7 for node share `share` [begin, end): x += h/2 v, its fastest velocity component and
/// whether a value is not finite into fastest[share] and nonfinite[share]. `twice`: then
/// stage 1 of the next substep (x += h/2 v again, before its restitution), the same two
/// roundings per coordinate in one pass over the nodes, the extremes noted at the substep's end.
void DriftShare(Body* body, double h, bool twice, int share, int begin, int end,
                std::vector<double>* fastest, std::vector<double>* nonfinite);
/// 7, after every share's drift: notes the fastest node if a share flagged one faster than
/// max_speed (m/s), and places the kinematic nodes at their frames at t.
void NoteDriftExtremes(Body* body, const std::vector<double>& fastest,
                       const std::vector<double>& nonfinite, double t, double max_speed);
/// Notes the body's fastest node, or a node with a non-finite value, for the sanity check.
void NoteFastest(Body* body);

}  // namespace msm_sim::core::internal
