#include "msm_sim/mechanics/lattice_uniaxial_tension.h"

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Core>

#include "msm_sim/material/extended_msm.h"

namespace msm_sim::core {
namespace {

// One spring per node of each A and B family (a = 1, κ = 1): the 3 edge and 6 face-diagonal
// springs a node shares with its neighbours (docs/physics.md §2.1).
struct CellSpring {
  Eigen::Vector3d rest;  // rest vector, |rest| = L0
};

std::array<CellSpring, 9> CellSprings() {
  return {CellSpring{{1, 0, 0}},  CellSpring{{0, 1, 0}},  CellSpring{{0, 0, 1}},
          CellSpring{{1, 1, 0}},  CellSpring{{1, -1, 0}}, CellSpring{{1, 0, 1}},
          CellSpring{{1, 0, -1}}, CellSpring{{0, 1, 1}},  CellSpring{{0, 1, -1}}};
}

// Σ k L0² over a node's star of 18 springs: 6 κ a² + 12 κ 2a².
constexpr double kStarWeight = 30.0;

// The Cauchy stress (units of κ / a) of the cell stretched by diag(axial, lateral, lateral):
// the springs' tensions t plus the dispersed tension t* = t'(L) L0 · 2 J / W, J = q Σ_star L0 t
// (k = 1; docs/physics.md §3, equal weights in the interior).
Eigen::Matrix3d CellStress(double axial, double lateral, double q, const PowerSpringLaw& law) {
  const Eigen::Vector3d stretch(axial, lateral, lateral);
  const std::array<CellSpring, 9> springs = CellSprings();
  std::array<double, 9> tension{};
  double inflow = 0.0;
  for (std::size_t i = 0; i < springs.size(); ++i) {
    const double l0 = springs[i].rest.norm();
    const double length = stretch.cwiseProduct(springs[i].rest).norm();
    tension[i] = law.Tension(1.0, l0, length);
    inflow += 2.0 * q * l0 * tension[i];  // each spring is in the star twice (±)
  }
  Eigen::Matrix3d stress = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < springs.size(); ++i) {
    const double l0 = springs[i].rest.norm();
    const Eigen::Vector3d current = stretch.cwiseProduct(springs[i].rest);
    const double tangent = law.TangentStiffness(1.0, l0, current.norm());
    const double total = tension[i] + tangent * l0 * 2.0 * inflow / kStarWeight;
    stress += total * current * current.transpose() / current.norm();
  }
  return stress / stretch.prod();
}

}  // namespace

LatticeTensionState LatticeUniaxialTension(double strain, double youngs, double poisson,
                                           const PowerSpringLaw& law) {
  if (!(strain > -0.5) || !std::isfinite(strain) || !(youngs > 0.0) ||
      !(poisson > -1.0 && poisson < 0.5)) {
    throw std::invalid_argument("lattice tension: strain " + std::to_string(strain) +
                                ", E and nu out of range");
  }
  const double q = 0.5 * DispersionRatio(poisson);
  const double axial = 1.0 + strain;
  const auto lateral_stress = [&](double l) { return CellStress(axial, l, q, law)(1, 1); };
  // σ_yy falls as the lattice contracts laterally; bisect on a bracket around the root.
  double low = 0.02, high = 1.5;
  double f_low = lateral_stress(low), f_high = lateral_stress(high);
  if (!(f_low < 0.0 && f_high > 0.0)) {
    throw std::runtime_error("lattice tension: no lateral equilibrium at strain " +
                             std::to_string(strain));
  }
  for (int i = 0; i < 200 && high - low > 1e-13; ++i) {
    const double mid = 0.5 * (low + high);
    (lateral_stress(mid) < 0.0 ? low : high) = mid;
  }
  LatticeTensionState state;
  state.lateral_stretch = 0.5 * (low + high);
  const double cauchy = CellStress(axial, state.lateral_stretch, q, law)(0, 0);
  const double shear = 1.0;  // μ = κ / a for κ = a = 1
  const double mu = youngs / (2.0 * (1.0 + poisson));
  state.nominal_stress = mu / shear * cauchy * state.lateral_stretch * state.lateral_stretch;
  return state;
}

}  // namespace msm_sim::core
