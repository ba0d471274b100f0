#pragma once

// The run kernels of ForceEvaluator's linearisation (Linearize) and of its stiffness diagonal
// (StiffnessDiagonal) for the models the force run kernels take: linear springs in the spring
// schedule, so each spring's tangent stiffness is its k (docs/physics.md §2-3).

#include "mechanics/force_kernels.h"

namespace msm_sim::core {

// The kernels take runs [run_begin, run_end) as the force kernels do (force_kernels.h), and are
// compiled the same way (SIMD clones, no errno), so that a length, 1 / L and a tension round as
// they do in PlainRuns, InflowRuns and OutflowRuns.

/// Plain MSM: each spring's total tension k (L - L0) into total_tensions and its linearisation
/// (u and T / L, ScheduledLinearization::Of's layout) into `storage`, the tensions as PlainRuns
/// gives them, without the forces. `drop_compression` leaves out compressed
/// springs' geometric term (GeometricStiffness::kDropCompression).
void LinearizePlainRuns(const ScheduledSprings& springs, int run_begin, int run_end,
                        int num_springs, const NodeArrays& positions, bool drop_compression,
                        double* total_tensions, double* storage);

/// eMSM, with g = J / W per node (after InflowRuns): the total tensions
/// k (L - L0) + outflow_a g_a + outflow_b g_b into total_tensions and the linearisation into
/// `storage`, the tensions as OutflowRuns without dampers gives them, without the forces.
void LinearizeDispersedRuns(const ScheduledSprings& springs, int run_begin, int run_end,
                            int num_springs, const NodeArrays& positions,
                            const double* dispersion_per_weight, bool drop_compression,
                            double* total_tensions, double* storage);

/// The stiffness diagonal's per-spring sums at the linearisation: adds each spring's k u^2 +
/// (T / L)(1 - u^2) to both ends' `diagonal`. With `inverse_star_weight` (1 / W per node; null
/// without dispersion) it also adds the dispersion through the other end's J,
/// k outflow_b inflow_b / W_b u^2 at a (and a's at b), and sums s1 = sum outflow u and
/// s2 = sum inflow k u over the springs at each node, u pointing away from it: the caller adds
/// (1 / W) s1 s2 per node.
void StiffnessDiagonalRuns(const ScheduledSprings& springs, int run_begin, int run_end,
                           const ScheduledLinearization& linearization,
                           const double* inverse_star_weight, const MutableNodeArrays& diagonal,
                           const MutableNodeArrays& s1, const MutableNodeArrays& s2);

}  // namespace msm_sim::core
