#pragma once

#include "msm_sim/material/power_spring_law.h"

namespace msm_sim::core {

/// The node-centred cubic eMSM lattice (docs/physics.md §2.1, §3) stretched homogeneously along
/// x and free to contract in y and z, with every spring following `law` (docs/physics.md §4.1).
struct LatticeTensionState {
  double nominal_stress = 0.0;   ///< Pa: axial force over the undeformed cross-section
  double lateral_stretch = 1.0;  ///< y and z stretch at which the lateral stress vanishes
};

/// The lattice's uniaxial response at engineering strain `strain` (> -0.5) for a material of
/// Young's modulus `youngs` (Pa) and Poisson's ratio `poisson` in (-1, 0.5), by the exact
/// reduction of docs/physics.md §4.1: under a homogeneous stretch F = diag(1 + strain, l, l)
/// every interior node of the lattice is a centre of symmetry, so it is in equilibrium, and the
/// stress is the cell's spring sum (A and B springs, κ = μ a, plus the §3 dispersion with
/// J = q Σ L0 t). The lateral stretch l is the root of σ_yy = 0. The result does not depend on
/// the spacing a and is proportional to `youngs`. Throws std::invalid_argument for arguments out
/// of range and std::runtime_error if σ_yy has no root for l in (0.02, 1.5).
LatticeTensionState LatticeUniaxialTension(double strain, double youngs, double poisson,
                                           const PowerSpringLaw& law);

}  // namespace msm_sim::core
