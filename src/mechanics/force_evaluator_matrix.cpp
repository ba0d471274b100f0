// ForceEvaluator::StiffnessMatrix: the linearisation ApplyStiffness multiplies by, assembled as a
// sparse matrix, for preconditioners that need its entries (docs/physics.md §7.1).

#include <stdexcept>
#include <vector>

#include "msm_sim/mechanics/force_evaluator.h"

namespace msm_sim::core {
namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

// Adds the 3 x 3 block at (row node, column node) to the triplets.
void AddBlock(int row, int column, const Eigen::Matrix3d& block, Triplets* triplets) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (block(i, j) != 0.0) triplets->emplace_back(3 * row + i, 3 * column + j, block(i, j));
    }
  }
}

// The column vector of d(length of spring s)/d(positions) (3N): -u at a, u at b, scaled by w,
// added to column `column` of a 3N x C matrix's triplets.
void AddElongationGradient(int a, int b, const Eigen::Vector3d& u, double w, int column,
                           Triplets* triplets) {
  for (int d = 0; d < 3; ++d) {
    triplets->emplace_back(3 * a + d, column, -w * u[d]);
    triplets->emplace_back(3 * b + d, column, w * u[d]);
  }
}

}  // namespace

Eigen::SparseMatrix<double> ForceEvaluator::StiffnessMatrix() const {
  if (directions_.cols() != model_->num_springs()) {
    throw std::logic_error(
        "StiffnessMatrix needs a per-spring linearisation (SpringKernels::kPerSpring)");
  }
  const auto& a = model_->spring_node_a();
  const auto& b = model_->spring_node_b();
  const Eigen::Index dofs = 3 * static_cast<Eigen::Index>(model_->num_nodes());
  // Springs: each a 3 x 3 block k' u u^T + (T / L)(I - u u^T) between its ends (as
  // ApplySpringStiffness's first loop).
  Triplets triplets;
  triplets.reserve(36 * static_cast<std::size_t>(model_->num_springs()));
  for (int s = 0; s < model_->num_springs(); ++s) {
    const Eigen::Vector3d u = directions_.col(s);
    const Eigen::Matrix3d uu = u * u.transpose();
    const Eigen::Matrix3d block =
        tangent_stiffness_[s] * uu +
        (geometric_tensions_[s] / lengths_[s]) * (Eigen::Matrix3d::Identity() - uu);
    AddBlock(a[s], a[s], block, &triplets);
    AddBlock(b[s], b[s], block, &triplets);
    AddBlock(a[s], b[s], -block, &triplets);
    AddBlock(b[s], a[s], -block, &triplets);
  }
  Eigen::SparseMatrix<double> stiffness(dofs, dofs);
  stiffness.setFromTriplets(triplets.begin(), triplets.end());
  if (model_->dispersion_fraction() != 0.0) stiffness += DispersionStiffnessMatrix();
  if (!model_->correction_edges().empty()) stiffness += CorrectionStiffnessMatrix();
  stiffness.makeCompressed();
  return stiffness;
}

Eigen::SparseMatrix<double> ForceEvaluator::DispersionStiffnessMatrix() const {
  // Sum over nodes x of o_x i_x^T / W_x, o_x the outflow's force directions and i_x the inflow's
  // elongation rates of x's springs (ApplySpringStiffness's dJ and dg).
  const auto& a = model_->spring_node_a();
  const auto& b = model_->spring_node_b();
  Triplets outflow, inflow;
  for (int s = 0; s < model_->num_springs(); ++s) {
    const Eigen::Vector3d u = directions_.col(s);
    AddElongationGradient(a[s], b[s], u, outflow_a_[s] * inverse_star_weight_[a[s]], a[s],
                          &outflow);
    AddElongationGradient(a[s], b[s], u, outflow_b_[s] * inverse_star_weight_[b[s]], b[s],
                          &outflow);
    AddElongationGradient(a[s], b[s], u, inflow_a_[s] * tangent_stiffness_[s], a[s], &inflow);
    AddElongationGradient(a[s], b[s], u, inflow_b_[s] * tangent_stiffness_[s], b[s], &inflow);
  }
  const Eigen::Index dofs = 3 * static_cast<Eigen::Index>(model_->num_nodes());
  Eigen::SparseMatrix<double> outflow_gradients(dofs, model_->num_nodes());
  Eigen::SparseMatrix<double> inflow_gradients(dofs, model_->num_nodes());
  outflow_gradients.setFromTriplets(outflow.begin(), outflow.end());
  inflow_gradients.setFromTriplets(inflow.begin(), inflow.end());
  return outflow_gradients * inflow_gradients.transpose();
}

Eigen::SparseMatrix<double> ForceEvaluator::CorrectionStiffnessMatrix() const {
  // Baudet correction: c sum_{axes i != j} r_i r_j^T per element, r_i the sum of the elongation
  // gradients of its four edges along axis i (ApplyCorrectionStiffness).
  const auto& a = model_->spring_node_a();
  const auto& b = model_->spring_node_b();
  const auto& edges = model_->correction_edges();
  const Eigen::Index axes = 3 * static_cast<Eigen::Index>(edges.size());
  Triplets rates, couplings;
  for (std::size_t e = 0; e < edges.size(); ++e) {
    for (int k = 0; k < 12; ++k) {
      const SpringIndex s = edges[e][k];
      AddElongationGradient(a[s], b[s], directions_.col(s), 1.0, static_cast<int>(3 * e + k / 4),
                            &rates);
    }
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        if (i != j) {
          couplings.emplace_back(3 * e + i, 3 * e + j, model_->correction_coefficients()[e]);
        }
      }
    }
  }
  Eigen::SparseMatrix<double> axis_rates(3 * static_cast<Eigen::Index>(model_->num_nodes()), axes);
  Eigen::SparseMatrix<double> coupling(axes, axes);
  axis_rates.setFromTriplets(rates.begin(), rates.end());
  coupling.setFromTriplets(couplings.begin(), couplings.end());
  return axis_rates * coupling * axis_rates.transpose();
}

}  // namespace msm_sim::core
