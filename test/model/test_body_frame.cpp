// BodyFrame: the centre of mass and best-fit rotation that the node publishes as an object's tf.
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/model/body_frame.h"
#include "msm_sim/model/state.h"

namespace msm_sim::core {
namespace {

Model Block() {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(0.4, 0.2, 0.1);
  options.lattice.spacing = 0.05;
  return BuildCubicLattice(Material::FromYoungsPoisson(1e5, 0.3, 1000.0), options);
}

TEST(BodyFrame, AtRestIsTheRestCentreOfMassWithoutRotation) {
  const Model model = Block();
  const Eigen::Isometry3d frame = BodyFrame(model, State::AtRest(model));
  // A uniform node-centred block: the centre of mass is the box centre.
  EXPECT_LT((frame.translation() - Eigen::Vector3d(0.2, 0.1, 0.05)).norm(), 1e-12);
  EXPECT_LT((frame.linear() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

TEST(BodyFrame, RecoversARigidMotion) {
  const Model model = Block();
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  motion.linear() =
      Eigen::AngleAxisd(2.5, Eigen::Vector3d(1.0, -2.0, 0.5).normalized()).toRotationMatrix();
  motion.translation() = Eigen::Vector3d(0.3, -1.2, 2.0);
  State state = State::AtRest(model);
  state.positions = motion * model.rest_positions();
  const Eigen::Isometry3d frame = BodyFrame(model, state);
  EXPECT_LT((frame.linear() - motion.linear()).norm(), 1e-12);
  EXPECT_LT((frame.translation() - motion * Eigen::Vector3d(0.2, 0.1, 0.05)).norm(), 1e-12);
}

TEST(BodyFrame, IgnoresAStretchAndReturnsAProperRotation) {
  const Model model = Block();
  // Stretch along x and squash along z, then turn 30 degrees about z: the frame keeps the turn.
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(M_PI / 6.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d stretch = Eigen::Vector3d(1.2, 1.0, 0.7).asDiagonal();
  State state = State::AtRest(model);
  state.positions = (rotation * stretch) * model.rest_positions();
  const Eigen::Isometry3d frame = BodyFrame(model, state);
  EXPECT_LT((frame.linear() - rotation).norm(), 1e-12);
  EXPECT_NEAR(frame.linear().determinant(), 1.0, 1e-12);
}

TEST(BodyFrame, NeverReturnsAReflection) {
  const Model model = Block();
  // A mirror image (z -> -z) has no rotation that maps rest onto it; the fit must still be a
  // rotation (determinant +1), not the reflection.
  State state = State::AtRest(model);
  state.positions.row(2) *= -1.0;
  const Eigen::Isometry3d frame = BodyFrame(model, state);
  EXPECT_NEAR(frame.linear().determinant(), 1.0, 1e-12);
  EXPECT_LT((frame.linear() * frame.linear().transpose() - Eigen::Matrix3d::Identity()).norm(),
            1e-12);
}

}  // namespace
}  // namespace msm_sim::core
