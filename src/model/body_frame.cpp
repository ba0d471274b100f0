#include "msm_sim/model/body_frame.h"

#include <Eigen/SVD>

namespace msm_sim::core {

Eigen::Isometry3d BodyFrame(const Model& model, const State& state) {
  const Eigen::VectorXd& m = model.masses();
  const Eigen::Matrix3Xd& x = state.positions;
  const Eigen::Matrix3Xd& rest = model.rest_positions();
  const Eigen::Vector3d centre = x * m / m.sum();
  const Eigen::Vector3d rest_centre = rest * m / m.sum();
  const Eigen::Matrix3d covariance =
      (x.colwise() - centre) * m.asDiagonal() * (rest.colwise() - rest_centre).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance,
                                              Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d rotation = svd.matrixU() * svd.matrixV().transpose();
  if (rotation.determinant() < 0.0) {
    Eigen::Matrix3d flip = Eigen::Matrix3d::Identity();
    flip(2, 2) = -1.0;
    rotation = svd.matrixU() * flip * svd.matrixV().transpose();
  }
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  frame.linear() = rotation;
  frame.translation() = centre;
  return frame;
}

}  // namespace msm_sim::core
