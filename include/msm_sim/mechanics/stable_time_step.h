#pragma once

#include <vector>

#include "msm_sim/model/model.h"

namespace msm_sim::core {

struct StableTimeStepOptions {
  double damping_beta = 0.0;  ///< s, the spring dampers' c = beta k
  /// Fraction of the stability limit to use (< 1 leaves room for contacts and prescribed
  /// motion, which the limit does not see).
  double safety = 0.8;
  /// Carrier springs stiffen under compression (tangent k (L0 / L)^2), as do power-law springs
  /// with alpha < 1 (docs/physics.md §4.1); the step stays stable for springs compressed down to
  /// this fraction of their rest length.
  double min_compression = 0.7;
  /// Power-law springs with beta > 0 (or alpha > 1) stiffen in tension; the step stays stable
  /// for springs stretched up to this multiple of their rest length (>= 1).
  double max_stretch = 2.0;
  /// Nodes that do not move (clamped or driven): the integrator never advances them, so their
  /// masses do not limit the step; their rows and columns are left out of K and C. Face anchors
  /// (AnchorNodes), whose token mass would otherwise give a step 10^3 times too short, must be
  /// among them. Default none.
  std::vector<NodeIndex> fixed_nodes;
};

/// Largest stable step (s) of the explicit integration of `model` (docs/physics.md §7).
///
/// Position Verlet (the dampers at the step's start velocity) is stable while
/// M - (dt^2 / 4) K - (dt / 2) C stays positive semi-definite; the step returned is the largest dt
/// for which it does, i.e. the largest eigenvalue of M^-1/2 ((dt^2 / 4) K + (dt / 2) C) M^-1/2 is
/// 1 (for symmetric K; times the safety factor). Without dampers it is 2 / omega_max; with
/// dampers C = beta K (plain MSM) it is (2 / omega_max)(sqrt(1 + zeta^2) - zeta),
/// zeta = beta omega_max / 2. The dampers act on the springs' own k only (C / beta = sum k u u^T),
/// not on the eMSM dispersion, so at nu = 0.49, where the dispersion makes the bulk mode 7 times
/// faster, omega_c << omega_max and the dampers shorten the step much less than Rayleigh damping
/// beta K would (docs/physics.md §7). omega_max^2 is the largest eigenvalue of M^-1/2 K M^-1/2 at
/// rest, and omega_c^2 that of M^-1/2 (C / beta) M^-1/2; the largest dt with
/// (dt^2 / 4) omega_max^2 + (dt / 2) beta omega_c^2 <= 1 is a sufficient bound (K and C are
/// positive semi-definite), a few percent short at nu near 1/2 where K's and C's highest modes
/// differ. The sharp limit lies between it and 2 / omega_max and is found by bisection on the
/// pencil's Rayleigh-Ritz projection on a Krylov basis of up to 60 vectors. All come from the
/// exact stiffness, so they count the eMSM dispersion, Baudet's correction and any mass
/// distribution; the per-node estimate min_i sqrt(m_i / sum_j k_ij) ignores the dispersion, which
/// at nu = 0.49 stiffens the bulk mode 7-fold. The eigenvalue is the largest Rayleigh-Ritz value
/// on a Krylov (Lanczos) basis of up to 60 vectors (K is symmetric for every spring law), which
/// converges in a few dozen products even where the top of the spectrum is clustered and never
/// exceeds the true value. For carrier springs omega_max is also raised by the stiffening of
/// springs compressed to min_compression, for power-law springs by a bound on their tangent
/// between min_compression and max_stretch. A model without springs, or whose nodes are all fixed,
/// gives +infinity. Throws std::invalid_argument for options out of range (safety in (0, 1],
/// min_compression in (0, 1], max_stretch >= 1, damping >= 0, fixed nodes that are not nodes of the
/// model).
double StableTimeStep(const Model& model, const StableTimeStepOptions& options = {});

}  // namespace msm_sim::core
