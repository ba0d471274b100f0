#include "msm_sim/mechanics/uniaxial_compression.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "msm_sim/mechanics/dof_constraints.h"
#include "msm_sim/mechanics/force_evaluator.h"
#include "msm_sim/mechanics/momentum_flow.h"

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

void ValidateAxisAndStrain(const UniaxialCompressionOptions& options) {
  if (options.axis < 0 || options.axis > 2) {
    throw std::invalid_argument("compression axis must be 0, 1 or 2, got " +
                                std::to_string(options.axis));
  }
  if (!(options.strain > 0.0 && options.strain < 0.5)) {
    throw std::invalid_argument("compressive strain must lie in (0, 0.5), got " +
                                std::to_string(options.strain));
  }
}

// Where the block is compressed, held and measured.
struct BlockLayout {
  int ax;          // compressed
  int lat1, lat2;  // lateral
  Eigen::Vector3d centre;
  double end_width;            // m: nodes this close to either end face are prescribed
  double central_half_length;  // m: half the length of the central region along ax
};

// Throws std::invalid_argument if the end regions leave no free middle.
BlockLayout LayoutOf(const Model& model, const UniaxialCompressionOptions& options) {
  const Eigen::Vector3d& size = options.body_size;
  BlockLayout layout;
  layout.ax = options.axis;
  layout.lat1 = (layout.ax + 1) % 3;
  layout.lat2 = (layout.ax + 2) % 3;
  layout.centre = 0.5 * size;
  const double longest_spring =
      model.num_springs() > 0
          ? *std::max_element(model.spring_rest_length().begin(), model.spring_rest_length().end())
          : model.characteristic_length();
  layout.end_width =
      options.end_region_width > 0.0 ? options.end_region_width : 1.5 * longest_spring;
  layout.central_half_length = 0.5 * options.central_length_fraction * size[layout.ax];
  if (layout.end_width >= 0.5 * size[layout.ax] - layout.central_half_length) {
    throw std::invalid_argument("the block is too short: end regions of " +
                                std::to_string(layout.end_width) +
                                " m leave no free middle; make it longer or the lattice finer");
  }
  return layout;
}

// The central region whose deformation gives nu. Throws std::invalid_argument if it holds
// fewer than 8 nodes.
std::vector<int> CentralNodes(const Eigen::Matrix3Xd& rest,
                              const UniaxialCompressionOptions& options,
                              const BlockLayout& layout) {
  const Eigen::Vector3d& size = options.body_size;
  std::vector<int> central;
  for (int i = 0; i < rest.cols(); ++i) {
    const Eigen::Vector3d r = rest.col(i) - layout.centre;
    if (std::abs(r[layout.ax]) > layout.central_half_length) continue;
    if (std::abs(r[layout.lat1]) > 0.5 * options.central_width_fraction * size[layout.lat1]) {
      continue;
    }
    if (std::abs(r[layout.lat2]) > 0.5 * options.central_width_fraction * size[layout.lat2]) {
      continue;
    }
    central.push_back(i);
  }
  const int num_central = static_cast<int>(central.size());
  if (num_central < 8) {
    throw std::invalid_argument("only " + std::to_string(num_central) +
                                " nodes in the central region; refine the lattice");
  }
  return central;
}

// Prescribed ends: affine compression about the centre along the axis, free laterally. The
// initial guess is the same affine compression everywhere (no lateral expansion). Returns the
// number of prescribed nodes; throws std::invalid_argument if there is none.
int PrescribeEnds(const Eigen::Matrix3Xd& rest, const UniaxialCompressionOptions& options,
                  const BlockLayout& layout, Eigen::Matrix3Xd* positions,
                  DofConstraints* constraints) {
  const int ax = layout.ax;
  const double centre = layout.centre[ax];
  const double length = options.body_size[ax];
  int end_nodes = 0;
  for (int i = 0; i < rest.cols(); ++i) {
    (*positions)(ax, i) = centre + (1.0 - options.strain) * (rest(ax, i) - centre);
    if (rest(ax, i) < layout.end_width || rest(ax, i) > length - layout.end_width) {
      constraints->FixDof(i, ax);
      ++end_nodes;
    }
  }
  if (end_nodes == 0) throw std::invalid_argument("no node lies in the end regions");
  return end_nodes;
}

// E from the momentum flow through the middle plane across the axis.
void MeasureYoungsFromFlow(const Model& model, const UniaxialCompressionOptions& options,
                           const BlockLayout& layout, UniaxialCompression* result) {
  const Eigen::Vector3d& size = options.body_size;
  const Eigen::Vector3d flow =
      MomentumFlowThroughPlane(model, result->positions, result->tensions,
                               MaterialPlane{layout.centre, Eigen::Vector3d::Unit(layout.ax)});
  result->axial_force = -flow[layout.ax];
  const double area = options.cross_section_area > 0.0 ? options.cross_section_area
                                                       : size[layout.lat1] * size[layout.lat2];
  result->youngs = (result->axial_force / area) / options.strain;
}

// nu from the deformation of the central region: a least-squares affine fit
// x = F X + c over its nodes, then the right stretch U = sqrt(F^T F). Free-slip ends leave the
// rotation about x undetermined; U is blind to it, where slopes of u_y against y are not.
double PoissonFromCentralStretch(const Eigen::Matrix3Xd& rest, const Eigen::Matrix3Xd& positions,
                                 const std::vector<int>& central, const BlockLayout& layout) {
  const Eigen::Matrix3d stretch = CentralStretch(rest, positions, central, layout.centre);
  const double strain_xx = stretch(layout.ax, layout.ax) - 1.0;
  const double strain_lateral =
      0.5 * (stretch(layout.lat1, layout.lat1) + stretch(layout.lat2, layout.lat2)) - 1.0;
  return -strain_lateral / strain_xx;
}

}  // namespace

UniaxialCompression MeasureUniaxialCompression(const Model& model,
                                               const UniaxialCompressionOptions& options) {
  ValidateAxisAndStrain(options);
  const BlockLayout layout = LayoutOf(model, options);
  const auto& rest = model.rest_positions();
  const int n = model.num_nodes();

  UniaxialCompression result;
  const std::vector<int> central = CentralNodes(rest, options, layout);
  result.central_nodes = static_cast<int>(central.size());
  result.positions = rest;
  DofConstraints constraints(n);
  result.end_nodes = PrescribeEnds(rest, options, layout, &result.positions, &constraints);

  StaticSolverOptions solver = options.solver;
  const double a = model.characteristic_length();
  if (solver.force_tolerance <= 0.0) {
    solver.force_tolerance = 1e-7 * model.material().youngs_modulus() * a * a * options.strain;
  }
  result.solver = SolveStaticEquilibrium(model, constraints, Eigen::Matrix3Xd::Zero(3, n), solver,
                                         &result.positions);

  // The tensions at equilibrium, which the momentum flow (and the experiment's Hardy stress) sum.
  ForceEvaluator evaluator(model);
  Eigen::Matrix3Xd forces = Eigen::Matrix3Xd::Zero(3, n);
  evaluator.AccumulateForces(result.positions, &forces);
  result.tensions = evaluator.total_tensions();
  MeasureYoungsFromFlow(model, options, layout, &result);
  result.poisson = PoissonFromCentralStretch(rest, result.positions, central, layout);
  return result;
}

}  // namespace msm_sim::core
