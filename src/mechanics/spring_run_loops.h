#pragma once

// The spring loops along a run that both precisions share, each one template on the scalar,
// for the double run kernels (force_kernels.cpp) and the single run loops
// (single_precision_kernels.cpp): SpringForcesAlongRun, the plain MSM's force pass and the eMSM's
// second pass; StretchInflowAlongRun, the eMSM's first pass; and the stiffness products
// StiffnessRunsOf and DispersedStiffnessRunsOf. For the kernels' files only: inlined into their
// SIMD clones (simd_clones.h). What stays per precision in SpringForcesAlongRun is two small
// choices, 1 / L (InverseLength) and where a spring's force goes (RunEnds).

#include "mechanics/spring_arithmetic.h"
#include "mechanics/spring_schedule.h"

namespace msm_sim::core::internal {

/// Longest run of the double schedule (SpringSchedule): the length of a run's scratch.
constexpr int kMaxRunLength = SpringSchedule::kMaxRunLength;

/// 1 / L. The double kernels' springs are the model's, never of zero length (ForceEvaluator's
/// precondition).
inline __attribute__((always_inline)) double InverseLength(double length) { return 1.0 / length; }

/// 1 / L in single precision, finite for a slot of zero length (a phantom between coinciding
/// nodes, single_precision_kernels.h): its r is then 0, and so is its force. The 1e-30 m leaves
/// any length above 1e-22 m unchanged (it is below half its last place); a select on L > 0, or
/// std::max, would not vectorise (GCC keeps the comparison's control flow, the division it
/// guards may trap).
inline __attribute__((always_inline)) float InverseLength(float length) {
  return 1.0f / (length + 1e-30f);
}

/// Where SpringForcesAlongRun puts spring i's force vector s (on its a end; the b end takes -s).
enum class RunEnds {
  /// Stores s at i in the first three arrays (a run's scratch) and the total tension at i in
  /// `total`; the caller applies s to both ends afterwards. For ends in one force array, where
  /// the two ends' stores of one SIMD loop would overlap whenever offset < the vector width.
  kScratch,
  /// Adds s at i to the first three arrays (the a ends) and subtracts it at i from the other
  /// three (the b ends): two force arrays, so that one loop takes both ends at any offset.
  kBothEnds,
};

/// Springs 0 .. n - 1 of a run, each joining nodes i and i + d of the node arrays (px .. vz
/// from the run's a0; velocities read only when Damped): total tension k (L - L0), plus the
/// dispersed tension o_a g_a + o_b g_b when Dispersed (o the end outflows v k L0, g per node from
/// a0; docs/physics.md §3), plus the damper's beta k dL/dt when Damped (docs/physics.md §7);
/// force t r / L on the a end, its opposite on the b end, put as `Ends` says. Per-spring arrays
/// (k, rest, outflows, total) from the run's first spring. The pointers are restrict parameters
/// because GCC trusts those: as restrict locals it kept a scalar fallback and took it.
template <typename Real, bool Damped, bool Dispersed, RunEnds Ends>
inline __attribute__((always_inline)) void SpringForcesAlongRun(
    int n, int d, const Real* __restrict px, const Real* __restrict py, const Real* __restrict pz,
    const Real* __restrict vx, const Real* __restrict vy, const Real* __restrict vz, Real beta,
    const Real* __restrict g, const Real* __restrict k, const Real* __restrict rest,
    const Real* __restrict outflow_a, const Real* __restrict outflow_b, Real* __restrict fax,
    Real* __restrict fay, Real* __restrict faz, Real* __restrict fbx, Real* __restrict fby,
    Real* __restrict fbz, Real* __restrict total) {
#pragma omp simd
  for (int i = 0; i < n; ++i) {
    // r as three scalars: an array is a memory object the loop may not vectorise.
    const Real rx = px[i + d] - px[i], ry = py[i + d] - py[i], rz = pz[i + d] - pz[i];
    const Real length = SpringLength(rx, ry, rz);
    const Real inverse_length = InverseLength(length);
    Real t = ElasticTension(k[i], length, rest[i]);
    if constexpr (Dispersed) t += DispersedTension(outflow_a[i], g[i], outflow_b[i], g[i + d]);
    if constexpr (Damped) {
      const Real rate =
          StretchRate(vx[i + d] - vx[i], vy[i + d] - vy[i], vz[i + d] - vz[i], rx, ry, rz);
      t += DamperTension(beta * k[i], rate, inverse_length);
    }
    const Real scale = t * inverse_length;
    const Real sx = scale * rx, sy = scale * ry, sz = scale * rz;
    if constexpr (Ends == RunEnds::kScratch) {
      total[i] = t;
      fax[i] = sx;
      fay[i] = sy;
      faz[i] = sz;
    } else {
      fax[i] += sx;
      fay[i] += sy;
      faz[i] += sz;
      fbx[i] -= sx;
      fby[i] -= sy;
      fbz[i] -= sz;
    }
  }
}

/// The eMSM first pass along a run: each spring's stretch L - L0 times its end outflows (o_a,
/// o_b), added to the a end's accumulator (ja, from the run's a0) and the b end's (jb, from node
/// a0 + d), which then hold J / q at every node (J = q sum o (L - L0), docs/physics.md §3). Only
/// the elastic tension feeds J, so the pass reads no velocities and stores nothing per spring;
/// the a and b ends' sums are separate arrays, so that one loop takes both ends at any offset.
template <typename Real>
inline __attribute__((always_inline)) void StretchInflowAlongRun(
    int n, int d, const Real* __restrict px, const Real* __restrict py, const Real* __restrict pz,
    const Real* __restrict rest, const Real* __restrict outflow_a, const Real* __restrict outflow_b,
    Real* __restrict ja, Real* __restrict jb) {
#pragma omp simd
  for (int i = 0; i < n; ++i) {
    const Real rx = px[i + d] - px[i], ry = py[i + d] - py[i], rz = pz[i + d] - pz[i];
    const Real stretch = SpringLength(rx, ry, rz) - rest[i];
    ja[i] += outflow_a[i] * stretch;
    jb[i] += outflow_b[i] * stretch;
  }
}

/// A run's per-spring force vectors (SpringForcesAlongRun's RunEnds::kScratch), which
/// ApplyToEnds applies to the a ends in a first loop and to the b ends in a second.
template <typename Real>
struct RunScratch {
  alignas(64) Real x[kMaxRunLength];
  alignas(64) Real y[kMaxRunLength];
  alignas(64) Real z[kMaxRunLength];
};

/// Adds c to the run's a ends and subtracts it from its b ends in one force array (x, y, z).
template <typename Real>
inline __attribute__((always_inline)) void ApplyToEnds(const SpringRun& run,
                                                       const RunScratch<Real>& c, Real* x, Real* y,
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

/// One run of the direct stiffness product; node arrays from the run's a0 (dv, the a ends'
/// out and change) or b0 (the b ends'). K dv on node a: -(k (u.dv) u + (T / L)(dv - u (u.dv)));
/// node b gets the opposite. With Disperse, the accumulators' change inflow k (u.dv) per end.
template <typename Real, bool Disperse>
inline __attribute__((always_inline)) void StiffnessRun(
    int n, int offset, const Real* __restrict k, const Real* __restrict in_a,
    const Real* __restrict in_b, const Real* __restrict ux, const Real* __restrict uy,
    const Real* __restrict uz, const Real* __restrict geometric, const Real* __restrict vx,
    const Real* __restrict vy, const Real* __restrict vz, Real* __restrict ax, Real* __restrict ay,
    Real* __restrict az, Real* __restrict bx, Real* __restrict by, Real* __restrict bz,
    Real* __restrict ja, Real* __restrict jb) {
  for (int i = 0; i < n; ++i) {
    const Real dx = vx[i + offset] - vx[i];
    const Real dy = vy[i + offset] - vy[i];
    const Real dz = vz[i + offset] - vz[i];
    const Real stretch = ux[i] * dx + uy[i] * dy + uz[i] * dz;
    const Real along = k[i] * stretch - geometric[i] * stretch;
    const Real cx = along * ux[i] + geometric[i] * dx;
    const Real cy = along * uy[i] + geometric[i] * dy;
    const Real cz = along * uz[i] + geometric[i] * dz;
    ax[i] -= cx;
    ay[i] -= cy;
    az[i] -= cz;
    bx[i] += cx;
    by[i] += cy;
    bz[i] += cz;
    if constexpr (Disperse) {
      const Real rate = k[i] * stretch;
      ja[i] += in_a[i] * rate;
      jb[i] += in_b[i] * rate;
    }
  }
}

/// One run of the dispersed part: the dispersed tensions' change o_a dg_a + o_b dg_b along u;
/// arrays from the run's first spring, a0 (dg, the a ends) or b0 (the b ends).
template <typename Real>
inline __attribute__((always_inline)) void DispersedStiffnessRun(
    int n, int offset, const Real* __restrict out_a, const Real* __restrict out_b,
    const Real* __restrict ux, const Real* __restrict uy, const Real* __restrict uz,
    const Real* __restrict dg, Real* __restrict ax, Real* __restrict ay, Real* __restrict az,
    Real* __restrict bx, Real* __restrict by, Real* __restrict bz) {
  for (int i = 0; i < n; ++i) {
    const Real change = out_a[i] * dg[i] + out_b[i] * dg[i + offset];
    ax[i] -= change * ux[i];
    ay[i] -= change * uy[i];
    az[i] -= change * uz[i];
    bx[i] += change * ux[i];
    by[i] += change * uy[i];
    bz[i] += change * uz[i];
  }
}

/// The direct stiffness product over runs [run_begin, run_end) in Real: springs' k, inflows and
/// the linearisation (u, T / L) in schedule order; dv as x, y, z arrays. Each spring's part goes
/// to its a end in `out_a` and to its b end in `out_b` (the caller sums the two), so that one
/// loop takes both ends at any offset; likewise the accumulators' change inflow k u.d(dv) to
/// `change_a` and `change_b` (null: no dispersion). Run: the double schedule's SpringRun, or the
/// float schedule's SingleRun over its slots (a phantom's zero k, u and T / L add nothing).
template <typename Real, typename Run>
inline __attribute__((always_inline)) void StiffnessRunsOf(
    const Run* runs, int run_begin, int run_end, const Real* stiffness, const Real* inflow_a,
    const Real* inflow_b, const Real* ux, const Real* uy, const Real* uz, const Real* geometric,
    const Real* const dv[3], Real* const out_a[3], Real* const out_b[3], Real* change_a,
    Real* change_b) {
  for (int r = run_begin; r < run_end; ++r) {
    const Run& run = runs[r];
    const int f = run.first, a0 = run.a0, b0 = run.a0 + run.offset;
    if (change_a == nullptr) {
      StiffnessRun<Real, false>(run.count, run.offset, stiffness + f, nullptr, nullptr, ux + f,
                                uy + f, uz + f, geometric + f, dv[0] + a0, dv[1] + a0, dv[2] + a0,
                                out_a[0] + a0, out_a[1] + a0, out_a[2] + a0, out_b[0] + b0,
                                out_b[1] + b0, out_b[2] + b0, nullptr, nullptr);
    } else {
      StiffnessRun<Real, true>(
          run.count, run.offset, stiffness + f, inflow_a + f, inflow_b + f, ux + f, uy + f, uz + f,
          geometric + f, dv[0] + a0, dv[1] + a0, dv[2] + a0, out_a[0] + a0, out_a[1] + a0,
          out_a[2] + a0, out_b[0] + b0, out_b[1] + b0, out_b[2] + b0, change_a + a0, change_b + b0);
    }
  }
}

/// The dispersed part, in Real: dg per node; ends as in StiffnessRunsOf.
template <typename Real, typename Run>
inline __attribute__((always_inline)) void DispersedStiffnessRunsOf(
    const Run* runs, int run_begin, int run_end, const Real* outflow_a, const Real* outflow_b,
    const Real* ux, const Real* uy, const Real* uz, const Real* dg, Real* const out_a[3],
    Real* const out_b[3]) {
  for (int r = run_begin; r < run_end; ++r) {
    const Run& run = runs[r];
    const int f = run.first, a0 = run.a0, b0 = run.a0 + run.offset;
    DispersedStiffnessRun<Real>(run.count, run.offset, outflow_a + f, outflow_b + f, ux + f, uy + f,
                                uz + f, dg + a0, out_a[0] + a0, out_a[1] + a0, out_a[2] + a0,
                                out_b[0] + b0, out_b[1] + b0, out_b[2] + b0);
  }
}

}  // namespace msm_sim::core::internal
