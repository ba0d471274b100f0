// The run kernels of ForceEvaluator's linearisation and stiffness diagonal. Compiled as
// force_kernels.cpp is (-fno-math-errno, SIMD clones; CMakeLists.txt), and written with the same
// expressions as its PlainRuns and OutflowRuns, so that the tensions they linearise are the ones
// those kernels give, to the bit.

#include "mechanics/linearization_kernels.h"

#include <algorithm>

#include "mechanics/simd_clones.h"
#include "mechanics/spring_arithmetic.h"

namespace msm_sim::core {

namespace {

// The loops take their arrays as __restrict parameters, which GCC honours (restrict-qualified
// locals it did not, and the loops stayed scalar). Arrays start at the run's first spring and
// its a0 node, so node a0 + offset + i is element offset + i.

// One run's total tensions and linearisation: k (L - L0), plus o_a g_a + o_b g_b when Dispersed
// (g per node from a0), as PlainRuns / OutflowRuns sum it (SpringForcesAlongRun).
template <bool Dispersed>
inline __attribute__((always_inline)) void LinearizeRun(
    int n, int d, const double* __restrict px, const double* __restrict py,
    const double* __restrict pz, const double* __restrict k, const double* __restrict rest,
    const double* __restrict out_a, const double* __restrict out_b, const double* __restrict g,
    bool drop_compression, double* __restrict total, double* __restrict ux, double* __restrict uy,
    double* __restrict uz, double* __restrict geometric) {
  for (int i = 0; i < n; ++i) {
    const double rx = px[i + d] - px[i], ry = py[i + d] - py[i], rz = pz[i + d] - pz[i];
    const double length = internal::SpringLength(rx, ry, rz);
    const double inverse_length = 1.0 / length;
    double t = internal::ElasticTension(k[i], length, rest[i]);
    if constexpr (Dispersed) t += internal::DispersedTension(out_a[i], g[i], out_b[i], g[i + d]);
    total[i] = t;
    ux[i] = rx * inverse_length;
    uy[i] = ry * inverse_length;
    uz[i] = rz * inverse_length;
    geometric[i] = (drop_compression ? std::max(t, 0.0) : t) * inverse_length;
  }
}

// LinearizeRun over runs [run_begin, run_end); `g` is read only when Dispersed.
template <bool Dispersed>
inline __attribute__((always_inline)) void LinearizeRunsOf(
    const ScheduledSprings& springs, int run_begin, int run_end, int num_springs,
    const NodeArrays& positions, const double* g, bool drop_compression, double* total_tensions,
    double* storage) {
  for (int r = run_begin; r < run_end; ++r) {
    const SpringRun& run = springs.runs[r];
    const int a0 = run.a0, f = run.first;
    double* ux = storage + f;
    LinearizeRun<Dispersed>(
        run.count, run.offset, positions.x + a0, positions.y + a0, positions.z + a0,
        springs.stiffness + f, springs.rest + f, Dispersed ? springs.outflow_a + f : nullptr,
        Dispersed ? springs.outflow_b + f : nullptr, Dispersed ? g + a0 : nullptr, drop_compression,
        total_tensions + f, ux, ux + num_springs, ux + 2 * num_springs, ux + 3 * num_springs);
  }
}

}  // namespace

MSM_SIM_SIMD_CLONES
void LinearizePlainRuns(const ScheduledSprings& springs, int run_begin, int run_end,
                        int num_springs, const NodeArrays& positions, bool drop_compression,
                        double* total_tensions, double* storage) {
  LinearizeRunsOf<false>(springs, run_begin, run_end, num_springs, positions, nullptr,
                         drop_compression, total_tensions, storage);
}

MSM_SIM_SIMD_CLONES
void LinearizeDispersedRuns(const ScheduledSprings& springs, int run_begin, int run_end,
                            int num_springs, const NodeArrays& positions,
                            const double* dispersion_per_weight, bool drop_compression,
                            double* total_tensions, double* storage) {
  LinearizeRunsOf<true>(springs, run_begin, run_end, num_springs, positions, dispersion_per_weight,
                        drop_compression, total_tensions, storage);
}

namespace {

// One end's share of a spring's diagonal block k u^2 + (T / L)(1 - u^2), plus `dispersed` u^2.
inline __attribute__((always_inline)) double DiagonalTerm(double k, double u, double geometric,
                                                          double dispersed) {
  const double u2 = u * u;
  return k * u2 + geometric * (1.0 - u2) + dispersed * u2;
}

// One end's blocks over a run: node i of the diagonal (arrays from the node at this end of the
// run's first spring). `w_there` (null: no dispersion) is 1 / W at the other ends, whose J holds
// these springs' inflows `in_there`, which their outflows `out_there` take back.
template <bool Disperse>
inline __attribute__((always_inline)) void DiagonalEnd(
    int n, const double* __restrict k, const double* __restrict ux, const double* __restrict uy,
    const double* __restrict uz, const double* __restrict geometric,
    const double* __restrict out_there, const double* __restrict in_there,
    const double* __restrict w_there, double* __restrict dx, double* __restrict dy,
    double* __restrict dz) {
  for (int i = 0; i < n; ++i) {
    const double dispersed = Disperse ? k[i] * out_there[i] * in_there[i] * w_there[i] : 0.0;
    dx[i] += DiagonalTerm(k[i], ux[i], geometric[i], dispersed);
    dy[i] += DiagonalTerm(k[i], uy[i], geometric[i], dispersed);
    dz[i] += DiagonalTerm(k[i], uz[i], geometric[i], dispersed);
  }
}

// One end's s1 += sign outflow u and s2 += sign (inflow k) u (sign -1 at the b ends, where u
// points towards the node).
inline __attribute__((always_inline)) void DispersionSumsEnd(
    int n, double sign, const double* __restrict k, const double* __restrict ux,
    const double* __restrict uy, const double* __restrict uz, const double* __restrict out_here,
    const double* __restrict in_here, double* __restrict s1x, double* __restrict s1y,
    double* __restrict s1z, double* __restrict s2x, double* __restrict s2y,
    double* __restrict s2z) {
  for (int i = 0; i < n; ++i) {
    const double o = sign * out_here[i];
    const double p = sign * (in_here[i] * k[i]);
    s1x[i] += o * ux[i];
    s1y[i] += o * uy[i];
    s1z[i] += o * uz[i];
    s2x[i] += p * ux[i];
    s2y[i] += p * uy[i];
    s2z[i] += p * uz[i];
  }
}

// The springs of one run at their a ends (End = 0, nodes a0 + i) or b ends (End = 1, nodes
// a0 + offset + i), in separate loops so that no loop writes a node twice.
template <int End, bool Disperse>
inline __attribute__((always_inline)) void DiagonalRunEnd(
    const ScheduledSprings& springs, const SpringRun& run,
    const ScheduledLinearization& linearization, const double* inverse_star_weight,
    const MutableNodeArrays& diagonal, const MutableNodeArrays& s1, const MutableNodeArrays& s2) {
  const int f = run.first, n = run.count;
  const int here = run.a0 + End * run.offset, there = run.a0 + (1 - End) * run.offset;
  const double* k = springs.stiffness + f;
  const double* ux = linearization.ux + f;
  const double* uy = linearization.uy + f;
  const double* uz = linearization.uz + f;
  DiagonalEnd<Disperse>(n, k, ux, uy, uz, linearization.geometric + f,
                        (End == 0 ? springs.outflow_b : springs.outflow_a) + f,
                        (End == 0 ? springs.inflow_b : springs.inflow_a) + f,
                        Disperse ? inverse_star_weight + there : nullptr, diagonal.x + here,
                        diagonal.y + here, diagonal.z + here);
  if constexpr (Disperse) {
    DispersionSumsEnd(n, End == 0 ? 1.0 : -1.0, k, ux, uy, uz,
                      (End == 0 ? springs.outflow_a : springs.outflow_b) + f,
                      (End == 0 ? springs.inflow_a : springs.inflow_b) + f, s1.x + here,
                      s1.y + here, s1.z + here, s2.x + here, s2.y + here, s2.z + here);
  }
}

template <bool Disperse>
inline __attribute__((always_inline)) void StiffnessDiagonalRunsImpl(
    const ScheduledSprings& springs, int run_begin, int run_end,
    const ScheduledLinearization& linearization, const double* inverse_star_weight,
    const MutableNodeArrays& diagonal, const MutableNodeArrays& s1, const MutableNodeArrays& s2) {
  for (int r = run_begin; r < run_end; ++r) {
    const SpringRun& run = springs.runs[r];
    DiagonalRunEnd<0, Disperse>(springs, run, linearization, inverse_star_weight, diagonal, s1, s2);
    DiagonalRunEnd<1, Disperse>(springs, run, linearization, inverse_star_weight, diagonal, s1, s2);
  }
}

}  // namespace

MSM_SIM_SIMD_CLONES
void StiffnessDiagonalRuns(const ScheduledSprings& springs, int run_begin, int run_end,
                           const ScheduledLinearization& linearization,
                           const double* inverse_star_weight, const MutableNodeArrays& diagonal,
                           const MutableNodeArrays& s1, const MutableNodeArrays& s2) {
  if (inverse_star_weight != nullptr) {
    StiffnessDiagonalRunsImpl<true>(springs, run_begin, run_end, linearization, inverse_star_weight,
                                    diagonal, s1, s2);
  } else {
    StiffnessDiagonalRunsImpl<false>(springs, run_begin, run_end, linearization, nullptr, diagonal,
                                     s1, s2);
  }
}

}  // namespace msm_sim::core
