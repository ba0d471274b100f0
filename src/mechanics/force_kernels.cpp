// The double run kernels of ForceEvaluator, and the entry points of the stiffness products in
// both precisions. Their loops along a run are the templates both precisions share
// (spring_run_loops.h), a spring's arithmetic is spring_arithmetic.h's. Compiled with
// -fno-math-errno (CMakeLists.txt): std::sqrt may then become one SIMD instruction instead of a
// call that sets errno, which lets the compiler vectorise the loops at all. Each run's forces go to
// one force array in two loops, one writing node a0 + i and one node a0 + offset + i, because a
// single loop's two stores would overlap within a SIMD register whenever offset < the vector width.

#include "mechanics/force_kernels.h"

#include <algorithm>

#include "mechanics/simd_clones.h"
#include "mechanics/spring_arithmetic.h"
#include "mechanics/spring_run_loops.h"

namespace msm_sim::core {

namespace {

using RunForces = internal::RunScratch<double>;

inline __attribute__((always_inline)) void ApplyToEnds(const SpringRun& run, const RunForces& c,
                                                       const MutableNodeArrays& forces) {
  internal::ApplyToEnds<double>(run, c, forces.x, forces.y, forces.z);
}

// The plain pass and the eMSM second pass (Dispersed: plus o_a g_a + o_b g_b, g per node):
// SpringForcesAlongRun in double, its force vectors applied to one force array run by run.
template <bool Damped, bool Dispersed>
inline __attribute__((always_inline)) void ForceRunsImpl(const ScheduledSprings& springs,
                                                         int run_begin, int run_end,
                                                         const NodeArrays& positions,
                                                         const RunDamping& damping, const double* g,
                                                         const MutableNodeArrays& forces,
                                                         double* __restrict total) {
  RunForces c;
  const NodeArrays none{nullptr, nullptr, nullptr};
  const NodeArrays& v = Damped ? *damping.velocities : none;
  for (int r = run_begin; r < run_end; ++r) {
    const SpringRun& run = springs.runs[r];
    const int a0 = run.a0, f = run.first;
    internal::SpringForcesAlongRun<double, Damped, Dispersed, internal::RunEnds::kScratch>(
        run.count, run.offset, positions.x + a0, positions.y + a0, positions.z + a0,
        Damped ? v.x + a0 : nullptr, Damped ? v.y + a0 : nullptr, Damped ? v.z + a0 : nullptr,
        damping.beta, Dispersed ? g + a0 : nullptr, springs.stiffness + f, springs.rest + f,
        Dispersed ? springs.outflow_a + f : nullptr, Dispersed ? springs.outflow_b + f : nullptr,
        c.x, c.y, c.z, nullptr, nullptr, nullptr, total + f);
    ApplyToEnds(run, c, forces);
  }
}

// ForceRunsImpl with or without dampers (`damping.velocities` null), each a loop of its own.
template <bool Dispersed>
inline __attribute__((always_inline)) void ForceRuns(const ScheduledSprings& springs, int run_begin,
                                                     int run_end, const NodeArrays& positions,
                                                     const RunDamping& damping, const double* g,
                                                     const MutableNodeArrays& forces,
                                                     double* total) {
  if (damping.velocities != nullptr) {
    ForceRunsImpl<true, Dispersed>(springs, run_begin, run_end, positions, damping, g, forces,
                                   total);
  } else {
    ForceRunsImpl<false, Dispersed>(springs, run_begin, run_end, positions, damping, g, forces,
                                    total);
  }
}

}  // namespace

MSM_SIM_SIMD_CLONES
void PlainRuns(const ScheduledSprings& springs, int run_begin, int run_end,
               const NodeArrays& positions, const RunDamping& damping,
               const MutableNodeArrays& forces, double* total_tensions) {
  ForceRuns<false>(springs, run_begin, run_end, positions, damping, nullptr, forces,
                   total_tensions);
}

MSM_SIM_SIMD_CLONES
void InflowRuns(const ScheduledSprings& springs, int run_begin, int run_end,
                const NodeArrays& positions, double* a_ends, double* b_ends) {
  for (int r = run_begin; r < run_end; ++r) {
    const SpringRun& run = springs.runs[r];
    const int a0 = run.a0, f = run.first;
    internal::StretchInflowAlongRun<double>(run.count, run.offset, positions.x + a0,
                                            positions.y + a0, positions.z + a0, springs.rest + f,
                                            springs.outflow_a + f, springs.outflow_b + f,
                                            a_ends + a0, b_ends + a0 + run.offset);
  }
}

MSM_SIM_SIMD_CLONES
void OutflowRuns(const ScheduledSprings& springs, int run_begin, int run_end,
                 const NodeArrays& positions, const RunDamping& damping,
                 const double* dispersion_per_weight, const MutableNodeArrays& forces,
                 double* total_tensions) {
  ForceRuns<true>(springs, run_begin, run_end, positions, damping, dispersion_per_weight, forces,
                  total_tensions);
}

MSM_SIM_SIMD_CLONES
void StiffnessRuns(const ScheduledSprings& springs, int run_begin, int run_end,
                   const ScheduledLinearization& linearization, const NodeArrays& dv,
                   const MutableNodeArrays& out_a, const MutableNodeArrays& out_b, double* change_a,
                   double* change_b) {
  const double* const from[3] = {dv.x, dv.y, dv.z};
  double* const to_a[3] = {out_a.x, out_a.y, out_a.z};
  double* const to_b[3] = {out_b.x, out_b.y, out_b.z};
  internal::StiffnessRunsOf<double>(springs.runs, run_begin, run_end, springs.stiffness,
                                    springs.inflow_a, springs.inflow_b, linearization.ux,
                                    linearization.uy, linearization.uz, linearization.geometric,
                                    from, to_a, to_b, change_a, change_b);
}

MSM_SIM_SIMD_CLONES
void DispersedStiffnessRuns(const ScheduledSprings& springs, int run_begin, int run_end,
                            const ScheduledLinearization& linearization, const double* dg,
                            const MutableNodeArrays& out_a, const MutableNodeArrays& out_b) {
  double* const to_a[3] = {out_a.x, out_a.y, out_a.z};
  double* const to_b[3] = {out_b.x, out_b.y, out_b.z};
  internal::DispersedStiffnessRunsOf<double>(springs.runs, run_begin, run_end, springs.outflow_a,
                                             springs.outflow_b, linearization.ux, linearization.uy,
                                             linearization.uz, dg, to_a, to_b);
}

MSM_SIM_SIMD_CLONES
void SingleStiffnessRuns(const SingleScheduledStiffness& springs, int run_begin, int run_end,
                         const float* dv, long n, float* out, float* accumulator_change) {
  const float* const from[3] = {dv, dv + n, dv + 2 * n};
  float* const to_a[3] = {out, out + n, out + 2 * n};
  float* const to_b[3] = {out + 3 * n, out + 4 * n, out + 5 * n};
  float* change_b = accumulator_change != nullptr ? accumulator_change + n : nullptr;
  internal::StiffnessRunsOf<float>(springs.runs, run_begin, run_end, springs.stiffness,
                                   springs.inflow_a, springs.inflow_b, springs.ux, springs.uy,
                                   springs.uz, springs.geometric, from, to_a, to_b,
                                   accumulator_change, change_b);
}

MSM_SIM_SIMD_CLONES
void SingleDispersedStiffnessRuns(const SingleScheduledStiffness& springs, int run_begin,
                                  int run_end, const float* dg, long n, float* out) {
  float* const to_a[3] = {out, out + n, out + 2 * n};
  float* const to_b[3] = {out + 3 * n, out + 4 * n, out + 5 * n};
  internal::DispersedStiffnessRunsOf<float>(springs.runs, run_begin, run_end, springs.outflow_a,
                                            springs.outflow_b, springs.ux, springs.uy, springs.uz,
                                            dg, to_a, to_b);
}

}  // namespace msm_sim::core
