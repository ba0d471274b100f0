// The single-precision passes along the runs, the entry points that choose runs or blocks
// (single_block_loops.h), and the layout conversions. The loops along a run are the ones the
// double run kernels instantiate too (SpringForcesAlongRun, StretchInflowAlongRun;
// spring_run_loops.h). Compiled with -fno-math-errno (CMakeLists.txt), as
// force_kernels.cpp: std::sqrt then becomes one SIMD instruction, which lets the loops
// vectorise. The schedule is built in single_precision_schedule.cpp.

#include "mechanics/single_precision_kernels.h"

#include <algorithm>
#include <cmath>

#include "mechanics/simd_clones.h"
#include "mechanics/single_block_loops.h"
#include "mechanics/spring_arithmetic.h"
#include "mechanics/spring_run_loops.h"

// The block loops' 8-float lanes pass only through inlined helpers (single_block_loops.h,
// spring_arithmetic.h), so GCC's note on their ABI applies nowhere in this file; it is emitted
// where the helpers' templates are instantiated, at the end of the file.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace msm_sim::core {

namespace {

// A node array from a run's a0, or null for none (no dampers, no dispersion).
inline const float* From(const float* array, int a0) {
  return array != nullptr ? array + a0 : nullptr;
}

// Calls part(a, count, beyond) for the slots of `run` in `share`: first those whose b ends lie
// below share.limit (beyond false), then those whose b ends lie at share.limit or past it (true).
template <typename Part>
inline __attribute__((always_inline)) void ForRunInShare(const SingleRun& run,
                                                         const SingleShare& share, Part&& part) {
  const int lo = std::max(run.a0, share.begin);
  const int hi = std::min(run.a0 + run.count, share.end);
  if (lo >= hi) return;
  const int split = std::clamp(share.limit - run.offset, lo, hi);
  if (split > lo) part(lo, split - lo, false);
  if (hi > split) part(split, hi - split, true);
}

// Where a part's b ends go: the shared arrays from node b, or the share's overflow from b - end.
inline float* BEnd(float* shared, float* overflow, int b, int end, bool beyond) {
  return beyond ? overflow + (b - end) : shared + b;
}

// The forces of the slots in `share` along the runs; Dispersed: by `g` per node (the eMSM second
// pass). The second pass recomputes L and 1 / L rather than reading them from the first: two
// stored arrays cost more than the square root and the division (docs/physics.md §9).
template <bool Damped, bool Dispersed>
inline __attribute__((always_inline)) void ForcesImpl(
    const SinglePrecisionSprings& springs, const SingleShare& share,
    const SingleNodeArrays& positions, const SingleNodeArrays* velocities, float beta,
    const float* g, const SingleEndForces& forces, const MutableSingleNodeArrays& overflow) {
  const SingleNodeArrays v = velocities != nullptr ? *velocities : SingleNodeArrays{};
  for (const SingleRun& run : springs.runs) {
    ForRunInShare(run, share, [&](int a, int count, bool beyond) {
      const int b = a + run.offset, f = run.first + (a - run.a0), end = share.limit;
      internal::SpringForcesAlongRun<float, Damped, Dispersed, internal::RunEnds::kBothEnds>(
          count, run.offset, positions.x + a, positions.y + a, positions.z + a, From(v.x, a),
          From(v.y, a), From(v.z, a), beta, From(g, a), springs.stiffness.data() + f,
          springs.rest.data() + f, springs.outflow_a.data() + f, springs.outflow_b.data() + f,
          forces.a.x + a, forces.a.y + a, forces.a.z + a,
          BEnd(forces.b.x, overflow.x, b, end, beyond),
          BEnd(forces.b.y, overflow.y, b, end, beyond),
          BEnd(forces.b.z, overflow.z, b, end, beyond), nullptr);
    });
  }
}

}  // namespace

bool SingleLoopsByBlocks(const SinglePrecisionSprings& springs, const SingleShare& share) {
  constexpr int kLanes = internal::kLanes;
  return !springs.blocks.offsets.empty() && share.begin % kLanes == 0 &&
         (share.end % kLanes == 0 || share.end >= springs.num_nodes);
}

namespace {

// The force loops of SinglePlainRuns and SingleOutflowRuns: by blocks or along the runs, with
// or without dampers (`velocities` null), each a loop compiled for its case.
template <bool Dispersed>
inline __attribute__((always_inline)) void Forces(const SinglePrecisionSprings& springs,
                                                  const SingleShare& share,
                                                  const SingleNodeArrays& p,
                                                  const SingleNodeArrays* velocities, float beta,
                                                  const float* g, const SingleEndForces& forces,
                                                  const MutableSingleNodeArrays& overflow) {
  if (SingleLoopsByBlocks(springs, share)) {
    if (velocities != nullptr) {
      internal::ForceBlocks<true, Dispersed>(springs, share, p, velocities, beta, g, forces,
                                             overflow);
    } else {
      internal::ForceBlocks<false, Dispersed>(springs, share, p, velocities, beta, g, forces,
                                              overflow);
    }
  } else if (velocities != nullptr) {
    ForcesImpl<true, Dispersed>(springs, share, p, velocities, beta, g, forces, overflow);
  } else {
    ForcesImpl<false, Dispersed>(springs, share, p, velocities, beta, g, forces, overflow);
  }
}

}  // namespace

MSM_SIM_SIMD_CLONES
void ToSingleNodeArrays(const double* vectors, long n, long begin, long end, const double origin[3],
                        float* arrays) {
  const double* __restrict from = vectors;
  float* __restrict x = arrays;
  float* __restrict y = arrays + n;
  float* __restrict z = arrays + 2 * n;
  const double ox = origin[0], oy = origin[1], oz = origin[2];
  for (long i = begin; i < end; ++i) {
    x[i] = static_cast<float>(from[3 * i] - ox);
    y[i] = static_cast<float>(from[3 * i + 1] - oy);
    z[i] = static_cast<float>(from[3 * i + 2] - oz);
  }
}

MSM_SIM_SIMD_CLONES
void SingleDispersion(const float* accumulators, double fraction, const double* inverse_star_weight,
                      long n, long begin, long end, float* g_single) {
  const float* __restrict ja = accumulators;
  const float* __restrict jb = accumulators + n;
  const double* __restrict w = inverse_star_weight;
  float* __restrict gs = g_single;
  for (long i = begin; i < end; ++i) {
    const double sum = fraction * (static_cast<double>(ja[i]) + static_cast<double>(jb[i]));
    gs[i] = static_cast<float>(sum * w[i]);
  }
}

namespace {

// Each node's a-end plus b-end force (float blocks of n, x y z for the a ends, then the b ends),
// added to or stored in n column-major 3-vectors, for nodes [begin, end).
template <bool kAdd>
inline __attribute__((always_inline)) void SumEndForces(const float* end_forces, long n, long begin,
                                                        long end, double* vectors) {
  const float* __restrict a = end_forces;
  const float* __restrict b = end_forces + 3 * n;
  double* __restrict to = vectors;
  for (long i = begin; i < end; ++i) {
    for (long d = 0; d < 3; ++d) {
      const double sum = static_cast<double>(a[d * n + i]) + static_cast<double>(b[d * n + i]);
      to[3 * i + d] = kAdd ? to[3 * i + d] + sum : sum;
    }
  }
}

}  // namespace

MSM_SIM_SIMD_CLONES
void AddSingleEndForces(const float* end_forces, long n, long begin, long end, double* vectors) {
  SumEndForces<true>(end_forces, n, begin, end, vectors);
}

MSM_SIM_SIMD_CLONES
void StoreSingleEndForces(const float* end_forces, long n, long begin, long end, double* vectors) {
  SumEndForces<false>(end_forces, n, begin, end, vectors);
}

MSM_SIM_SIMD_CLONES
void SinglePlainRuns(const SinglePrecisionSprings& springs, const SingleShare& share,
                     const SingleNodeArrays& positions, const SingleNodeArrays* velocities,
                     float beta, const SingleEndForces& forces,
                     const MutableSingleNodeArrays& overflow) {
  Forces<false>(springs, share, positions, velocities, beta, nullptr, forces, overflow);
}

MSM_SIM_SIMD_CLONES
void SingleInflowRuns(const SinglePrecisionSprings& springs, const SingleShare& share,
                      const SingleNodeArrays& positions, float* j_a, float* j_b,
                      float* j_b_overflow) {
  if (SingleLoopsByBlocks(springs, share)) {
    internal::InflowBlocks(springs, share, positions, j_a, j_b, j_b_overflow);
    return;
  }
  for (const SingleRun& run : springs.runs) {
    ForRunInShare(run, share, [&](int a, int count, bool beyond) {
      const int b = a + run.offset, f = run.first + (a - run.a0);
      internal::StretchInflowAlongRun<float>(
          count, run.offset, positions.x + a, positions.y + a, positions.z + a,
          springs.rest.data() + f, springs.outflow_a.data() + f, springs.outflow_b.data() + f,
          j_a + a, BEnd(j_b, j_b_overflow, b, share.limit, beyond));
    });
  }
}

MSM_SIM_SIMD_CLONES
void SingleOutflowRuns(const SinglePrecisionSprings& springs, const SingleShare& share,
                       const SingleNodeArrays& positions, const SingleNodeArrays* velocities,
                       float beta, const float* dispersion_per_weight,
                       const SingleEndForces& forces, const MutableSingleNodeArrays& overflow) {
  Forces<true>(springs, share, positions, velocities, beta, dispersion_per_weight, forces,
               overflow);
}

}  // namespace msm_sim::core
