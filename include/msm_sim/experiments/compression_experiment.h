#pragma once

#include <Eigen/Core>

#include "msm_sim/mechanics/static_solver.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// The uniaxial compression experiment of docs/physics.md §6 / thesis 3.2.1 on a block [0, size]
/// (below, x stands for the compressed axis and y, z for the other two).
struct CompressionExperimentOptions {
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

struct CompressionExperimentResult {
  double youngs_measured = 0.0;           ///< Pa: (F / A) / imposed strain
  double poisson_measured = 0.0;          ///< -eps_lateral / eps_xx from the central region
  double youngs_stress_corrected = 0.0;   ///< Pa, from Hardy stress and probe strain at centre
  double poisson_stress_corrected = 0.0;  ///< from Hardy stress and probe strain at centre
  double axial_force = 0.0;               ///< N, compressive > 0, momentum flow through x = Lx / 2
  Eigen::Matrix3d centre_strain = Eigen::Matrix3d::Zero();  ///< Delaunay probe at the centre
  Eigen::Matrix3d centre_stress = Eigen::Matrix3d::Zero();  ///< Pa, Hardy probe R = 1.3 ã
  int end_nodes = 0;                                        ///< nodes with prescribed x
  int central_nodes = 0;                                    ///< nodes in the regression region
  StaticSolverReport solver;
};

/// Runs the experiment. Throws std::invalid_argument for an impossible set-up (axis or strain out
/// of range, end regions that leave no free middle, a central region with too few nodes); a solver
/// that fails to converge is reported in result.solver, not thrown.
CompressionExperimentResult RunCompressionExperiment(const Model& model,
                                                     const CompressionExperimentOptions& options);

/// Poisson's ratio from a stress and a strain measured at one point, exact for isotropic linear
/// elasticity: nu = (e_xx s_yy - e_yy s_xx) / (e_xx (s_xx + s_zz) - e_yy (s_yy + s_zz)).
/// (docs/physics.md §6 derives it; the formula printed in the eMSM paper, eq. 29, is not this
/// inversion: under uniaxial stress it returns nu / (1 + nu).)
double StressCorrectedPoisson(const Eigen::Matrix3d& strain, const Eigen::Matrix3d& stress);

}  // namespace msm_sim::core
