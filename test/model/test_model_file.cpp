// Model files (SaveModel / LoadModel): bit-exact round trips of every model kind, and one clean
// std::runtime_error, never a crash, for every damaged or foreign file.
#include <sys/stat.h>
#include <sys/types.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "model_file_bytes.h"
#include "model_file_test.h"
#include "msm_sim/geometry/mesh_primitives.h"
#include "msm_sim/geometry/solid_mesh.h"
#include "msm_sim/lattice/mesh_lattice_builder.h"
#include "msm_sim/lattice/random_lattice_builder.h"
#include "msm_sim/mechanics/force_evaluator.h"
#include "msm_sim/model/model_file.h"

namespace msm_sim::core {
namespace {

// Layout of format versions 1 to 3 (model_file.h), for crafting damaged files.
constexpr std::size_t kVersionOffset = 16;
constexpr std::size_t kCountsOffset = 20;
constexpr std::size_t kLawOffset = 32;
constexpr std::size_t kMaterialOffset = 36;
constexpr std::size_t kNodesOffset = 84;

Model RandomModel() {
  RandomLatticeOptions options;
  options.size = Eigen::Vector3d(0.5, 0.4, 0.4);
  options.lattice.spacing = 0.1;
  options.seed = 7;
  return BuildRandomLattice(Material::FromYoungsPoisson(2e5, 0.4, 1200.0), options);
}

void ExpectIdentical(const Model& a, const Model& b) {
  ASSERT_EQ(a.num_nodes(), b.num_nodes());
  ASSERT_EQ(a.num_springs(), b.num_springs());
  EXPECT_TRUE(SameBits(a.rest_positions(), b.rest_positions()));
  EXPECT_TRUE(SameBits(a.masses(), b.masses()));
  EXPECT_TRUE(SameBits(a.surface_insets(), b.surface_insets()));
  EXPECT_EQ(a.spring_node_a(), b.spring_node_a());
  EXPECT_EQ(a.spring_node_b(), b.spring_node_b());
  EXPECT_TRUE(SameBits(a.spring_rest_length(), b.spring_rest_length()));
  EXPECT_TRUE(SameBits(a.spring_stiffness(), b.spring_stiffness()));
  EXPECT_TRUE(SameBits(a.dispersion_weight_a(), b.dispersion_weight_a()));
  EXPECT_TRUE(SameBits(a.dispersion_weight_b(), b.dispersion_weight_b()));
  EXPECT_EQ(a.correction_edges(), b.correction_edges());
  EXPECT_TRUE(SameBits(a.correction_coefficients(), b.correction_coefficients()));
  EXPECT_EQ(a.incidence_offsets(), b.incidence_offsets());
  EXPECT_EQ(a.incident_springs(), b.incident_springs());
  EXPECT_EQ(a.spring_law(), b.spring_law());
  EXPECT_TRUE(SameBits(a.dispersion_fraction(), b.dispersion_fraction()));
  EXPECT_TRUE(SameBits(a.volume(), b.volume()));
  EXPECT_TRUE(SameBits(a.characteristic_length(), b.characteristic_length()));
  EXPECT_TRUE(SameBits(a.material().youngs_modulus(), b.material().youngs_modulus()));
  EXPECT_TRUE(SameBits(a.material().poisson_ratio(), b.material().poisson_ratio()));
  EXPECT_TRUE(SameBits(a.material().density(), b.material().density()));
}

// Perturbs every node by up to 1 % of the spacing, so springs, dispersion and corrections all act.
Eigen::Matrix3Xd Perturbed(const Model& model) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::Matrix3Xd positions = model.rest_positions();
  for (Eigen::Index i = 0; i < positions.size(); ++i) {
    positions.data()[i] += 0.01 * model.characteristic_length() * uniform(rng);
  }
  return positions;
}

void ExpectSameForces(const Model& a, const Model& b) {
  const Eigen::Matrix3Xd positions = Perturbed(a);
  ForceEvaluator eval_a(a), eval_b(b);
  Eigen::Matrix3Xd forces_a = Eigen::Matrix3Xd::Zero(3, a.num_nodes());
  Eigen::Matrix3Xd forces_b = Eigen::Matrix3Xd::Zero(3, b.num_nodes());
  eval_a.AccumulateForces(positions, &forces_a);
  eval_b.AccumulateForces(positions, &forces_b);
  EXPECT_GT(forces_a.norm(), 0.0);
  EXPECT_TRUE(SameBits(forces_a, forces_b));
  EXPECT_TRUE(SameBits(eval_a.ElasticEnergy(positions), eval_b.ElasticEnergy(positions)));
}

TEST_F(ModelFileTest, RoundTripsACubicEmsmLattice) {
  const Model model = CubicModel();
  ASSERT_GT(model.dispersion_fraction(), 0.0);
  SaveModel(model, Path("cubic.msm"));
  const Model loaded = LoadModel(Path("cubic.msm"));
  ExpectIdentical(model, loaded);
  ExpectSameForces(model, loaded);
}

// A lattice filling a sphere: its cut cells' nodes carry surface insets.
TEST_F(ModelFileTest, RoundTripsTheSurfaceInsetsOfAMeshLattice) {
  MeshCubicLatticeOptions options;
  options.lattice.spacing = 0.3;
  const Model model = BuildCubicLatticeInSolid(Material::FromYoungsPoisson(1e5, 0.3, 1000.0),
                                               SolidMesh(MakeIcosphereMesh(1.0, 3)), options);
  ASSERT_GT(model.surface_insets().maxCoeff(), 0.0);
  SaveModel(model, Path("sphere.msm"));
  const Model loaded = LoadModel(Path("sphere.msm"));
  ExpectIdentical(model, loaded);
}

TEST_F(ModelFileTest, RoundTripsARandomLattice) {
  const Model model = RandomModel();
  SaveModel(model, Path("random.msm"));
  const Model loaded = LoadModel(Path("random.msm"));
  ExpectIdentical(model, loaded);
  ExpectSameForces(model, loaded);
}

TEST_F(ModelFileTest, RoundTripsABaudetLattice) {
  const Model model = BaudetModel();
  ASSERT_FALSE(model.correction_edges().empty());
  SaveModel(model, Path("baudet.msm"));
  const Model loaded = LoadModel(Path("baudet.msm"));
  ExpectIdentical(model, loaded);
  ExpectSameForces(model, loaded);
}

TEST_F(ModelFileTest, SaveReplacesAnExistingFileAndLeavesNoTemporaryFile) {
  SaveModel(CubicModel(), Path("model.msm"));
  const Model baudet = BaudetModel();
  SaveModel(baudet, Path("model.msm"));
  ExpectIdentical(baudet, LoadModel(Path("model.msm")));
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir_)) {
    ++files;
    EXPECT_EQ(entry.path().filename(), "model.msm");
  }
  EXPECT_EQ(files, 1);
}

TEST_F(ModelFileTest, SaveToAnUnwritablePathThrows) {
  const Model model = BaudetModel(0.1);
  const std::string missing_dir = Path("no_such_dir/model.msm");
  try {
    SaveModel(model, missing_dir);
    ADD_FAILURE() << "SaveModel wrote into a missing directory";
  } catch (const std::runtime_error& e) {
    EXPECT_CONTAINS(std::string(e.what()), missing_dir);
  }
  // A directory in the way: the rename fails, and the temporary file must not stay behind.
  std::filesystem::create_directory(Path("taken"));
  EXPECT_THROW(SaveModel(model, Path("taken")), std::runtime_error);
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir_)) {
    ++files;
    EXPECT_EQ(entry.path().filename(), "taken");
  }
  EXPECT_EQ(files, 1);
}

TEST_F(ModelFileTest, RejectsFilesThatAreNotModelFiles) {
  try {
    LoadModel(Path("missing.msm"));
    ADD_FAILURE() << "loaded a missing file";
  } catch (const std::runtime_error& e) {
    EXPECT_CONTAINS(std::string(e.what()), "cannot open: No such file or directory");
  }
  EXPECT_CONTAINS(LoadError({}), "empty file");
  const std::string text = "E = 1e5\nnu = 0.3\nthis is a text file, not a model\n";
  EXPECT_CONTAINS(LoadError(Bytes(text.begin(), text.end())), "bad magic");
  EXPECT_CONTAINS(LoadError(Bytes(200, 0)), "bad magic");

  try {
    LoadModel(dir_);
    ADD_FAILURE() << "loaded a directory";
  } catch (const std::runtime_error& e) {
    EXPECT_CONTAINS(std::string(e.what()), "is a directory");
  }
  // A FIFO without a writer would block a plain open() forever.
  ASSERT_EQ(mkfifo(Path("fifo").c_str(), 0600), 0);
  try {
    LoadModel(Path("fifo"));
    ADD_FAILURE() << "loaded a FIFO";
  } catch (const std::runtime_error& e) {
    EXPECT_CONTAINS(std::string(e.what()), "not a regular file");
  }
}

TEST_F(ModelFileTest, RejectsBadMagicAndOtherVersions) {
  const Bytes good = Saved(BaudetModel(0.1));
  Bytes bad_magic = good;
  bad_magic[3] = 'X';
  EXPECT_CONTAINS(LoadError(bad_magic), "not an msm_sim model file (bad magic)");

  Bytes newer = good;
  PutU32(&newer, kVersionOffset, 7);
  Reseal(&newer);
  EXPECT_CONTAINS(LoadError(newer),
                  "written by format version 7, this build reads versions 1 to 3");
}

TEST_F(ModelFileTest, EveryTruncationThrows) {
  const Bytes good = Saved(BaudetModel(0.1));
  ASSERT_GT(good.size(), 1000u);
  for (std::size_t length = 0; length < good.size(); ++length) {
    WriteBytes(Path("prefix.msm"), good.data(), length);
    EXPECT_THROW(LoadModel(Path("prefix.msm")), std::runtime_error) << "prefix " << length;
  }
  const Bytes prefix(good.begin(), good.end() - 1);
  EXPECT_CONTAINS(LoadError(prefix), "truncated (expected " + std::to_string(good.size()) +
                                         " bytes, file has " + std::to_string(prefix.size()) + ")");
  Bytes longer = good;
  longer.push_back(0);
  EXPECT_CONTAINS(LoadError(longer), "trailing data");
}

TEST_F(ModelFileTest, EveryFlippedByteThrows) {
  const Bytes good = Saved(BaudetModel(0.1));
  for (std::size_t i = 0; i < good.size(); ++i) {
    for (const unsigned char mask : {0x01, 0x80, 0xff}) {
      Bytes damaged = good;
      damaged[i] ^= mask;
      WriteBytes(Path("flipped.msm"), damaged);
      EXPECT_THROW(LoadModel(Path("flipped.msm")), std::runtime_error) << "byte " << i;
    }
  }
  // A flipped payload byte is reported as corruption, not as whatever it happens to spell.
  Bytes damaged = good;
  damaged[good.size() / 2] ^= 0x10;
  EXPECT_CONTAINS(LoadError(damaged), "checksum mismatch (file corrupt)");
}

// Invalid header and node fields, each refused with its reason (`edit`: the test's lambda).
template <typename Edit>
void ExpectInvalidHeaderAndNodesRefused(const Edit& edit) {
  // Absurd counts are refused before anything is allocated.
  EXPECT_CONTAINS(edit([](Bytes* b) { PutU32(b, kCountsOffset, 0x7fffffff); }), "truncated");
  EXPECT_CONTAINS(edit([](Bytes* b) { PutU32(b, kCountsOffset + 4, 0xffffffff); }),
                  "counts out of range");
  EXPECT_CONTAINS(edit([](Bytes* b) { PutU32(b, kCountsOffset, 0); }), "no nodes");
  EXPECT_CONTAINS(edit([](Bytes* b) { PutU32(b, kLawOffset, 3); }), "unknown spring law code 3");
  EXPECT_CONTAINS(edit([](Bytes* b) { PutF64(b, kMaterialOffset + 8, 0.5); }),
                  "invalid material: Poisson's ratio");
  EXPECT_CONTAINS(edit([](Bytes* b) { PutF64(b, kMaterialOffset + 24, -0.5); }),
                  "dispersion fraction");
  EXPECT_CONTAINS(edit([](Bytes* b) { PutF64(b, kMaterialOffset + 32, 0.0); }), "volume");
  EXPECT_CONTAINS(edit([](Bytes* b) { PutF64(b, kNodesOffset + 24, std::nan("")); }),
                  "node 0 has mass nan");
  EXPECT_CONTAINS(edit([](Bytes* b) { PutF64(b, kNodesOffset + 40 + 8, INFINITY); }),
                  "node 1 has a non-finite position");
  EXPECT_CONTAINS(edit([](Bytes* b) { PutF64(b, kNodesOffset + 32, -1.0); }),
                  "node 0 has inset -1");
}

// Files with a valid checksum but invalid content: what a buggy or malicious writer produces.
TEST_F(ModelFileTest, RejectsInvalidContentWithAValidChecksum) {
  const Bytes good = Saved(BaudetModel(0.1));
  const std::uint32_t nodes = GetU32(good, kCountsOffset);
  const std::uint32_t springs = GetU32(good, kCountsOffset + 4);
  const std::size_t springs_offset = kNodesOffset + 40 * std::size_t{nodes};
  const std::size_t corrections_offset = springs_offset + 40 * std::size_t{springs};
  auto edit = [&](auto change) {
    Bytes bytes = good;
    change(&bytes);
    Reseal(&bytes);
    return LoadError(bytes);
  };

  ExpectInvalidHeaderAndNodesRefused(edit);

  const std::uint32_t a0 = GetU32(good, springs_offset);
  const std::uint32_t b0 = GetU32(good, springs_offset + 4);
  EXPECT_CONTAINS(edit([&](Bytes* b) { PutU32(b, springs_offset + 4, a0); }),
                  "spring 0 joins node " + std::to_string(a0) + " to itself");
  EXPECT_CONTAINS(edit([&](Bytes* b) { PutU32(b, springs_offset, 1000000); }),
                  "spring 0 joins node 1000000 to node");
  EXPECT_CONTAINS(edit([&](Bytes* b) { PutF64(b, springs_offset + 8, -1.0); }),
                  "spring 0 has stiffness -1");
  EXPECT_CONTAINS(edit([&](Bytes* b) { PutF64(b, springs_offset + 32, -1.0); }),
                  "dispersion weights");
  // Spring 0's nodes moved onto each other: the builder's own check, wrapped into one line.
  EXPECT_CONTAINS(edit([&](Bytes* b) {
                    for (int d = 0; d < 3; ++d) {
                      PutF64(b, kNodesOffset + 32 * b0 + 8 * d,
                             GetF64(good, kNodesOffset + 32 * a0 + 8 * d));
                    }
                  }),
                  "spring 0: spring joins two coincident nodes");
  const double rest_length = GetF64(good, springs_offset + 16);
  EXPECT_CONTAINS(edit([&](Bytes* b) { PutF64(b, springs_offset + 16, rest_length * 1.001); }),
                  "spring 0 has stored rest length");
  // A relative difference below 1e-12 (another platform's rounding) is accepted.
  {
    Bytes bytes = good;
    PutF64(&bytes, springs_offset + 16, std::nextafter(rest_length, 1.0));
    Reseal(&bytes);
    WriteBytes(Path("rounded.msm"), bytes);
    EXPECT_NO_THROW(LoadModel(Path("rounded.msm")));
  }
  EXPECT_CONTAINS(edit([&](Bytes* b) { PutU32(b, corrections_offset + 44, springs); }),
                  "correction element 0 refers to spring " + std::to_string(springs));
  EXPECT_CONTAINS(edit([&](Bytes* b) { PutF64(b, corrections_offset + 48, NAN); }),
                  "correction element 0 has a non-finite coefficient");
}

}  // namespace
}  // namespace msm_sim::core
