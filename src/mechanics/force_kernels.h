#pragma once

#include <vector>

#include "mechanics/single_precision_kernels.h"
#include "mechanics/spring_schedule.h"

namespace msm_sim::core {

/// Node vectors as structure of arrays (x, y, z components each contiguous), the layout the run
/// kernels load and store with whole SIMD registers.
struct NodeArrays {
  const double* x;
  const double* y;
  const double* z;
};
struct MutableNodeArrays {
  double* x;
  double* y;
  double* z;
};

/// Per-spring data in schedule order (SpringSchedule), linear springs t = k (L - L0).
struct ScheduledSprings {
  const SpringRun* runs;
  const double* rest;
  const double* stiffness;
  const double* inflow_a;  // q v L0 at the scheduled a end (eMSM)
  const double* inflow_b;
  const double* outflow_a;  // v k L0 at the scheduled a end (eMSM)
  const double* outflow_b;
};

/// Spring dampers: velocities (nullptr for none) and beta (s); tension beta k dL/dt.
struct RunDamping {
  const NodeArrays* velocities;
  double beta;
};

// The kernels take runs [run_begin, run_end) and write the per-spring results at schedule
// positions. They are compiled for AVX2 + FMA where the CPU has it (chosen at load time) and
// for baseline x86-64 otherwise; results for a given CPU and thread count are deterministic.
// Preconditions: no spring has zero length; the arrays hold every node the runs touch.

/// Plain MSM: adds each spring's force (tension plus damper) to both ends and stores the total
/// tension.
void PlainRuns(const ScheduledSprings& springs, int run_begin, int run_end,
               const NodeArrays& positions, const RunDamping& damping,
               const MutableNodeArrays& forces, double* total_tensions);

/// eMSM first pass: adds each spring's end outflow v k L0 times its stretch L - L0 to the a
/// ends' sums `a_ends` and the b ends' `b_ends` (node arrays); q (a_ends + b_ends) is then J per
/// node (docs/physics.md §3). Dampers do not disperse, so it takes no velocities.
void InflowRuns(const ScheduledSprings& springs, int run_begin, int run_end,
                const NodeArrays& positions, double* a_ends, double* b_ends);

/// eMSM second pass: total tension = k (L - L0) + outflow_a g_a + outflow_b g_b plus the
/// damper's, with g = J / W per node, applied to both ends and stored.
void OutflowRuns(const ScheduledSprings& springs, int run_begin, int run_end,
                 const NodeArrays& positions, const RunDamping& damping,
                 const double* dispersion_per_weight, const MutableNodeArrays& forces,
                 double* total_tensions);

/// A linearisation in schedule order (ForceEvaluator::Linearize): each spring's unit vector u
/// (a -> b) and geometric coefficient T / L. A linear spring's tangent stiffness is its k.
struct ScheduledLinearization {
  const double* ux;
  const double* uy;
  const double* uz;
  const double* geometric;

  /// The view of `storage`, which holds blocks ux, uy, uz, geometric of num_springs each.
  static ScheduledLinearization Of(const double* storage, int num_springs) {
    return {storage, storage + num_springs, storage + 2 * num_springs, storage + 3 * num_springs};
  }
};

/// Stiffness product, direct part: the change of the springs' own tensions (k u.d(dv) along u
/// plus the geometric term), each spring's part added at its a end to `out_a` and at its b end
/// to `out_b` (K_direct dv is their sum), and, when `change_a` is not null, the eMSM
/// accumulators' change inflow * k u.d(dv) at the a ends to `change_a` and at the b ends to
/// `change_b`.
void StiffnessRuns(const ScheduledSprings& springs, int run_begin, int run_end,
                   const ScheduledLinearization& linearization, const NodeArrays& dv,
                   const MutableNodeArrays& out_a, const MutableNodeArrays& out_b, double* change_a,
                   double* change_b);

/// Stiffness product, dispersed part: the change of the dispersed tensions
/// outflow_a dg_a + outflow_b dg_b along u, with dg = (accumulator change) / W per node, its
/// ends added to `out_a` and `out_b` as in StiffnessRuns.
void DispersedStiffnessRuns(const ScheduledSprings& springs, int run_begin, int run_end,
                            const ScheduledLinearization& linearization, const double* dg,
                            const MutableNodeArrays& out_a, const MutableNodeArrays& out_b);

/// The stiffness product's per-slot data in single precision, along the float schedule's runs
/// (SinglePrecisionSprings, phantoms zero): the springs' k and eMSM coefficients, and a
/// linearisation's u and T / L, all rounded from the double ones (ForceEvaluator with
/// SpringPrecision::kSingle).
struct SingleScheduledStiffness {
  const SingleRun* runs;
  const float* stiffness;
  const float* inflow_a;
  const float* inflow_b;
  const float* outflow_a;
  const float* outflow_b;
  const float* ux;
  const float* uy;
  const float* uz;
  const float* geometric;
};

/// StiffnessRuns in single precision: dv as float x, y, z blocks of n; `out` the a ends' x, y, z
/// blocks then the b ends'; `accumulator_change` (null: no dispersion) the a ends' then the b
/// ends'.
void SingleStiffnessRuns(const SingleScheduledStiffness& springs, int run_begin, int run_end,
                         const float* dv, long n, float* out, float* accumulator_change);
/// DispersedStiffnessRuns in single precision, `out` as in SingleStiffnessRuns.
void SingleDispersedStiffnessRuns(const SingleScheduledStiffness& springs, int run_begin,
                                  int run_end, const float* dg, long n, float* out);

/// Copies n column-major 3-vectors into x, y, z blocks of n (the run kernels' layout).
inline void ToNodeArrays(const double* vectors, long n, double* arrays) {
  const double* __restrict from = vectors;
  double* __restrict to = arrays;
  for (long i = 0; i < n; ++i) {
    to[i] = from[3 * i];
    to[n + i] = from[3 * i + 1];
    to[2 * n + i] = from[3 * i + 2];
  }
}

/// Adds x, y, z blocks of n to n column-major 3-vectors.
inline void AddNodeArrays(const double* arrays, long n, double* vectors) {
  const double* __restrict from = arrays;
  double* __restrict to = vectors;
  for (long i = 0; i < n; ++i) {
    to[3 * i] += from[i];
    to[3 * i + 1] += from[n + i];
    to[3 * i + 2] += from[2 * n + i];
  }
}

}  // namespace msm_sim::core

namespace msm_sim::core {

/// The schedule-order copy of a model's springs that the run kernels read; immutable, so that
/// copies of an evaluator share it.
struct ScheduledSpringData {
  SpringSchedule schedule;
  std::vector<double> rest, stiffness, inflow_a, inflow_b, outflow_a, outflow_b;

  ScheduledSprings View() const {
    return {schedule.runs.data(), rest.data(),      stiffness.data(), inflow_a.data(),
            inflow_b.data(),      outflow_a.data(), outflow_b.data()};
  }
};

}  // namespace msm_sim::core
