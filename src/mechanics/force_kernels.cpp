// The double run kernels of ForceEvaluator, and the entry points of the stiffness products in
// both precisions. The loops that both precisions share (the plain pass's, the stiffness
// products') are templates in spring_run_loops.h, a spring's arithmetic in spring_arithmetic.h;
// the eMSM passes here are the double ones (the single ones store and recompute other things,
// single_precision_kernels.h). Compiled with -fno-math-errno (CMakeLists.txt): std::sqrt may
// then become one SIMD instruction instead of a call that sets errno, which lets the compiler
// vectorise the loops at all. Each run's forces go to one force array in two loops, one writing
// node a0 + i and one node a0 + offset + i, because a single loop's two stores would overlap
// within a SIMD register whenever offset < the vector width.

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

// One run's total tensions from `tension`, stored and turned into force vectors in `c`, for
// the eMSM second pass, whose tensions come from the first (the plain pass is SpringForcesAlongRun,
// spring_run_loops.h). `tension(i, r, &inverse_length)` returns spring first + i's tension and
// sets 1 / L, given r = x_b - x_a.
template <typename Tension>
inline __attribute__((always_inline)) void RunTensions(const SpringRun& run,
                                                       const NodeArrays& positions,
                                                       Tension&& tension, double* __restrict total,
                                                       RunForces* __restrict c) {
  const double* __restrict px = positions.x + run.a0;
  const double* __restrict py = positions.y + run.a0;
  const double* __restrict pz = positions.z + run.a0;
  const int d = run.offset;
  for (int i = 0; i < run.count; ++i) {
    const double r[3] = {px[i + d] - px[i], py[i + d] - py[i], pz[i + d] - pz[i]};
    double inverse_length;
    const double t = tension(i, r, &inverse_length);
    total[run.first + i] = t;
    const double scale = t * inverse_length;
    c->x[i] = scale * r[0];
    c->y[i] = scale * r[1];
    c->z[i] = scale * r[2];
  }
}

// RunTensions (without dampers) and ApplyToEnds in one loop, for runs whose offset is at least
// kFusedMinOffset: iteration i then writes node a0 + offset + i, which iteration i + offset
// reads again, so vectors of up to that many lanes never hold both (safelen), and the per-spring
// force vectors need not go through memory. Used for the eMSM second pass only: the damped
// plain pass, fused the same way, was not vectorised (docs/design/speed-against-bullet.md).
constexpr int kFusedMinOffset = 4;

template <typename Tension>
inline __attribute__((always_inline)) void FusedRunTensions(const SpringRun& run,
                                                            const NodeArrays& positions,
                                                            Tension&& tension,
                                                            double* __restrict total,
                                                            const MutableNodeArrays& forces) {
  const double* __restrict px = positions.x + run.a0;
  const double* __restrict py = positions.y + run.a0;
  const double* __restrict pz = positions.z + run.a0;
  double* fx = forces.x + run.a0;
  double* fy = forces.y + run.a0;
  double* fz = forces.z + run.a0;
  const int d = run.offset;
#pragma omp simd safelen(kFusedMinOffset)
  for (int i = 0; i < run.count; ++i) {
    const double r[3] = {px[i + d] - px[i], py[i + d] - py[i], pz[i + d] - pz[i]};
    double inverse_length;
    const double t = tension(i, r, &inverse_length);
    total[run.first + i] = t;
    const double scale = t * inverse_length;
    fx[i] += scale * r[0];
    fy[i] += scale * r[1];
    fz[i] += scale * r[2];
    fx[i + d] -= scale * r[0];
    fy[i + d] -= scale * r[1];
    fz[i + d] -= scale * r[2];
  }
}

// The plain pass: SpringForcesAlongRun in double, its force vectors applied to one force array run
// by run.
template <bool Damped>
inline __attribute__((always_inline)) void PlainRunsImpl(
    const ScheduledSprings& springs, int run_begin, int run_end, const NodeArrays& positions,
    const RunDamping& damping, const MutableNodeArrays& forces, double* __restrict total) {
  RunForces c;
  const NodeArrays none{nullptr, nullptr, nullptr};
  const NodeArrays& v = Damped ? *damping.velocities : none;
  for (int r = run_begin; r < run_end; ++r) {
    const SpringRun& run = springs.runs[r];
    const int a0 = run.a0, f = run.first;
    internal::SpringForcesAlongRun<double, Damped, false, internal::RunEnds::kScratch>(
        run.count, run.offset, positions.x + a0, positions.y + a0, positions.z + a0,
        Damped ? v.x + a0 : nullptr, Damped ? v.y + a0 : nullptr, Damped ? v.z + a0 : nullptr,
        damping.beta, nullptr, springs.stiffness + f, springs.rest + f, nullptr, nullptr, c.x, c.y,
        c.z, nullptr, nullptr, nullptr, total + f);
    ApplyToEnds(run, c, forces);
  }
}

// The dampers' tensions are already in `tensions` (InflowRuns adds them where it has r and 1 / L),
// so this pass reads no velocities.
inline __attribute__((always_inline)) void OutflowRunsImpl(
    const ScheduledSprings& springs, int run_begin, int run_end, const NodeArrays& positions,
    const double* __restrict g, const double* __restrict tensions,
    const double* __restrict inverse_lengths, const MutableNodeArrays& forces,
    double* __restrict total) {
  RunForces c;
  for (int r = run_begin; r < run_end; ++r) {
    const SpringRun& run = springs.runs[r];
    const double* __restrict t = tensions + run.first;
    const double* __restrict out_a = springs.outflow_a + run.first;
    const double* __restrict out_b = springs.outflow_b + run.first;
    const double* __restrict ga = g + run.a0;
    const double* __restrict gb = g + run.a0 + run.offset;
    // 1 / L from the first pass: no square root or division in this pass.
    const double* __restrict inverse = inverse_lengths + run.first;
    const auto tension = [&](int i, const double*, double* inverse_length) {
      *inverse_length = inverse[i];
      return t[i] + out_a[i] * ga[i] + out_b[i] * gb[i];
    };
    if (run.offset >= kFusedMinOffset) {
      FusedRunTensions(run, positions, tension, total, forces);
    } else {
      RunTensions(run, positions, tension, total, &c);
      ApplyToEnds(run, c, forces);
    }
  }
}

// One run of the eMSM first pass; node arrays start at the run's a0, so node a0 + offset + i is
// element offset + i.
template <bool Damped>
inline __attribute__((always_inline)) void InflowRun(
    int n, int offset, const double* __restrict px, const double* __restrict py,
    const double* __restrict pz, const double* __restrict vx, const double* __restrict vy,
    const double* __restrict vz, double beta, const double* __restrict k,
    const double* __restrict rest, const double* __restrict in_a, const double* __restrict in_b,
    double* __restrict t, double* __restrict inverse, double* __restrict j,
    double* __restrict elastic) {
  for (int i = 0; i < n; ++i) {
    const double rx = px[i + offset] - px[i];
    const double ry = py[i + offset] - py[i];
    const double rz = pz[i + offset] - pz[i];
    const double length = internal::SpringLength(rx, ry, rz);
    const double inverse_length = 1.0 / length;
    elastic[i] = internal::ElasticTension(k[i], length, rest[i]);
    double total = elastic[i];
    if constexpr (Damped) {
      const double rate = internal::StretchRate(vx[i + offset] - vx[i], vy[i + offset] - vy[i],
                                                vz[i + offset] - vz[i], rx, ry, rz);
      total += internal::DamperTension(beta * k[i], rate, inverse_length);
    }
    t[i] = total;
    inverse[i] = inverse_length;
    j[i] += in_a[i] * elastic[i];
  }
  for (int i = 0; i < n; ++i) j[offset + i] += in_b[i] * elastic[i];
}

template <bool Damped>
inline __attribute__((always_inline)) void InflowRunsImpl(
    const ScheduledSprings& springs, int run_begin, int run_end, const NodeArrays& positions,
    const RunDamping& damping, double* tensions, double* inverse_lengths, double* accumulator) {
  alignas(64) double elastic[internal::kMaxRunLength];
  const NodeArrays none{nullptr, nullptr, nullptr};
  const NodeArrays& v = Damped ? *damping.velocities : none;
  for (int r = run_begin; r < run_end; ++r) {
    const SpringRun& run = springs.runs[r];
    const int a0 = run.a0, f = run.first;
    InflowRun<Damped>(run.count, run.offset, positions.x + a0, positions.y + a0, positions.z + a0,
                      Damped ? v.x + a0 : nullptr, Damped ? v.y + a0 : nullptr,
                      Damped ? v.z + a0 : nullptr, damping.beta, springs.stiffness + f,
                      springs.rest + f, springs.inflow_a + f, springs.inflow_b + f, tensions + f,
                      inverse_lengths + f, accumulator + a0, elastic);
  }
}

}  // namespace

MSM_SIM_SIMD_CLONES
void PlainRuns(const ScheduledSprings& springs, int run_begin, int run_end,
               const NodeArrays& positions, const RunDamping& damping,
               const MutableNodeArrays& forces, double* total_tensions) {
  if (damping.velocities != nullptr) {
    PlainRunsImpl<true>(springs, run_begin, run_end, positions, damping, forces, total_tensions);
  } else {
    PlainRunsImpl<false>(springs, run_begin, run_end, positions, damping, forces, total_tensions);
  }
}

MSM_SIM_SIMD_CLONES
void InflowRuns(const ScheduledSprings& springs, int run_begin, int run_end,
                const NodeArrays& positions, const RunDamping& damping, double* tensions,
                double* inverse_lengths, double* accumulator) {
  if (damping.velocities != nullptr) {
    InflowRunsImpl<true>(springs, run_begin, run_end, positions, damping, tensions, inverse_lengths,
                         accumulator);
  } else {
    InflowRunsImpl<false>(springs, run_begin, run_end, positions, damping, tensions,
                          inverse_lengths, accumulator);
  }
}

MSM_SIM_SIMD_CLONES
void OutflowRuns(const ScheduledSprings& springs, int run_begin, int run_end,
                 const NodeArrays& positions, const double* dispersion_per_weight,
                 const double* tensions, const double* inverse_lengths,
                 const MutableNodeArrays& forces, double* total_tensions) {
  OutflowRunsImpl(springs, run_begin, run_end, positions, dispersion_per_weight, tensions,
                  inverse_lengths, forces, total_tensions);
}

MSM_SIM_SIMD_CLONES
void LinearizeRuns(const ScheduledSprings& springs, int run_begin, int run_end, int num_springs,
                   const NodeArrays& positions, const double* total_tensions, bool drop_compression,
                   double* storage) {
  for (int r = run_begin; r < run_end; ++r) {
    const SpringRun& run = springs.runs[r];
    const double* __restrict px = positions.x + run.a0;
    const double* __restrict py = positions.y + run.a0;
    const double* __restrict pz = positions.z + run.a0;
    const double* __restrict total = total_tensions + run.first;
    double* __restrict ux = storage + run.first;
    double* __restrict uy = ux + num_springs;
    double* __restrict uz = uy + num_springs;
    double* __restrict geometric = uz + num_springs;
    const int d = run.offset, n = run.count;
    for (int i = 0; i < n; ++i) {
      const double rx = px[i + d] - px[i], ry = py[i + d] - py[i], rz = pz[i + d] - pz[i];
      const double inverse_length = 1.0 / internal::SpringLength(rx, ry, rz);
      ux[i] = rx * inverse_length;
      uy[i] = ry * inverse_length;
      uz[i] = rz * inverse_length;
      const double t = drop_compression ? std::max(total[i], 0.0) : total[i];
      geometric[i] = t * inverse_length;
    }
  }
}

MSM_SIM_SIMD_CLONES
void StiffnessRuns(const ScheduledSprings& springs, int run_begin, int run_end,
                   const ScheduledLinearization& linearization, const NodeArrays& dv,
                   const MutableNodeArrays& out, double* accumulator_change) {
  const double* const from[3] = {dv.x, dv.y, dv.z};
  double* const to[3] = {out.x, out.y, out.z};
  internal::StiffnessRunsOf<double>(springs.runs, run_begin, run_end, springs.stiffness,
                                    springs.inflow_a, springs.inflow_b, linearization.ux,
                                    linearization.uy, linearization.uz, linearization.geometric,
                                    from, to, accumulator_change);
}

MSM_SIM_SIMD_CLONES
void DispersedStiffnessRuns(const ScheduledSprings& springs, int run_begin, int run_end,
                            const ScheduledLinearization& linearization, const double* dg,
                            const MutableNodeArrays& out) {
  double* const to[3] = {out.x, out.y, out.z};
  internal::DispersedStiffnessRunsOf<double>(springs.runs, run_begin, run_end, springs.outflow_a,
                                             springs.outflow_b, linearization.ux, linearization.uy,
                                             linearization.uz, dg, to);
}

MSM_SIM_SIMD_CLONES
void SingleStiffnessRuns(const SingleScheduledStiffness& springs, int run_begin, int run_end,
                         const float* dv, long n, float* out, float* accumulator_change) {
  const float* const from[3] = {dv, dv + n, dv + 2 * n};
  float* const to[3] = {out, out + n, out + 2 * n};
  internal::StiffnessRunsOf<float>(springs.runs, run_begin, run_end, springs.stiffness,
                                   springs.inflow_a, springs.inflow_b, springs.ux, springs.uy,
                                   springs.uz, springs.geometric, from, to, accumulator_change);
}

MSM_SIM_SIMD_CLONES
void SingleDispersedStiffnessRuns(const SingleScheduledStiffness& springs, int run_begin,
                                  int run_end, const float* dg, long n, float* out) {
  float* const to[3] = {out, out + n, out + 2 * n};
  internal::DispersedStiffnessRunsOf<float>(springs.runs, run_begin, run_end, springs.outflow_a,
                                            springs.outflow_b, springs.ux, springs.uy, springs.uz,
                                            dg, to);
}

}  // namespace msm_sim::core
