// Acceptance tests of models built from meshes (issue "Any mesh in"): the thesis anti-aliasing
// experiment, mass conservation, and the calibration surviving the mesh path for any nu.
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "compression_helpers.h"
#include "msm_sim/experiments/compression_experiment.h"
#include "msm_sim/geometry/mesh_primitives.h"
#include "msm_sim/lattice/baudet_lattice_builder.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/lattice/mesh_lattice_builder.h"
#include "msm_sim/lattice/random_lattice_builder.h"

namespace msm_sim::core {
namespace {

// A box mesh occupying [0, size], the frame the compression experiment expects.
SolidMesh BoxSolid(const Eigen::Vector3d& size) {
  TriangleMesh box = MakeBoxMesh(size);
  box.vertices.colwise() += 0.5 * size;
  return SolidMesh(box);
}

struct Spread {
  double mean = 0.0, mean_abs = 0.0, deviation = 0.0;
};

Spread SpreadOf(const std::vector<double>& errors) {
  Spread s;
  for (const double e : errors) {
    s.mean += e / errors.size();
    s.mean_abs += std::abs(e) / errors.size();
  }
  for (const double e : errors) s.deviation += (e - s.mean) * (e - s.mean) / errors.size();
  s.deviation = std::sqrt(s.deviation);
  return s;
}

// Thesis 5.2.1: a 5 x 5 x 5 box on a lattice of spacing 1 rotated 30 ways, compressed by 5 %
// along y (E = 250, nu = 1/4). The end plates grip the nodes within 0.75 a of the y faces: the
// mean half-extent along a fixed direction of a randomly oriented cubic cell, i.e. the nodes
// whose cells reach the plate on average.
TEST(AntiAliasing, RotatedLatticesKeepEAndNuOfTheThesisBox) {
  const Material material = Material::FromYoungsPoisson(250.0, 0.25, 1.0);
  const Eigen::Vector3d size(5.0, 5.0, 5.0);
  const SolidMesh box = BoxSolid(size);
  std::vector<double> e_error[2], nu_error[2];  // [0]: with AA, [1]: without
  std::mt19937_64 rng(2014);
  std::normal_distribution<double> gaussian;
  std::uniform_real_distribution<double> angle(0.0, M_PI);
  for (int rotation = 0; rotation < 30; ++rotation) {
    const Eigen::Vector3d axis(gaussian(rng), gaussian(rng), gaussian(rng));
    const double theta = angle(rng);
    for (const int variant : {0, 1}) {
      MeshCubicLatticeOptions options;
      options.lattice.spacing = 1.0;
      options.lattice.rotation_axis = axis;
      options.lattice.rotation_angle = theta;
      options.antialias = variant == 0;
      const Model model = BuildCubicLatticeInSolid(material, box, options);
      CompressionExperimentOptions test;
      test.body_size = size;
      test.axis = 1;
      test.strain = 0.05;
      test.end_region_width = 0.75;
      const CompressionExperimentResult r = RunCompressionExperiment(model, test);
      ASSERT_TRUE(r.solver.converged) << r.solver.message;
      e_error[variant].push_back(r.youngs_measured / 250.0 - 1.0);
      nu_error[variant].push_back(r.poisson_measured - 0.25);
    }
  }
  const Spread e_aa = SpreadOf(e_error[0]), e_plain = SpreadOf(e_error[1]);
  const Spread nu_aa = SpreadOf(nu_error[0]), nu_plain = SpreadOf(nu_error[1]);
  std::printf("  30 rotations      mean E err  mean |E err|  sd E    mean nu err  sd nu\n");
  std::printf("  with AA           %+7.2f %%   %6.2f %%     %5.2f %%  %+8.4f    %6.4f\n",
              100 * e_aa.mean, 100 * e_aa.mean_abs, 100 * e_aa.deviation, nu_aa.mean,
              nu_aa.deviation);
  std::printf("  without AA        %+7.2f %%   %6.2f %%     %5.2f %%  %+8.4f    %6.4f\n",
              100 * e_plain.mean, 100 * e_plain.mean_abs, 100 * e_plain.deviation, nu_plain.mean,
              nu_plain.deviation);
  EXPECT_LE(e_aa.mean_abs, 0.05);
  EXPECT_LT(std::abs(e_aa.mean), std::abs(e_plain.mean));
  EXPECT_LT(e_aa.deviation, e_plain.deviation);
  EXPECT_LT(std::abs(nu_aa.mean), std::abs(nu_plain.mean));
  EXPECT_LT(nu_aa.deviation, nu_plain.deviation);
}

TEST(AntiAliasing, KeepsTheMassOfASphere) {
  const Material material = Material::FromYoungsPoisson(1e5, 0.25, 1000.0);
  const SolidMesh sphere(MakeIcosphereMesh(1.0, 5));
  const double expected = material.density() * sphere.volume();
  for (const int cells_per_radius : {2, 3, 4, 5}) {
    MeshCubicLatticeOptions options;
    options.lattice.spacing = 1.0 / cells_per_radius;
    options.antialias = true;
    // The body's own mass: what mass scaling added to cut cells is not (docs/physics.md §7).
    const Model aliased = BuildCubicLatticeInSolid(material, sphere, options);
    const double with_aa = aliased.masses().sum() - aliased.added_mass();
    options.antialias = false;
    const Model plain = BuildCubicLatticeInSolid(material, sphere, options);
    const double without = plain.masses().sum() - plain.added_mass();
    std::printf("  sphere R = 1, a = 1/%d: mass error %+6.2f %% with AA, %+6.2f %% without\n",
                cells_per_radius, 100 * (with_aa / expected - 1), 100 * (without / expected - 1));
    EXPECT_NEAR(with_aa / expected, 1.0, 0.02) << "a = 1/" << cells_per_radius;
  }
}

// The mesh path builds the same calibrated eMSM as the box builders: an aligned box mesh gives
// E and nu within the tolerances of the "Any Poisson's ratio" issue.
TEST(MeshModels, CubicFromAMeshMatchesAnyPoissonRatio) {
  const Eigen::Vector3d size(2.0, 1.0, 1.0);
  const SolidMesh box = BoxSolid(size);
  for (const double nu : {-0.5, 0.25, 0.45}) {
    MeshCubicLatticeOptions options;
    options.lattice.spacing = 1.0 / 12.0;
    const Model model =
        BuildCubicLatticeInSolid(Material::FromYoungsPoisson(1e5, nu, 1100.0), box, options);
    const CompressionExperimentResult r = testing::Compress(model, size);
    EXPECT_NEAR(r.poisson_measured, nu, 0.02) << "target nu " << nu;
    EXPECT_NEAR(r.youngs_measured / 1e5, 1.0, 0.03) << "target nu " << nu;
  }
}

TEST(MeshModels, SpringLawReachesMeshBuiltModels) {
  const SolidMesh sphere(MakeIcosphereMesh(1.0, 3));
  const Material material = Material::FromYoungsPoisson(1e5, 0.45, 1000.0);
  MeshCubicLatticeOptions cubic;
  cubic.lattice.spacing = 0.25;
  cubic.lattice.spring_law = SpringLaw::kNonlinear;
  const Model cubic_model = BuildCubicLatticeInSolid(material, sphere, cubic);
  EXPECT_EQ(cubic_model.spring_law(), SpringLaw::kNonlinear);
  EXPECT_GT(cubic_model.dispersion_fraction(), 0.0);
  RandomLatticeOptions random;
  random.lattice.spacing = 0.25;
  random.lattice.spring_law = SpringLaw::kNonlinear;
  const Model random_model = BuildRandomLatticeInSolid(material, sphere, random);
  EXPECT_EQ(random_model.spring_law(), SpringLaw::kNonlinear);
  EXPECT_GT(random_model.dispersion_fraction(), 0.0);
}

// The fitted law's alpha and beta reach the model from the lattice options, for every builder.
TEST(MeshModels, PowerLawParametersReachEveryBuilder) {
  const SolidMesh sphere(MakeIcosphereMesh(1.0, 3));
  const Material material = Material::FromYoungsPoisson(1e5, 0.45, 1000.0);
  LatticeOptions lattice;
  lattice.spacing = 0.25;
  lattice.spring_law = SpringLaw::kPower;
  lattice.power_law = PowerSpringLaw{-2.5, 0.125};
  const auto expect_law = [](const Model& model, const char* builder) {
    EXPECT_EQ(model.spring_law(), SpringLaw::kPower) << builder;
    EXPECT_EQ(model.power_spring_law().alpha, -2.5) << builder;
    EXPECT_EQ(model.power_spring_law().beta, 0.125) << builder;
  };
  MeshCubicLatticeOptions in_solid;
  in_solid.lattice = lattice;
  expect_law(BuildCubicLatticeInSolid(material, sphere, in_solid), "cubic in a solid");
  RandomLatticeOptions random;
  random.lattice = lattice;
  expect_law(BuildRandomLatticeInSolid(material, sphere, random), "random in a solid");
  CubicLatticeOptions box;
  box.lattice = lattice;
  expect_law(BuildCubicLattice(material, box), "cubic box");
  BaudetLatticeOptions baudet;
  baudet.lattice = lattice;
  expect_law(BuildBaudetLattice(material, baudet), "Baudet");
}

// No spring of a random model bridges the notch of a concave body: a torus's hole.
TEST(MeshModels, RandomSpringsDoNotCrossTheSurface) {
  const SolidMesh torus(MakeTorusMesh(1.0, 0.35, 64, 24));
  RandomLatticeOptions options;
  options.lattice.spacing = 0.15;
  options.max_distance = 1.9;
  const Model model =
      BuildRandomLatticeInSolid(Material::FromYoungsPoisson(1e5, 0.25, 1000.0), torus, options);
  int checked = 0;
  for (int s = 0; s < model.num_springs(); ++s) {
    const Eigen::Vector3d a = model.rest_positions().col(model.spring_node_a()[s]);
    const Eigen::Vector3d b = model.rest_positions().col(model.spring_node_b()[s]);
    ASSERT_TRUE(torus.Contains(a) && torus.Contains(b));
    ASSERT_FALSE(torus.SegmentCrossesSurface(a, b)) << "spring " << s;
    ++checked;
  }
  EXPECT_GT(checked, 1000);
  EXPECT_NEAR(model.masses().sum() / (1000.0 * torus.volume()), 1.0, 1e-12);
}

TEST(MeshModels, RandomFromAMeshMatchesAnyPoissonRatio) {
  const Eigen::Vector3d size(3.0, 1.0, 1.0);
  const SolidMesh box = BoxSolid(size);
  for (const double nu : {0.0, 0.45}) {
    RandomLatticeOptions options;
    options.lattice.spacing = 0.1;
    options.max_distance = 1.9;
    const Model model =
        BuildRandomLatticeInSolid(Material::FromYoungsPoisson(1e5, nu, 1100.0), box, options);
    const CompressionExperimentResult r = testing::Compress(model, size);
    EXPECT_NEAR(r.poisson_measured, nu, 0.03) << "target nu " << nu;
    EXPECT_NEAR(r.youngs_measured / 1e5, 1.0, 0.05) << "target nu " << nu;
  }
}

}  // namespace
}  // namespace msm_sim::core
