#include "msm_sim/experiments/compression_experiment.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "msm_sim/experiments/hardy_stress.h"
#include "msm_sim/experiments/momentum_flow.h"
#include "msm_sim/experiments/strain_probe.h"
#include "msm_sim/mechanics/dof_constraints.h"
#include "msm_sim/mechanics/force_evaluator.h"

namespace msm_sim::core {

namespace {

// Right stretch tensor U = sqrt(F^T F) of the least-squares affine map x = F X + c over `nodes`.
Eigen::Matrix3d CentralStretch(const Eigen::Matrix3Xd& rest, const Eigen::Matrix3Xd& positions,
                               const std::vector<int>& nodes, const Eigen::Vector3d& centre) {
  Eigen::MatrixXd design(nodes.size(), 4);
  Eigen::MatrixXd target(nodes.size(), 3);
  for (std::size_t row = 0; row < nodes.size(); ++row) {
    design.row(row) << (rest.col(nodes[row]) - centre).transpose(), 1.0;
    target.row(row) = (positions.col(nodes[row]) - centre).transpose();
  }
  const Eigen::MatrixXd solution = design.colPivHouseholderQr().solve(target);  // 4 x 3
  const Eigen::Matrix3d f = solution.topRows<3>().transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(f.transpose() * f);
  return eigen.eigenvectors() * eigen.eigenvalues().cwiseSqrt().asDiagonal() *
         eigen.eigenvectors().transpose();
}

}  // namespace

double StressCorrectedPoisson(const Eigen::Matrix3d& e, const Eigen::Matrix3d& s) {
  // From e_xx = (s_xx - nu (s_yy + s_zz)) / E and e_yy = (s_yy - nu (s_xx + s_zz)) / E.
  const double numerator = e(0, 0) * s(1, 1) - e(1, 1) * s(0, 0);
  const double denominator = e(0, 0) * (s(0, 0) + s(2, 2)) - e(1, 1) * (s(1, 1) + s(2, 2));
  return numerator / denominator;
}

CompressionExperimentResult RunCompressionExperiment(const Model& model,
                                                     const CompressionExperimentOptions& options) {
  if (options.axis < 0 || options.axis > 2) {
    throw std::invalid_argument("compression axis must be 0, 1 or 2, got " +
                                std::to_string(options.axis));
  }
  if (!(options.strain > 0.0 && options.strain < 0.5)) {
    throw std::invalid_argument("compressive strain must lie in (0, 0.5), got " +
                                std::to_string(options.strain));
  }
  const Eigen::Vector3d& size = options.body_size;
  const int ax = options.axis;                         // compressed
  const int lat1 = (ax + 1) % 3, lat2 = (ax + 2) % 3;  // lateral
  const Eigen::Vector3d centre = 0.5 * size;
  const auto& rest = model.rest_positions();
  const int n = model.num_nodes();
  const double longest_spring =
      model.num_springs() > 0
          ? *std::max_element(model.spring_rest_length().begin(), model.spring_rest_length().end())
          : model.characteristic_length();
  const double end_width =
      options.end_region_width > 0.0 ? options.end_region_width : 1.5 * longest_spring;
  const double central_half_length = 0.5 * options.central_length_fraction * size[ax];
  if (end_width >= 0.5 * size[ax] - central_half_length) {
    throw std::invalid_argument("the block is too short: end regions of " +
                                std::to_string(end_width) +
                                " m leave no free middle; make it longer or the lattice finer");
  }

  CompressionExperimentResult result;
  // The central region whose deformation gives nu.
  std::vector<int> central;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d r = rest.col(i) - centre;
    if (std::abs(r[ax]) > central_half_length) continue;
    if (std::abs(r[lat1]) > 0.5 * options.central_width_fraction * size[lat1]) continue;
    if (std::abs(r[lat2]) > 0.5 * options.central_width_fraction * size[lat2]) continue;
    central.push_back(i);
  }
  result.central_nodes = static_cast<int>(central.size());
  if (result.central_nodes < 8) {
    throw std::invalid_argument("only " + std::to_string(result.central_nodes) +
                                " nodes in the central region; refine the lattice");
  }

  // Prescribed ends: affine compression about the centre along x, free laterally.
  Eigen::Matrix3Xd positions = rest;
  DofConstraints constraints(n);
  for (int i = 0; i < n; ++i) {
    // The initial guess is the same affine compression everywhere (no lateral expansion).
    positions(ax, i) = centre[ax] + (1.0 - options.strain) * (rest(ax, i) - centre[ax]);
    if (rest(ax, i) < end_width || rest(ax, i) > size[ax] - end_width) {
      constraints.FixDof(i, ax);
      ++result.end_nodes;
    }
  }
  if (result.end_nodes == 0) throw std::invalid_argument("no node lies in the end regions");

  StaticSolverOptions solver = options.solver;
  const double a = model.characteristic_length();
  if (solver.force_tolerance <= 0.0) {
    solver.force_tolerance = 1e-7 * model.material().youngs_modulus() * a * a * options.strain;
  }
  result.solver =
      SolveStaticEquilibrium(model, constraints, Eigen::Matrix3Xd::Zero(3, n), solver, &positions);

  // E from the momentum flow through the middle plane across the axis.
  ForceEvaluator evaluator(model);
  Eigen::Matrix3Xd forces = Eigen::Matrix3Xd::Zero(3, n);
  evaluator.AccumulateForces(positions, &forces);
  const Eigen::VectorXd& tensions = evaluator.total_tensions();
  const Eigen::Vector3d flow = MomentumFlowThroughPlane(
      model, positions, tensions, MaterialPlane{centre, Eigen::Vector3d::Unit(ax)});
  result.axial_force = -flow[ax];
  const double area =
      options.cross_section_area > 0.0 ? options.cross_section_area : size[lat1] * size[lat2];
  result.youngs_measured = (result.axial_force / area) / options.strain;

  // nu from the deformation of the central region: a least-squares affine fit
  // x = F X + c over its nodes, then the right stretch U = sqrt(F^T F). Free-slip ends leave the
  // rotation about x undetermined; U is blind to it, where slopes of u_y against y are not.
  const Eigen::Matrix3d stretch = CentralStretch(rest, positions, central, centre);
  const double strain_xx = stretch(ax, ax) - 1.0;
  const double strain_lateral = 0.5 * (stretch(lat1, lat1) + stretch(lat2, lat2)) - 1.0;
  result.poisson_measured = -strain_lateral / strain_xx;

  // Stress-corrected values from point probes at the centre (thesis 3.1).
  const StrainProbe probe(rest);
  const auto centre_strain = probe.StrainAt(centre, positions - rest, 0.5 * a);
  result.centre_stress = HardyStress(model, positions, tensions, centre, 1.3 * a);
  if (centre_strain) {
    result.centre_strain = *centre_strain;
    // The formulas below take the compressed axis first: permute (ax, lat1, lat2) -> (x, y, z).
    Eigen::Matrix3d to_axis_first = Eigen::Matrix3d::Zero();
    to_axis_first(0, ax) = to_axis_first(1, lat1) = to_axis_first(2, lat2) = 1.0;
    const Eigen::Matrix3d e = to_axis_first * result.centre_strain * to_axis_first.transpose();
    const Eigen::Matrix3d s = to_axis_first * result.centre_stress * to_axis_first.transpose();
    result.poisson_stress_corrected = StressCorrectedPoisson(e, s);
    result.youngs_stress_corrected =
        (s(0, 0) - result.poisson_stress_corrected * (s(1, 1) + s(2, 2))) / e(0, 0);
  } else {
    result.poisson_stress_corrected = std::nan("");
    result.youngs_stress_corrected = std::nan("");
  }
  return result;
}

}  // namespace msm_sim::core
