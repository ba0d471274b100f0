#pragma once

#include <Eigen/Core>

#include "msm_sim/mechanics/static_solver.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// The uniaxial compression of docs/physics.md §6 / thesis 3.2.1 on a block [0, size] (below, x
/// stands for the compressed axis and y, z for the other two): both ends are moved affinely
/// along x and left free in y and z, the rest relaxes to static equilibrium, and E and nu are
/// read from the momentum flow through the middle plane and the central region's stretch. The
/// measurement the compression experiment (experiments/compression_experiment.h) and the random
/// lattices' self-calibration (MeasureRandomSelfCalibration) share.
struct UniaxialCompressionOptions {
  Eigen::Vector3d body_size = Eigen::Vector3d::Ones();  ///< m; the block the model fills
  int axis = 0;                                         ///< compressed axis: 0 (x), 1 (y) or 2 (z)
  double strain = 0.01;  ///< imposed compressive strain along x, in (0, 0.5)
  /// Nodes whose rest x is within this distance (m) of either x face are moved affinely along x
  /// and left free in y and z (ends that slide laterally). <= 0: 1.5 times the longest rest
  /// spring.
  double end_region_width = 0.0;
  /// Cross-section (m^2) the axial force is divided by; <= 0: the block's, Ly Lz. A body that
  /// is not a block (a mesh) gives the area of its section through the middle plane.
  double cross_section_area = 0.0;
  /// The central region whose deformation gives nu: |x - xc| <= fraction Lx / 2 and the central
  /// width fraction of the block in y and z (0.8 by default, as in the thesis).
  double central_length_fraction = 0.5;
  double central_width_fraction = 0.8;
  /// Solver settings; a force_tolerance <= 0 means 1e-7 E ã^2 strain.
  StaticSolverOptions solver{0.0};
};

/// The compressed block at equilibrium and what is read from it.
struct UniaxialCompression {
  double youngs = 0.0;       ///< Pa: (F / A) / imposed strain
  double poisson = 0.0;      ///< -eps_lateral / eps_xx from the central region's stretch
  double axial_force = 0.0;  ///< N, compressive > 0, momentum flow through x = Lx / 2
  int end_nodes = 0;         ///< nodes with prescribed x
  int central_nodes = 0;     ///< nodes in the regression region
  StaticSolverReport solver;
  Eigen::Matrix3Xd positions;  ///< m, the nodes at equilibrium (or where the solver stopped)
  /// N, the springs' total tensions at `positions` (ForceEvaluator::total_tensions, in double).
  Eigen::VectorXd tensions;
};

/// Compresses and measures the block. Throws std::invalid_argument for an impossible set-up
/// (axis or strain out of range, end regions that leave no free middle, a central region with
/// fewer than 8 nodes); a solver that fails to converge is reported in result.solver, not thrown.
UniaxialCompression MeasureUniaxialCompression(const Model& model,
                                               const UniaxialCompressionOptions& options);

}  // namespace msm_sim::core
