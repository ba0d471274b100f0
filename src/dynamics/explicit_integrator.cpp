// The explicit integrator's stages 1-4 on the node shares, and the one-pass substep
// (explicit_integrator.h). Compiled without contraction into FMAs (CMakeLists.txt): the AVX2
// clones then compute exactly what the baseline build does.
#include "dynamics/explicit_integrator.h"

#include <functional>
#include <vector>

#include "dynamics/node_stages.h"
#include "mechanics/node_shares.h"
#include "mechanics/simd_clones.h"

namespace msm_sim::core::internal {
namespace {

// The kick's per-node loops, with AVX2 clones as the spring loops.

// v += h f / m + h g for n nodes (3-vectors, column-major).
MSM_SIM_SIMD_CLONES
void KickNodes(int n, double h, const double* forces, const double* inverse_masses,
               const double g[3], double* velocities) {
  const double* __restrict f = forces;
  const double* __restrict inverse_mass = inverse_masses;
  double* __restrict v = velocities;
  const double hg[3] = {h * g[0], h * g[1], h * g[2]};
  for (int i = 0; i < n; ++i) {
    const double scale = h * inverse_mass[i];
    for (int d = 0; d < 3; ++d) v[3 * i + d] += scale * f[3 * i + d] + hg[d];
  }
}

// KickNodes for nodes [begin, end) with the forces as the single-precision loops leave them
// (internal::NodeStages::after_unstored: x, y, z blocks of the a ends, then of the b ends,
// `stride` floats apart): node i's force is the double sum of its a- and
// b-end floats, which StoreSingleEndForces would have stored for KickNodes to read back. The
// same arithmetic, without that round trip through memory.
MSM_SIM_SIMD_CLONES
void KickNodesFromEndForces(long stride, long begin, long end, double h, const float* end_forces,
                            const double* inverse_masses, const double g[3], double* velocities) {
  const float* __restrict a = end_forces;
  const float* __restrict b = end_forces + 3 * stride;
  const double* __restrict inverse_mass = inverse_masses;
  double* __restrict v = velocities;
  const double hg[3] = {h * g[0], h * g[1], h * g[2]};
  for (long i = begin; i < end; ++i) {
    const double scale = h * inverse_mass[i];
    for (long d = 0; d < 3; ++d) {
      const double f =
          static_cast<double>(a[d * stride + i]) + static_cast<double>(b[d * stride + i]);
      v[3 * i + d] += scale * f + hg[d];
    }
  }
}

}  // namespace

bool ExplicitIntegrator::SubstepsInOnePass() const {
  if (world_.options.integrator != Integrator::kExplicit || world_.bodies.size() != 1) return false;
  const Body& body = world_.bodies.front();
  return body.groups.empty() && !body.options.self_collision;
}

void ExplicitIntegrator::SubstepInOnePass(Body* body, double h, double t0) {
  const bool contacts = !world_.colliders.empty();
  ContactStage stage;
  if (contacts) stage = contacts_.BeginContactStage(body);
  std::vector<double> fastest(internal::NodeShares::Count(body->evaluator)),
      nonfinite(fastest.size());
  // The first share's rebounds wait in next_pending while the shares still apply `pending`.
  body->next_pending.clear();
  // Within a Step, the next substep's stages 1-2 come with this one's last drift, and its float
  // loops' rounding with them (one pass over the nodes and one hand-over fewer). Nothing between
  // the two substeps moves a node: the sanity check reads the drift's flags (a flagged substep's
  // NoteFastest sees the rebounds applied), and a rejected step restores its start.
  const bool drifted = world_.drifted_ahead, rounded = world_.rounded_ahead;
  world_.drifted_ahead = world_.substep_index + 1 < world_.substep_count;
  world_.rounded_ahead = world_.drifted_ahead && internal::NodeShares::Rounds(body->evaluator);
  const Eigen::Matrix3Xd* dampers =
      body->options.damping_beta != 0.0 ? &body->state.velocities : nullptr;
  const std::function<void(int, int, int)> finish = [&](int share, int begin, int end) {
    if (contacts)
      contacts_.CollideShare(&stage, body, share, begin, end, &body->next_pending);      // 5-6
    DriftShare(body, h, world_.drifted_ahead, share, begin, end, &fastest, &nonfinite);  // 7 (, 1)
    if (!world_.drifted_ahead) return;
    if (contacts) {  // the next 2: the rebounds this share's contacts left, on its own nodes
      ApplyPendingRestitution(
          body, share == 0 ? body->next_pending : body->share_records[share - 1].pending, begin,
          end);
    }
    if (world_.rounded_ahead) {
      internal::NodeShares::Round(&body->evaluator, body->state.positions, dampers, begin, end,
                                  body->float_origin.data());
    }
  };
  DriftForceAndKick(body, h, t0, &finish, drifted, rounded, world_.rounded_ahead);  // 1-4, `finish`
  body->pending.swap(body->next_pending);  // `pending` was cleared
  if (contacts) ColliderContacts::EndContactStage(stage, body, &world_.microcollisions);
  if (world_.drifted_ahead) body->pending.clear();  // applied
  NoteDriftExtremes(body, fastest, nonfinite, t0 + h, world_.options.max_speed);
}

void ExplicitIntegrator::Kick(Body* body, double h, int begin, int end) const {
  // Gravity comes in the same pass over the nodes: this loop and the drifts are a third of a
  // 12k-node step besides the force evaluation.
  KickNodes(end - begin, h, body->forces.data() + 3L * begin, body->inverse_masses.data() + begin,
            world_.options.gravity.data(), body->state.velocities.data() + 3L * begin);
}

void ExplicitIntegrator::DriftForceAndKick(Body* body, double h, double t0,
                                           const std::function<void(int, int, int)>* finish,
                                           bool drifted, bool rounded, bool rounds_ahead) {
  // Each node share of the force loops drifts, kicks and places its own nodes on its own thread
  // (internal::NodeStages): they stay in that core's cache, and with two threads the
  // per-node stages no longer wait on one core (docs/physics.md §9).
  // The frames' poses here, on the caller's thread: a pose function need not be thread-safe.
  const std::vector<Eigen::Isometry3d> poses = GroupPoses(*body, t0 + 0.5 * h);
  internal::NodeStages stages;
  stages.origin = body->float_origin.data();
  stages.rounded = rounded && internal::NodeShares::Rounds(body->evaluator);
  stages.rounds_ahead = rounds_ahead;
  const bool save = world_.substep_index == 0;  // SaveForRollback's copy of the nodes
  stages.before = [body, h, &poses, save, drifted](int, int begin, int end) {
    if (drifted) return;                                       // 1-2 taken ahead
    DriftHalf(body, h, poses, begin, end, save);               // 1
    ApplyPendingRestitution(body, body->pending, begin, end);  // 2
  };
  stages.after = [this, body, h, finish](int share, int begin, int end) {
    AddPushes(body, begin, end);  // 3, with the springs' and dampers' forces
    Kick(body, h, begin, end);    // 4
    if (finish != nullptr) (*finish)(share, begin, end);
  };
  if (body->pushes.empty()) {
    // Without pushes the kick takes the springs' forces as the float loops leave them (body->
    // forces is not written): the same sums, one pass over the nodes instead of two.
    stages.after_unstored = [this, body, h, finish](int share, int begin, int end,
                                                    const float* end_forces, long stride) {
      KickNodesFromEndForces(stride, begin, end, h, end_forces, body->inverse_masses.data(),
                             world_.options.gravity.data(), body->state.velocities.data());  // 3-4
      if (finish != nullptr) (*finish)(share, begin, end);
    };
  }
  internal::NodeShares::SetForces(&body->evaluator, body->state.positions, body->state.velocities,
                                  body->options.damping_beta, &body->forces, stages);
  body->pending.clear();
}

}  // namespace msm_sim::core::internal
