// Selective mass scaling of cut cells (src/lattice/selective_mass_scaling.h,
// NodeCentredSurfaceOptions::mass_scaling, docs/physics.md §7 "Selective mass scaling"): bounded,
// only on cut cells, boxes untouched, and the mesh object's explicit substeps near a box's. The
// accuracy tests it must keep passing are the dynamics, grasp and Hertz tests, run with it on.
#include "lattice/selective_mass_scaling.h"

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "msm_sim/geometry/mesh_import.h"
#include "msm_sim/lattice/body_recipe.h"
#include "msm_sim/lattice/body_shape.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/mechanics/stable_time_step.h"

namespace msm_sim::core {
namespace {

// The grasp issue's bean: E 259 kPa, nu 0.49, rho 1070, 3 mm, outer layer keeping 1/4.
const Material kSilicone = Material::FromYoungsPoisson(259e3, 0.49, 1070.0);
constexpr double kSpacing = 0.003;

BodyRecipe Recipe(double bound) {
  BodyRecipe recipe(kSilicone);
  recipe.lattice.spacing = kSpacing;
  recipe.surface.surface_dispersion = 0.25;
  recipe.surface.mass_scaling = bound;
  return recipe;
}

Model Bean(double bound) {
  BodyRecipe recipe = Recipe(bound);
  MeshImportOptions import;
  import.scale = 0.42;
  recipe.solid = std::make_shared<const SolidMesh>(
      ImportSolidMesh(std::string(MSM_SIM_PACKAGE_DIR) + "/meshes/soft_bean.obj", import));
  return BuildModel(recipe);
}

Model Box(double bound) {
  BodyRecipe recipe = Recipe(bound);
  recipe.box_size = Eigen::Vector3d(0.048, 0.03, 0.03);  // 16 x 10 x 10 cells, the bean's size
  return BuildModel(recipe);
}

// Explicit substeps per 1 ms step in the grasp experiment's World: its dampers (1 ms), safety
// 0.8 (World::Step divides the step by the stable step).
int SubstepsPerStep(const Model& model, double beta = 1e-3) {
  StableTimeStepOptions options;
  options.damping_beta = beta;
  return static_cast<int>(std::ceil(1e-3 / StableTimeStep(model, options)));
}

TEST(SelectiveMassScaling, LeavesABoxOfWholeCellsExactlyAsBuilt) {
  const Model scaled = Box(0.01), plain = Box(0.0);
  EXPECT_EQ(scaled.added_mass(), 0.0);
  EXPECT_FALSE(scaled.mass_scaling_limited());
  ASSERT_EQ(scaled.num_nodes(), plain.num_nodes());
  for (int i = 0; i < scaled.num_nodes(); ++i) ASSERT_EQ(scaled.masses()[i], plain.masses()[i]);
  EXPECT_EQ(scaled.spring_stiffness(), plain.spring_stiffness());
}

// The default bound (1 %) holds; only cut cells (lighter than a whole cell) gain mass, none
// loses any, and every node that gained is brought down to a whole interior cell's figure.
TEST(SelectiveMassScaling, AddsBoundedMassToCutCellsOnly) {
  const Model scaled = Bean(0.01), plain = Bean(0.0);
  ASSERT_EQ(scaled.num_nodes(), plain.num_nodes());
  EXPECT_EQ(plain.added_mass(), 0.0);
  const double body = plain.masses().sum();
  EXPECT_GT(scaled.added_mass(), 0.0);
  EXPECT_LE(scaled.added_mass(), 0.01 * body * (1.0 + 1e-9));
  EXPECT_NEAR(scaled.masses().sum() - body, scaled.added_mass(), 1e-12 * body);
  const double cell = kSilicone.density() * std::pow(kSpacing, 3);
  int gained = 0;
  for (int i = 0; i < scaled.num_nodes(); ++i) {
    ASSERT_GE(scaled.masses()[i], plain.masses()[i]);
    if (scaled.masses()[i] == plain.masses()[i]) continue;
    EXPECT_LT(plain.masses()[i], cell * (1.0 - 1e-6)) << "node " << i << " is a whole cell";
    ++gained;
  }
  EXPECT_GT(gained, 0);
  std::printf("bean: %d nodes, %d scaled, added %.3f %% of %.2f g%s\n", scaled.num_nodes(), gained,
              100.0 * scaled.added_mass() / body, 1e3 * body,
              scaled.mass_scaling_limited() ? " (limited)" : "");
}

// docs/physics.md §7 "Selective mass scaling": the bean's explicit substeps per 1 ms step within
// 1.25 times those of a box of the same spacing and material (deterministic: the stable step).
TEST(SelectiveMassScaling, BeanTakesNearlyTheSubstepsOfABox) {
  const int box = SubstepsPerStep(Box(0.01));
  const int plain = SubstepsPerStep(Bean(0.0));
  const int scaled = SubstepsPerStep(Bean(0.01));
  std::printf("substeps per 1 ms step: box %d, bean %d unscaled, %d scaled\n", box, plain, scaled);
  EXPECT_LE(scaled, 1.25 * box);
  EXPECT_LT(scaled, plain);
}

// A bound too small for the full-cell figure: the scaling spends exactly the bound and says so.
TEST(SelectiveMassScaling, ScalesLessWhenTheBoundWouldBeExceeded) {
  const Model limited = Bean(1e-4), plain = Bean(0.0);
  const double body = plain.masses().sum();
  EXPECT_TRUE(limited.mass_scaling_limited());
  EXPECT_NEAR(limited.added_mass(), 1e-4 * body, 1e-9 * body);
  EXPECT_LE(SubstepsPerStep(limited), SubstepsPerStep(plain));
}

TEST(SelectiveMassScaling, RefusesABoundOutOfRangeNamingTheKey) {
  for (const double bound : {-0.01, 0.2, std::nan("")}) {
    CubicLatticeOptions options;
    options.size = Eigen::Vector3d(0.01, 0.01, 0.01);
    options.lattice.spacing = 0.005;
    options.surface.mass_scaling = bound;
    try {
      BuildCubicLattice(kSilicone, options);
      ADD_FAILURE() << "accepted mass_scaling " << bound;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("mass_scaling"), std::string::npos) << e.what();
    }
  }
}

Model Primitive(BodyShape::Kind kind, double bound) {
  BodyShape shape;
  shape.kind = kind;
  shape.radius = kind == BodyShape::Kind::kSphere ? 0.025 : 0.02;
  shape.length = 0.06;
  BodyRecipe recipe = Recipe(bound);
  recipe.solid = std::make_shared<const SolidMesh>(MakeBodySolid(shape));
  return BuildModel(recipe);
}

// Sphere (5 cm) and cylinder (4 x 6 cm) of the grasp grid at 3 mm: within the default bound,
// and fewer substeps than without.
TEST(SelectiveMassScaling, PrimitivesStayWithinTheDefaultBound) {
  for (const BodyShape::Kind kind : {BodyShape::Kind::kSphere, BodyShape::Kind::kCylinder}) {
    const Model model = Primitive(kind, 0.01), plain = Primitive(kind, 0.0);
    const double fraction = model.added_mass() / plain.masses().sum();
    const int substeps = SubstepsPerStep(model), unscaled = SubstepsPerStep(plain);
    std::printf("%s: %d nodes, added %.3f %%%s, substeps per 1 ms step %d unscaled, %d scaled\n",
                kind == BodyShape::Kind::kSphere ? "sphere" : "cylinder", model.num_nodes(),
                100.0 * fraction, model.mass_scaling_limited() ? " (limited)" : "", unscaled,
                substeps);
    EXPECT_LE(fraction, 0.01 * (1.0 + 1e-9));
    EXPECT_LT(substeps, unscaled);
  }
}

}  // namespace
}  // namespace msm_sim::core
