#pragma once

#include <Eigen/Core>

#include "msm_sim/mechanics/static_solver.h"
#include "msm_sim/mechanics/uniaxial_compression.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// The uniaxial compression experiment of docs/physics.md §6 / thesis 3.2.1 on a block [0, size]:
/// the measurement MeasureUniaxialCompression makes (E from the momentum flow, nu from the
/// central stretch), plus the stress-corrected values from point probes at the centre.
using CompressionExperimentOptions = UniaxialCompressionOptions;

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
