// The double run kernels of ForceEvaluator, a spring's arithmetic from spring_arithmetic.h.
// Compiled with -fno-math-errno (CMakeLists.txt): std::sqrt may then become one SIMD instruction
// instead of a call that sets errno, which lets the compiler vectorise the loops at all. Each run
// is taken in two loops, one writing node a0 + i and one node a0 + offset + i, because a single
// loop's two stores would overlap within a SIMD register whenever offset < the vector width.

#include "mechanics/force_kernels.h"

#include <algorithm>

#include "mechanics/simd_clones.h"
#include "mechanics/spring_arithmetic.h"

namespace msm_sim::core {

namespace {

constexpr int kMax = SpringSchedule::kMaxRunLength;

// A run's per-spring force vectors, applied to the a ends in the first loop and to the b ends
// in the second.
template <typename Real>
struct RunForcesOf {
  alignas(64) Real x[kMax];
  alignas(64) Real y[kMax];
  alignas(64) Real z[kMax];
};
using RunForces = RunForcesOf<double>;

template <typename Real>
inline __attribute__((always_inline)) void ApplyToEnds(const SpringRun& run,
                                                       const RunForcesOf<Real>& c, Real* x, Real* y,
                                                       Real* z) {
  Real* __restrict fx = x;
  Real* __restrict fy = y;
  Real* __restrict fz = z;
  const int a0 = run.a0, b0 = run.a0 + run.offset, n = run.count;
  for (int i = 0; i < n; ++i) {
    fx[a0 + i] += c.x[i];
    fy[a0 + i] += c.y[i];
    fz[a0 + i] += c.z[i];
  }
  for (int i = 0; i < n; ++i) {
    fx[b0 + i] -= c.x[i];
    fy[b0 + i] -= c.y[i];
    fz[b0 + i] -= c.z[i];
  }
}

inline __attribute__((always_inline)) void ApplyToEnds(const SpringRun& run, const RunForces& c,
                                                       const MutableNodeArrays& forces) {
  ApplyToEnds<double>(run, c, forces.x, forces.y, forces.z);
}

// One run's total tensions (the direct or outflow part from `tension`, plus dampers), stored and
// turned into force vectors. `tension(i, r, &inverse_length)` returns spring first + i's tension
// without the damper and sets 1 / L, given r = x_b - x_a.
template <bool Damped, typename Tension>
inline __attribute__((always_inline)) void RunTensions(const ScheduledSprings& springs,
                                                       const SpringRun& run,
                                                       const NodeArrays& positions,
                                                       const RunDamping& damping, Tension&& tension,
                                                       double* __restrict total,
                                                       RunForces* __restrict c) {
  const double* __restrict px = positions.x + run.a0;
  const double* __restrict py = positions.y + run.a0;
  const double* __restrict pz = positions.z + run.a0;
  const double* __restrict k = springs.stiffness + run.first;
  const int d = run.offset;
  for (int i = 0; i < run.count; ++i) {
    const double r[3] = {px[i + d] - px[i], py[i + d] - py[i], pz[i + d] - pz[i]};
    double inverse_length;
    double t = tension(i, r, &inverse_length);
    if constexpr (Damped) {
      const double* __restrict vx = damping.velocities->x + run.a0;
      const double* __restrict vy = damping.velocities->y + run.a0;
      const double* __restrict vz = damping.velocities->z + run.a0;
      const double rate = internal::StretchRate(vx[i + d] - vx[i], vy[i + d] - vy[i],
                                                vz[i + d] - vz[i], r[0], r[1], r[2]);
      t += internal::DamperTension(damping.beta * k[i], rate, inverse_length);
    }
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

template <bool Damped>
inline __attribute__((always_inline)) void PlainRunsImpl(
    const ScheduledSprings& springs, int run_begin, int run_end, const NodeArrays& positions,
    const RunDamping& damping, const MutableNodeArrays& forces, double* __restrict total) {
  RunForces c;
  for (int r = run_begin; r < run_end; ++r) {
    const SpringRun& run = springs.runs[r];
    const double* __restrict k = springs.stiffness + run.first;
    const double* __restrict rest = springs.rest + run.first;
    const auto tension = [&](int i, const double r[3], double* inverse_length) {
      const double length = internal::SpringLength(r[0], r[1], r[2]);
      *inverse_length = 1.0 / length;
      return internal::ElasticTension(k[i], length, rest[i]);
    };
    RunTensions<Damped>(springs, run, positions, damping, tension, total, &c);
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
      RunTensions<false>(springs, run, positions, RunDamping{nullptr, 0.0}, tension, total, &c);
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
  alignas(64) double elastic[kMax];
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

namespace {

// One run of the direct stiffness product; node arrays start at the run's a0.
template <typename Real>
inline __attribute__((always_inline)) void StiffnessRun(
    int n, int offset, const Real* __restrict k, const Real* __restrict ux,
    const Real* __restrict uy, const Real* __restrict uz, const Real* __restrict geometric,
    const Real* __restrict vx, const Real* __restrict vy, const Real* __restrict vz,
    RunForcesOf<Real>* __restrict c, Real* __restrict rate) {
  for (int i = 0; i < n; ++i) {
    const Real dx = vx[i + offset] - vx[i];
    const Real dy = vy[i + offset] - vy[i];
    const Real dz = vz[i + offset] - vz[i];
    const Real stretch = ux[i] * dx + uy[i] * dy + uz[i] * dz;
    const Real along = k[i] * stretch - geometric[i] * stretch;
    rate[i] = k[i] * stretch;
    // K dv on node a: -(k (u.dv) u + (T / L)(dv - u (u.dv))); node b gets the opposite.
    c->x[i] = -(along * ux[i] + geometric[i] * dx);
    c->y[i] = -(along * uy[i] + geometric[i] * dy);
    c->z[i] = -(along * uz[i] + geometric[i] * dz);
  }
}

// The direct stiffness product over runs [run_begin, run_end) in Real: springs' k, inflows and
// the linearisation (u, T / L) in schedule order; dv and out as x, y, z arrays;
// accumulator_change (null: no dispersion) per node.
template <typename Real>
inline __attribute__((always_inline)) void StiffnessRunsOf(
    const SpringRun* runs, int run_begin, int run_end, const Real* stiffness, const Real* inflow_a,
    const Real* inflow_b, const Real* ux, const Real* uy, const Real* uz, const Real* geometric,
    const Real* const dv[3], Real* const out[3], Real* accumulator_change) {
  RunForcesOf<Real> c;
  alignas(64) Real rate[kMax];
  for (int r = run_begin; r < run_end; ++r) {
    const SpringRun& run = runs[r];
    const int f = run.first;
    StiffnessRun<Real>(run.count, run.offset, stiffness + f, ux + f, uy + f, uz + f, geometric + f,
                       dv[0] + run.a0, dv[1] + run.a0, dv[2] + run.a0, &c, rate);
    ApplyToEnds<Real>(run, c, out[0], out[1], out[2]);
    if (accumulator_change == nullptr) continue;
    Real* __restrict ja = accumulator_change + run.a0;
    Real* __restrict jb = ja + run.offset;
    const Real* __restrict in_a = inflow_a + f;
    const Real* __restrict in_b = inflow_b + f;
    for (int i = 0; i < run.count; ++i) ja[i] += in_a[i] * rate[i];
    for (int i = 0; i < run.count; ++i) jb[i] += in_b[i] * rate[i];
  }
}

// The dispersed part, in Real: dg per node.
template <typename Real>
inline __attribute__((always_inline)) void DispersedStiffnessRunsOf(
    const SpringRun* runs, int run_begin, int run_end, const Real* outflow_a, const Real* outflow_b,
    const Real* ux, const Real* uy, const Real* uz, const Real* dg, Real* const out[3]) {
  RunForcesOf<Real> c;
  for (int r = run_begin; r < run_end; ++r) {
    const SpringRun& run = runs[r];
    const Real* __restrict out_a = outflow_a + run.first;
    const Real* __restrict out_b = outflow_b + run.first;
    const Real* __restrict ga = dg + run.a0;
    const Real* __restrict gb = ga + run.offset;
    const Real* __restrict x = ux + run.first;
    const Real* __restrict y = uy + run.first;
    const Real* __restrict z = uz + run.first;
    for (int i = 0; i < run.count; ++i) {
      const Real change = out_a[i] * ga[i] + out_b[i] * gb[i];
      c.x[i] = -change * x[i];
      c.y[i] = -change * y[i];
      c.z[i] = -change * z[i];
    }
    ApplyToEnds<Real>(run, c, out[0], out[1], out[2]);
  }
}

}  // namespace

MSM_SIM_SIMD_CLONES
void StiffnessRuns(const ScheduledSprings& springs, int run_begin, int run_end,
                   const ScheduledLinearization& linearization, const NodeArrays& dv,
                   const MutableNodeArrays& out, double* accumulator_change) {
  const double* const from[3] = {dv.x, dv.y, dv.z};
  double* const to[3] = {out.x, out.y, out.z};
  StiffnessRunsOf<double>(springs.runs, run_begin, run_end, springs.stiffness, springs.inflow_a,
                          springs.inflow_b, linearization.ux, linearization.uy, linearization.uz,
                          linearization.geometric, from, to, accumulator_change);
}

MSM_SIM_SIMD_CLONES
void DispersedStiffnessRuns(const ScheduledSprings& springs, int run_begin, int run_end,
                            const ScheduledLinearization& linearization, const double* dg,
                            const MutableNodeArrays& out) {
  double* const to[3] = {out.x, out.y, out.z};
  DispersedStiffnessRunsOf<double>(springs.runs, run_begin, run_end, springs.outflow_a,
                                   springs.outflow_b, linearization.ux, linearization.uy,
                                   linearization.uz, dg, to);
}

MSM_SIM_SIMD_CLONES
void SingleStiffnessRuns(const SingleScheduledStiffness& springs, int run_begin, int run_end,
                         const float* dv, long n, float* out, float* accumulator_change) {
  const float* const from[3] = {dv, dv + n, dv + 2 * n};
  float* const to[3] = {out, out + n, out + 2 * n};
  StiffnessRunsOf<float>(springs.runs, run_begin, run_end, springs.stiffness, springs.inflow_a,
                         springs.inflow_b, springs.ux, springs.uy, springs.uz, springs.geometric,
                         from, to, accumulator_change);
}

MSM_SIM_SIMD_CLONES
void SingleDispersedStiffnessRuns(const SingleScheduledStiffness& springs, int run_begin,
                                  int run_end, const float* dg, long n, float* out) {
  float* const to[3] = {out, out + n, out + 2 * n};
  DispersedStiffnessRunsOf<float>(springs.runs, run_begin, run_end, springs.outflow_a,
                                  springs.outflow_b, springs.ux, springs.uy, springs.uz, dg, to);
}

}  // namespace msm_sim::core
