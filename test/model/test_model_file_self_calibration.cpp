// The self-calibration block of model files (model_file.h, format version 2): a random lattice's
// correction and what it was measured for survive SaveModel / LoadModel, files of version 1 still
// load (without one), and a block with invalid content is one clean std::runtime_error.

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "model_file_bytes.h"
#include "msm_sim/lattice/random_lattice_builder.h"
#include "msm_sim/model/model_file.h"

namespace msm_sim::core {
namespace {

// Offsets of format versions 2 and 3 (model_file.h): the block is the last 100 bytes before the
// checksum, version 3's 16 bytes of spring-law parameters before it, the format version at
// byte 16.
constexpr std::size_t kVersionOffset = 16;
constexpr std::size_t kBlockBytes = 100;
constexpr std::size_t kSpringLawParameterBytes = 16;

const Material kMaterial = Material::FromYoungsPoisson(2e5, 0.4, 1200.0);

RandomLatticeOptions Options() {
  RandomLatticeOptions options;
  options.size = Eigen::Vector3d(0.5, 0.4, 0.4);
  options.lattice.spacing = 0.1;
  options.seed = 7;
  return options;
}

// A random lattice corrected by a (made-up) measured self-calibration, which the model keeps.
Model CalibratedModel() {
  RandomLatticeOptions options = Options();
  options.calibration = RandomSelfCalibration{
      1.05, 3.5, 1.9e5, 0.399, 2, RandomSelfCalibrationConditions(kMaterial, options)};
  options.calibration->conditions.seed = 0x1234567890abcdefULL;
  options.calibration->conditions.stiffness_law = SelfCalibrationConditions::kUniformStiffness;
  options.calibration->conditions.spring_law = SpringLaw::kNonlinear;
  options.calibration->conditions.isotropic_dispersion = false;
  return BuildRandomLattice(kMaterial, options);
}

class SelfCalibrationFileTest : public ModelFileDirectoryTest {
 protected:
  // LoadModel's message for `bytes` with the block's field at `offset` set by `edit`.
  template <typename Edit>
  std::string BlockError(const Bytes& good, Edit edit) {
    Bytes bytes = good;
    edit(&bytes, bytes.size() - kChecksumBytes - kBlockBytes);
    Reseal(&bytes);
    return LoadError(bytes);
  }
};

TEST_F(SelfCalibrationFileTest, RoundTripsTheCorrectionAndItsConditions) {
  const Model model = CalibratedModel();
  ASSERT_TRUE(model.self_calibration());
  const Bytes bytes = Saved(model);
  EXPECT_EQ(bytes[kVersionOffset], kModelFileVersion);
  const Model loaded = LoadModel(Path("saved.msm"));
  ASSERT_TRUE(loaded.self_calibration());
  const SelfCalibration& a = *model.self_calibration();
  const SelfCalibration& b = *loaded.self_calibration();
  EXPECT_EQ(b.stiffness_factor, a.stiffness_factor);
  EXPECT_EQ(b.dispersion_fraction, a.dispersion_fraction);
  EXPECT_EQ(b.measured_youngs, a.measured_youngs);
  EXPECT_EQ(b.measured_poisson, a.measured_poisson);
  EXPECT_EQ(b.measurements, a.measurements);
  EXPECT_TRUE(b.conditions == a.conditions);
  EXPECT_EQ(loaded.spring_stiffness(), model.spring_stiffness());

  // A model without one loads without one.
  SaveModel(BuildRandomLattice(kMaterial, Options()), Path("plain.msm"));
  EXPECT_FALSE(LoadModel(Path("plain.msm")).self_calibration());
}

// Version 1 is version 3 without the spring-law parameters, the block and the nodes' surface
// insets (the last 8 of each 40-byte node record after the 84-byte header): such files still
// load, with no self-calibration.
TEST_F(SelfCalibrationFileTest, ReadsVersionOneFiles) {
  const Model model = CalibratedModel();
  Bytes bytes = Saved(model);
  bytes.erase(bytes.end() - kChecksumBytes - kBlockBytes - kSpringLawParameterBytes,
              bytes.end() - kChecksumBytes);
  constexpr std::size_t kHeaderBytes = 84, kNodeBytes = 40, kInsetOffset = 32;
  for (int i = model.num_nodes() - 1; i >= 0; --i) {
    const auto inset = bytes.begin() + kHeaderBytes + kNodeBytes * i + kInsetOffset;
    bytes.erase(inset, inset + 8);
  }
  PutU32(&bytes, kVersionOffset, 1);
  Reseal(&bytes);
  const Model loaded = Loaded(bytes);
  EXPECT_FALSE(loaded.self_calibration());
  EXPECT_EQ(loaded.spring_stiffness(), model.spring_stiffness());
  EXPECT_EQ(loaded.dispersion_fraction(), model.dispersion_fraction());
  EXPECT_EQ(loaded.rest_positions(), model.rest_positions());
  EXPECT_EQ(loaded.surface_insets().maxCoeff(), 0.0);
  // A version-1 header on a file that has the block: trailing data, not a misread.
  Bytes mislabelled = Saved(model);
  PutU32(&mislabelled, kVersionOffset, 1);
  Reseal(&mislabelled);
  EXPECT_THROW(Loaded(mislabelled), std::runtime_error);
}

TEST_F(SelfCalibrationFileTest, RejectsInvalidBlocksNamingThem) {
  const Bytes good = Saved(CalibratedModel());
  const auto u32 = [](std::size_t field, std::uint32_t value) {
    return [=](Bytes* b, std::size_t block) { PutU32(b, block + field, value); };
  };
  const auto f64 = [](std::size_t field, double value) {
    return [=](Bytes* b, std::size_t block) { PutF64(b, block + field, value); };
  };
  EXPECT_CONTAINS(BlockError(good, u32(0, 2)), "self-calibration block: presence flag 2");
  EXPECT_CONTAINS(BlockError(good, u32(4, 0)), "unknown lattice code 0");
  EXPECT_CONTAINS(BlockError(good, u32(8, 5)), "unknown stiffness law code 5");
  EXPECT_CONTAINS(BlockError(good, u32(12, 9)), "unknown spring law code 9");
  EXPECT_CONTAINS(BlockError(good, u32(16, 3)), "isotropic dispersion flag 3");
  EXPECT_CONTAINS(BlockError(good, u32(20, 0)), "representative block of 0 cells");
  EXPECT_CONTAINS(BlockError(good, f64(32, -0.1)), "conditions spacing -0.1");
  EXPECT_CONTAINS(BlockError(good, f64(40, 0.5)), "nu 0.5");
  EXPECT_CONTAINS(BlockError(good, f64(48, 3.0)), "0 < minL < maxL");
  EXPECT_CONTAINS(BlockError(good, f64(64, 0.0)), "stiffness factor 0");
  EXPECT_CONTAINS(BlockError(good, f64(72, 3.25)), "the model's q is 3.5");
  EXPECT_CONTAINS(BlockError(good, f64(80, NAN)), "measured E nan");
}

}  // namespace
}  // namespace msm_sim::core
