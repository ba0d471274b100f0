#pragma once

#include <Eigen/Core>

#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// A material plane through `point` with unit `normal`, in the rest configuration.
struct MaterialPlane {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();  ///< unit length
};

/// Momentum flow through a material plane (docs/physics.md §6): the force that the springs crossing
/// the plane transmit, sum_s t_s r̂_s with r̂_s oriented towards the +normal side (tension > 0). Its
/// normal component is sigma_nn times the cross-section area (negative in compression).
///
/// The plane cuts the node set by rest position (n·(x0 - p) >= 0 is the + side), so the result is
/// exactly the force one part of the body exerts on the other, even when nodes lie on the plane.
/// `tensions` are the springs' total tensions (ForceEvaluator::total_tensions(), which include
/// the eMSM dispersion). Preconditions: positions has model.num_nodes() columns, tensions has
/// model.num_springs() entries.
Eigen::Vector3d MomentumFlowThroughPlane(const Model& model, const Eigen::Matrix3Xd& positions,
                                         const Eigen::VectorXd& tensions,
                                         const MaterialPlane& plane);

}  // namespace msm_sim::core
