#pragma once

// A spring's arithmetic, written once for every scalar the kernels run in: double (the double
// run kernels, force_kernels.cpp), float (the single run loops, single_precision_kernels.cpp) and
// the single block loops' 8 float lanes (single_block_loops.h); the run loops both precisions
// share are in spring_run_loops.h. For the kernels' files only: inlined into their SIMD clones
// (simd_clones.h). The expressions fix the order of the operations, so every caller rounds alike
// (docs/physics.md §9).

#include <cmath>

namespace msm_sim::core::internal {

// The block loops instantiate these for GCC's 32-byte vector types; everything here is inlined,
// so the ABI note GCC gives for passing them does not apply (as in single_block_loops.h).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

/// |r| for r = x_b - x_a (not for lanes: their square root is single_block_loops.h's Sqrt).
template <typename Real>
inline __attribute__((always_inline)) Real SpringLength(Real rx, Real ry, Real rz) {
  return std::sqrt(rx * rx + ry * ry + rz * rz);
}

/// A linear spring's elastic tension k (L - L0) (docs/physics.md §2).
template <typename Real>
inline __attribute__((always_inline)) Real ElasticTension(Real k, Real length, Real rest) {
  return k * (length - rest);
}

/// dL/dt times L: (v_b - v_a) . r, from the ends' velocity differences along x, y and z.
template <typename Real>
inline __attribute__((always_inline)) Real StretchRate(Real dvx, Real dvy, Real dvz, Real rx,
                                                       Real ry, Real rz) {
  return dvx * rx + dvy * ry + dvz * rz;
}

/// The damper's tension beta k dL/dt = (beta k) (stretch rate) / L (docs/physics.md §7).
template <typename Real>
inline __attribute__((always_inline)) Real DamperTension(Real beta_k, Real rate,
                                                         Real inverse_length) {
  return beta_k * rate * inverse_length;
}

/// The single loops' dispersed tension o_a g_a + o_b g_b (o the end outflows v k L0, g = J / W
/// at each end; docs/physics.md §3). The double kernels add it to the stored tension term by term.
template <typename Real>
inline __attribute__((always_inline)) Real DispersedTension(Real outflow_a, Real g_a,
                                                            Real outflow_b, Real g_b) {
  return outflow_a * g_a + outflow_b * g_b;
}

#pragma GCC diagnostic pop

}  // namespace msm_sim::core::internal
