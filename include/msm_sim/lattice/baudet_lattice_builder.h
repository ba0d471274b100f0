#pragma once

#include <Eigen/Core>

#include "msm_sim/lattice/lattice_options.h"
#include "msm_sim/material/material.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// A box [0, size] meshed with cubic bricks of edge `lattice.spacing` in the manner of Baudet et
/// al. (seeds 003/004): every brick has 8 corner masses, 12 edge springs and 4 inner-diagonal
/// springs, plus orthogonal correction forces that make any Poisson's ratio possible.
struct BaudetLatticeOptions {
  Eigen::Vector3d size = Eigen::Vector3d::Ones();  ///< m, each > 0
  /// Brick edge a (m, <= the smallest size), spring law, node limit and rotation about the box
  /// centre (LatticeOptions).
  LatticeOptions lattice;
  /// Off drops the correction forces: then only nu = 1/4 is reproduced (the paper's finding).
  bool orthogonal_correction = true;
};

/// Stiffnesses of one brick of edge a, from the Lagrangian derivation in
/// docs/baudet_derivation.md (lambda, mu the Lame constants).
struct BaudetStiffness {
  double edge;        ///< k = (lambda + mu) a / 4, per brick edge (shared edges add up)
  double diagonal;    ///< k_c = 3 mu a / 4 = 3 E a / (8 (1 + nu)), per inner diagonal
  double correction;  ///< c = (lambda - mu) a / 16 = E a (4 nu - 1) / (32 (1 + nu)(1 - 2 nu))
};
BaudetStiffness ComputeBaudetStiffness(const Material& material, double spacing);

/// Builds the Baudet model of the box: bricks whose centre lies inside it, mass rho a^3 / 8 at
/// each brick corner, the brick springs above (edges shared by neighbouring bricks add up), and
/// one correction element per brick (Model::correction_edges). Under any homogeneous strain each
/// brick stores exactly the continuum energy of its volume, so a block has the target E and nu.
/// No eMSM dispersion. Throws std::invalid_argument for bad geometry, like BuildCubicLattice.
Model BuildBaudetLattice(const Material& material, const BaudetLatticeOptions& options);

}  // namespace msm_sim::core
