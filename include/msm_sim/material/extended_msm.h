#pragma once

#include "msm_sim/material/material.h"

namespace msm_sim::core {

/// Extended MSM (eMSM, docs/physics.md §3; Kot & Nagahashi 2015): springs calibrated as a Cauchy
/// solid with the target shear modulus mu, plus momentum dispersion that adds the "fluid" modulus
/// B = lambda - mu = Q K_direct. For nu = 1/4, Q = 0 and the eMSM is the plain MSM.

/// Q = B / ((5/3) mu) = 3 (4 nu - 1) / (5 (1 - 2 nu)); Q in (-1, inf) for nu in (-1, 1/2).
double DispersionRatio(double poisson_ratio);

/// Inverse of DispersionRatio: nu(Q) = (1 + 5Q/3) / (2 (2 + 5Q/3)).
double PoissonFromDispersionRatio(double dispersion_ratio);

/// The dispersion fraction q = Q / 2 used by the force algorithm.
inline double DispersionFraction(double poisson_ratio) {
  return 0.5 * DispersionRatio(poisson_ratio);
}

/// Sum of k L^2 the direct springs of a body of volume V must have: 15 V mu (= 6 V E at
/// nu = 1/4, docs/physics.md §2).
inline double DirectSpringSumKL2(const Material& material, double volume) {
  return 15.0 * volume * material.shear_modulus();
}

}  // namespace msm_sim::core
