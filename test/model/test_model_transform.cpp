// TransformedModel: the same model rigidly moved, for an eMSM built by hand and a Baudet model
// with orthogonal correction elements.
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "msm_sim/lattice/baudet_lattice_builder.h"
#include "msm_sim/mechanics/force_evaluator.h"
#include "msm_sim/model/model_builder.h"
#include "msm_sim/model/model_transform.h"

namespace msm_sim::core {
namespace {

const Material kMaterial = Material::FromYoungsPoisson(5e4, 0.4, 1100.0);

// A jittered 3 x 3 x 3 block of spacing 0.1 m with springs between nodes closer than 0.16 m,
// carrier springs, eMSM dispersion and every per-node and per-spring value different.
Model HandBuiltEmsm() {
  std::mt19937_64 random(42);
  std::uniform_real_distribution<double> jitter(-0.02, 0.02);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  ModelBuilder builder(kMaterial);
  builder.SetSpringLaw(SpringLaw::kNonlinear);
  builder.SetDispersionFraction(0.3);
  std::vector<Eigen::Vector3d> positions;
  for (int i = 0; i < 27; ++i) {
    const Eigen::Vector3d lattice(i % 3, (i / 3) % 3, i / 9);
    positions.push_back(0.1 * lattice +
                        Eigen::Vector3d(jitter(random), jitter(random), jitter(random)));
    builder.AddNode(positions.back(), 0.01 + 0.01 * unit(random));
  }
  for (NodeIndex a = 0; a < 27; ++a) {
    for (NodeIndex b = a + 1; b < 27; ++b) {
      if ((positions[b] - positions[a]).norm() > 0.16) continue;
      const SpringIndex s = builder.AddSpring(a, b, 100.0 + 50.0 * unit(random));
      builder.SetDispersionWeight(s, a, 0.5 + unit(random));
      builder.SetDispersionWeight(s, b, 0.5 + unit(random));
    }
  }
  return builder.Build(0.027, 0.1);
}

// nu = 0.4 gives a non-zero correction coefficient.
Model BaudetBlock() {
  BaudetLatticeOptions options;
  options.size = Eigen::Vector3d(0.3, 0.2, 0.2);
  options.lattice.spacing = 0.1;
  options.lattice.spring_law = SpringLaw::kNonlinear;
  return BuildBaudetLattice(kMaterial, options);
}

Eigen::Isometry3d SomePose() {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  pose.pretranslate(Eigen::Vector3d(0.5, -1.2, 2.0));
  return pose;
}

// Everything but the rest positions and rest lengths is copied exactly.
void ExpectSameTopologyAndParameters(const Model& moved, const Model& model) {
  ASSERT_EQ(moved.num_nodes(), model.num_nodes());
  ASSERT_EQ(moved.num_springs(), model.num_springs());
  EXPECT_EQ(moved.masses(), model.masses());
  EXPECT_EQ(moved.spring_node_a(), model.spring_node_a());
  EXPECT_EQ(moved.spring_node_b(), model.spring_node_b());
  EXPECT_EQ(moved.spring_stiffness(), model.spring_stiffness());
  EXPECT_EQ(moved.dispersion_weight_a(), model.dispersion_weight_a());
  EXPECT_EQ(moved.dispersion_weight_b(), model.dispersion_weight_b());
  EXPECT_EQ(moved.incidence_offsets(), model.incidence_offsets());
  EXPECT_EQ(moved.incident_springs(), model.incident_springs());
  EXPECT_EQ(moved.correction_edges(), model.correction_edges());
  EXPECT_EQ(moved.correction_coefficients(), model.correction_coefficients());
  EXPECT_EQ(moved.spring_law(), model.spring_law());
  EXPECT_EQ(moved.dispersion_fraction(), model.dispersion_fraction());
  EXPECT_EQ(moved.volume(), model.volume());
  EXPECT_EQ(moved.characteristic_length(), model.characteristic_length());
  EXPECT_EQ(moved.material().youngs_modulus(), model.material().youngs_modulus());
  EXPECT_EQ(moved.material().poisson_ratio(), model.material().poisson_ratio());
  EXPECT_EQ(moved.material().density(), model.material().density());
}

void ExpectMovedBy(const Model& moved, const Model& model, const Eigen::Isometry3d& pose) {
  const Eigen::Matrix3d rotation = pose.linear();
  for (NodeIndex i = 0; i < model.num_nodes(); ++i) {
    const Eigen::Vector3d expected = rotation * model.rest_positions().col(i) + pose.translation();
    EXPECT_LT((moved.rest_positions().col(i) - expected).norm(), 1e-14) << "node " << i;
  }
  for (SpringIndex s = 0; s < model.num_springs(); ++s) {
    EXPECT_NEAR(moved.spring_rest_length()[s], model.spring_rest_length()[s],
                1e-13 * model.spring_rest_length()[s])
        << "spring " << s;
  }
}

// The moved model is the same physics: at the moved deformed positions its internal forces are
// the rotated forces and its energy and spring tensions are unchanged, correction and
// dispersion included.
void ExpectSamePhysics(const Model& moved, const Model& model, const Eigen::Isometry3d& pose) {
  std::mt19937_64 random(7);
  std::normal_distribution<double> displacement(0.0, 0.005);
  Eigen::Matrix3Xd positions = model.rest_positions();
  for (Eigen::Index i = 0; i < positions.size(); ++i) positions.data()[i] += displacement(random);
  const Eigen::Matrix3Xd moved_positions =
      (pose.linear() * positions).colwise() + pose.translation();

  ForceEvaluator evaluator(model);
  ForceEvaluator moved_evaluator(moved);
  Eigen::Matrix3Xd forces = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
  Eigen::Matrix3Xd moved_forces = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
  evaluator.AccumulateForces(positions, &forces);
  moved_evaluator.AccumulateForces(moved_positions, &moved_forces);
  const double scale = forces.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0.1);  // the deformation is not negligible (forces of order k * 5 mm)
  EXPECT_LT((moved_forces - pose.linear() * forces).cwiseAbs().maxCoeff(), 1e-9 * scale);
  EXPECT_LT((moved_evaluator.total_tensions() - evaluator.total_tensions()).cwiseAbs().maxCoeff(),
            1e-9 * scale);
  const double energy = evaluator.ElasticEnergy(positions);
  EXPECT_GT(energy, 0.0);
  EXPECT_NEAR(moved_evaluator.ElasticEnergy(moved_positions), energy, 1e-9 * energy);
}

TEST(ModelTransform, MovesAnEmsmRigidly) {
  const Model model = HandBuiltEmsm();
  ASSERT_GT(model.num_springs(), 100);
  const Eigen::Isometry3d pose = SomePose();
  const Model moved = TransformedModel(model, pose);
  ExpectSameTopologyAndParameters(moved, model);
  ExpectMovedBy(moved, model, pose);
  ExpectSamePhysics(moved, model, pose);
}

TEST(ModelTransform, KeepsBaudetCorrectionElements) {
  const Model model = BaudetBlock();
  ASSERT_EQ(model.correction_edges().size(), 3u * 2u * 2u);  // one per brick
  ASSERT_NE(model.correction_coefficients()[0], 0.0);
  const Eigen::Isometry3d pose = SomePose();
  const Model moved = TransformedModel(model, pose);
  ExpectSameTopologyAndParameters(moved, model);
  ExpectMovedBy(moved, model, pose);
  ExpectSamePhysics(moved, model, pose);
}

TEST(ModelTransform, IdentityAndPureTranslation) {
  const Model model = HandBuiltEmsm();
  const Model same = TransformedModel(model, Eigen::Isometry3d::Identity());
  ExpectSameTopologyAndParameters(same, model);
  EXPECT_EQ(same.rest_positions(), model.rest_positions());
  EXPECT_EQ(same.spring_rest_length(), model.spring_rest_length());

  const Eigen::Vector3d shift(-3.0, 0.25, 10.0);
  const Model shifted = TransformedModel(model, Eigen::Isometry3d(Eigen::Translation3d(shift)));
  EXPECT_LT(
      ((shifted.rest_positions().colwise() - shift) - model.rest_positions()).cwiseAbs().maxCoeff(),
      1e-14);
}

TEST(ModelTransform, MovesEverySpringAlongTheRotatedDirection) {
  // A rotation of a quarter turn about z maps the Baudet block's x-edges onto y: the spring
  // directions turn with it.
  const Model model = BaudetBlock();
  Eigen::Isometry3d quarter = Eigen::Isometry3d::Identity();
  quarter.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  const Model moved = TransformedModel(model, quarter);
  for (SpringIndex s = 0; s < model.num_springs(); ++s) {
    const auto direction = [s](const Model& m) {
      return Eigen::Vector3d(m.rest_positions().col(m.spring_node_b()[s]) -
                             m.rest_positions().col(m.spring_node_a()[s]));
    };
    const Eigen::Vector3d d = direction(model);
    EXPECT_LT((direction(moved) - Eigen::Vector3d(-d.y(), d.x(), d.z())).norm(), 1e-14)
        << "spring " << s;
  }
}

TEST(ModelTransform, CarriesThePowerLawAndChangesTheLaw) {
  const Model model = HandBuiltEmsm();
  const Model power = WithSpringLaw(model, SpringLaw::kPower, PowerSpringLaw{-4.54, 0.116});
  EXPECT_EQ(power.spring_law(), SpringLaw::kPower);
  EXPECT_TRUE(power.rest_positions() == model.rest_positions());
  EXPECT_EQ(power.spring_rest_length(), model.spring_rest_length());
  const Model moved = TransformedModel(power, SomePose());
  EXPECT_EQ(moved.spring_law(), SpringLaw::kPower);
  EXPECT_EQ(moved.power_spring_law().alpha, -4.54);
  EXPECT_EQ(moved.power_spring_law().beta, 0.116);
  ExpectSamePhysics(moved, power, SomePose());
}

}  // namespace
}  // namespace msm_sim::core
