// The power spring law in model files (model_file.h, format version 3): a model with the fitted law
// of docs/physics.md §4.1 saves and loads with its alpha and beta and the same forces, its
// self-calibration keeps the law, version-2 files still load, and bad parameters are one clean
// std::runtime_error.

#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "model_file_bytes.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/lattice/random_lattice_builder.h"
#include "msm_sim/mechanics/force_evaluator.h"
#include "msm_sim/model/model_file.h"
#include "msm_sim/model/model_transform.h"

namespace msm_sim::core {
namespace {

// Offsets of format version 3 (model_file.h): the spring-law parameters are the 16 bytes before
// the 100-byte self-calibration block, which ends 8 bytes (the checksum) before the end.
constexpr std::size_t kVersionOffset = 16;
constexpr std::size_t kLawOffset = 32;
constexpr std::size_t kBlockBytes = 100;
constexpr std::size_t kParameterBytes = 16;

// The law `msm_lab fit --tensile` gives for test/data/ecoflex_00_30_tensile.csv (docs/lab.md).
const PowerSpringLaw kFittedLaw{-4.54, 0.116};
const Material kMaterial = Material::FromYoungsPoisson(1e5, 0.45, 1000.0);

Model PowerLawCube() {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(0.4, 0.3, 0.3);
  options.lattice.spacing = 0.1;
  options.lattice.spring_law = SpringLaw::kPower;
  options.lattice.power_law = kFittedLaw;
  return BuildCubicLattice(kMaterial, options);
}

RandomLatticeOptions PowerLawRandomOptions() {
  RandomLatticeOptions options;
  options.size = Eigen::Vector3d(0.5, 0.4, 0.4);
  options.lattice.spacing = 0.1;
  options.lattice.spring_law = SpringLaw::kPower;
  options.lattice.power_law = kFittedLaw;
  options.seed = 7;
  return options;
}

// A power-law random lattice corrected by a (made-up) self-calibration of `conditions`.
Model CalibratedPowerLawModel(const SelfCalibrationConditions& conditions) {
  RandomLatticeOptions options = PowerLawRandomOptions();
  options.calibration = RandomSelfCalibration{1.05, 3.5, 1.9e5, 0.399, 2, conditions};
  return BuildRandomLattice(kMaterial, options);
}

std::size_t ParametersOffset(const Bytes& bytes) {
  return bytes.size() - kChecksumBytes - kBlockBytes - kParameterBytes;
}

// The same forces and energy, bit for bit, at perturbed positions (the law acts beyond rest).
void ExpectSameForces(const Model& a, const Model& b) {
  Eigen::Matrix3Xd positions = a.rest_positions();
  for (Eigen::Index i = 0; i < positions.size(); ++i) {
    positions.data()[i] *= 1.0 + 0.02 * std::sin(static_cast<double>(i));
  }
  ForceEvaluator eval_a(a), eval_b(b);
  Eigen::Matrix3Xd forces_a = Eigen::Matrix3Xd::Zero(3, a.num_nodes());
  Eigen::Matrix3Xd forces_b = Eigen::Matrix3Xd::Zero(3, b.num_nodes());
  eval_a.AccumulateForces(positions, &forces_a);
  eval_b.AccumulateForces(positions, &forces_b);
  EXPECT_GT(forces_a.norm(), 0.0);
  EXPECT_TRUE(forces_a == forces_b);
  EXPECT_EQ(eval_a.ElasticEnergy(positions), eval_b.ElasticEnergy(positions));
}

class PowerLawFileTest : public ModelFileDirectoryTest {
 protected:
  // LoadModel's one-line message for `bytes` resealed; fails the test if it loads.
  std::string LoadError(Bytes bytes) {
    Reseal(&bytes);
    return ModelFileDirectoryTest::LoadError(bytes);
  }
};

TEST_F(PowerLawFileTest, RoundTripsThePowerLawAndItsForces) {
  const Model model = PowerLawCube();
  ASSERT_EQ(model.spring_law(), SpringLaw::kPower);
  const Bytes bytes = Saved(model);
  EXPECT_EQ(bytes[kVersionOffset], 3u);
  const Model loaded = LoadModel(Path("saved.msm"));
  EXPECT_EQ(loaded.spring_law(), SpringLaw::kPower);
  EXPECT_EQ(loaded.power_spring_law().alpha, kFittedLaw.alpha);
  EXPECT_EQ(loaded.power_spring_law().beta, kFittedLaw.beta);
  EXPECT_EQ(loaded.spring_stiffness(), model.spring_stiffness());
  ExpectSameForces(model, loaded);
  // A transformed model (WithSpringLaw) round-trips as well, whatever law it had.
  const Model carrier = WithSpringLaw(model, SpringLaw::kNonlinear);
  SaveModel(carrier, Path("carrier.msm"));
  EXPECT_EQ(LoadModel(Path("carrier.msm")).spring_law(), SpringLaw::kNonlinear);
}

TEST_F(PowerLawFileTest, TheSelfCalibrationKeepsThePowerLaw) {
  const Model model =
      CalibratedPowerLawModel(RandomSelfCalibrationConditions(kMaterial, PowerLawRandomOptions()));
  ASSERT_TRUE(model.self_calibration());
  ASSERT_EQ(model.self_calibration()->conditions.power_law.alpha, kFittedLaw.alpha);
  SaveModel(model, Path("calibrated.msm"));
  const Model loaded = LoadModel(Path("calibrated.msm"));
  ASSERT_TRUE(loaded.self_calibration());
  EXPECT_EQ(loaded.self_calibration()->conditions.spring_law, SpringLaw::kPower);
  EXPECT_TRUE(loaded.self_calibration()->conditions == model.self_calibration()->conditions);
  EXPECT_EQ(loaded.self_calibration()->conditions.power_law.beta, kFittedLaw.beta);

  // Conditions of another power law: the file holds one alpha and beta, so nothing is written.
  SelfCalibrationConditions other = model.self_calibration()->conditions;
  other.power_law.beta = 0.2;
  EXPECT_FALSE(other == model.self_calibration()->conditions);
  EXPECT_THROW(SaveModel(CalibratedPowerLawModel(other), Path("other.msm")), std::runtime_error);
  EXPECT_FALSE(std::filesystem::exists(Path("other.msm")));
}

// Version 2 is version 3 without the 16 bytes of spring-law parameters: such files still load,
// with the law of their header (linear or carrier; version 2 has no power law).
TEST_F(PowerLawFileTest, ReadsVersionTwoFiles) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(0.4, 0.3, 0.3);
  options.lattice.spacing = 0.1;
  options.lattice.spring_law = SpringLaw::kNonlinear;
  const Model model = BuildCubicLattice(kMaterial, options);
  Bytes bytes = Saved(model);
  const auto parameters = bytes.begin() + static_cast<std::ptrdiff_t>(ParametersOffset(bytes));
  bytes.erase(parameters, parameters + kParameterBytes);
  PutU32(&bytes, kVersionOffset, 2);
  Reseal(&bytes);
  const Model loaded = Loaded(bytes);
  EXPECT_EQ(loaded.spring_law(), SpringLaw::kNonlinear);
  EXPECT_EQ(loaded.power_spring_law().alpha, -1.0);
  EXPECT_EQ(loaded.spring_stiffness(), model.spring_stiffness());
  ExpectSameForces(model, loaded);
  // The power-law code in a version-2 file: it has no alpha and beta to give.
  PutU32(&bytes, kLawOffset, 2);
  EXPECT_CONTAINS(LoadError(bytes), "spring law code 2 (power) in a format version 2 file");
}

TEST_F(PowerLawFileTest, RejectsBadParametersNamingThem) {
  const Bytes good = Saved(PowerLawCube());
  const std::size_t alpha = ParametersOffset(good), beta = alpha + 8;
  const auto edited = [&](std::size_t offset, double value) {
    Bytes bytes = good;
    PutF64(&bytes, offset, value);
    return bytes;
  };
  EXPECT_CONTAINS(LoadError(edited(alpha, NAN)), "spring-law parameters alpha nan");
  EXPECT_CONTAINS(LoadError(edited(beta, -0.5)), "beta -0.5 (need a finite alpha");
  EXPECT_CONTAINS(LoadError(edited(beta, INFINITY)), "beta inf");
  // A linear model's record holds the linear law's own (1, 0).
  Bytes linear = Saved(BuildCubicLattice(kMaterial, [] {
    CubicLatticeOptions options;
    options.size = Eigen::Vector3d(0.2, 0.2, 0.2);
    options.lattice.spacing = 0.1;
    return options;
  }()));
  PutF64(&linear, ParametersOffset(linear), 2.0);
  EXPECT_CONTAINS(LoadError(linear), "but the header's law is linear (1, 0)");
  // A power-law code in the self-calibration block of a model whose springs are not power-law.
  Bytes block = Saved(
      CalibratedPowerLawModel(RandomSelfCalibrationConditions(kMaterial, PowerLawRandomOptions())));
  PutU32(&block, kLawOffset, 0);
  PutF64(&block, ParametersOffset(block), 1.0);
  PutF64(&block, ParametersOffset(block) + 8, 0.0);
  EXPECT_CONTAINS(LoadError(block), "self-calibration block: spring law code 2 (power) but");
}

}  // namespace
}  // namespace msm_sim::core
