#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "msm_sim/core/model.h"

namespace msm_sim::core {

/// Spring tensions t_s = k_s (L_s - L0_s) for the given positions (N; tension > 0).
/// Precondition: positions has model.num_nodes() columns.
void ComputeSpringTensions(const Model& model, const Eigen::Matrix3Xd& positions,
                           Eigen::VectorXd* tensions);

/// Adds every spring's force on its two nodes to `forces` (3 x N, N) and returns the elastic
/// energy (J). A stretched spring pulls its nodes together.
/// Precondition: positions and forces have model.num_nodes() columns; no spring has zero length.
double AccumulateSpringForces(const Model& model, const Eigen::Matrix3Xd& positions,
                              Eigen::Matrix3Xd* forces);

/// Appends the tangent stiffness K = d^2 W / dx^2 of every spring as 3x3 blocks in node-major DOF
/// numbering (dof = 3 node + axis). A spring contributes k u u^T + (t / L)(I - u u^T) to its
/// diagonal blocks and the negative to its off-diagonal blocks. Blocks whose DOFs map to -1 in
/// `dof_to_unknown` are skipped (constrained DOFs), others are renumbered through it.
void AppendTangentStiffness(const Model& model, const Eigen::Matrix3Xd& positions,
                            const std::vector<int>& dof_to_unknown,
                            std::vector<Eigen::Triplet<double>>* triplets);

}  // namespace msm_sim::core
