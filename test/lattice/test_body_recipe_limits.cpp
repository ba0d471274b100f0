// The body recipe's spacing chosen from a node count, and the recipes it refuses: combinations no
// builder takes, the builders' own errors, and more nodes than the limit.
#include <cmath>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "body_recipe_checks.h"
#include "msm_sim/lattice/baudet_lattice_builder.h"
#include "msm_sim/lattice/body_recipe.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/lattice/mesh_lattice_builder.h"

namespace msm_sim::core {
namespace {

// --- Spacing from a node count --------------------------------------------------------------

TEST(BodyRecipe, TargetNodesChooseTheSpacingFromTheVolume) {
  // A box: V = size.prod().
  BodyRecipe box(kMaterial);
  box.box_size = kBox;
  box.lattice.spacing = 123.0;  // ignored
  box.target_nodes = 500;
  const double box_spacing = std::cbrt(kBox.prod() / 500);
  CubicLatticeOptions options;
  options.size = kBox;
  options.lattice.spacing = box_spacing;
  const Model model = BuildModel(box);
  EXPECT_EQ(model.characteristic_length(), box_spacing);
  ExpectSameModel(model, BuildCubicLattice(kMaterial, options));

  // A solid: V = its volume.
  BodyRecipe solid(kMaterial);
  solid.solid = BoxSolid(kBox);
  solid.target_nodes = 400;
  MeshCubicLatticeOptions mesh_options;
  mesh_options.lattice.spacing = std::cbrt(solid.solid->volume() / 400);
  ExpectSameModel(BuildModel(solid),
                  BuildCubicLatticeInSolid(kMaterial, *solid.solid, mesh_options));

  // An explicit volume overrides the region's.
  BodyRecipe baudet(kMaterial);
  baudet.lattice_kind = LatticeKind::kBaudet;
  baudet.box_size = kBox;
  baudet.target_nodes = 300;
  baudet.target_volume = 0.8 * kBox.prod();
  BaudetLatticeOptions baudet_options;
  baudet_options.size = kBox;
  baudet_options.lattice.spacing = std::cbrt(0.8 * kBox.prod() / 300);
  ExpectSameModel(BuildModel(baudet), BuildBaudetLattice(kMaterial, baudet_options));
}

// --- Invalid recipes ------------------------------------------------------------------------

void ExpectInvalid(const BodyRecipe& recipe, const std::string& mentions) {
  try {
    BuildModel(recipe);
    ADD_FAILURE() << "no exception; expected one mentioning " << mentions;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(mentions), std::string::npos) << e.what();
  }
}

TEST(BodyRecipe, RejectsCombinationsNoBuilderTakes) {
  BodyRecipe baudet_in_solid(kMaterial);
  baudet_in_solid.lattice_kind = LatticeKind::kBaudet;
  baudet_in_solid.solid = BoxSolid(kBox);
  ExpectInvalid(baudet_in_solid, "boxes only");

  BodyRecipe corner_in_solid(kMaterial);
  corner_in_solid.solid = BoxSolid(kBox);
  corner_in_solid.construction = CubicConstruction::kElementCorner;
  ExpectInvalid(corner_in_solid, "node-centred cubic or random lattices");

  BodyRecipe centred_solid(kMaterial);
  centred_solid.solid = BoxSolid(kBox);
  centred_solid.centre_box = true;
  ExpectInvalid(centred_solid, "centre_box");

  BodyRecipe random_bending(kMaterial);
  random_bending.box_size = kBox;
  random_bending.lattice_kind = LatticeKind::kRandom;
  random_bending.surface.free_face_bending = true;
  ExpectInvalid(random_bending, "bending correction is for node-centred cubic lattices");

  BodyRecipe random_softer(kMaterial);
  random_softer.box_size = kBox;
  random_softer.lattice_kind = LatticeKind::kRandom;
  random_softer.surface.surface_dispersion = 0.5;
  ExpectInvalid(random_softer, "surface_dispersion is for node-centred cubic lattices");

  BodyRecipe negative_count(kMaterial);
  negative_count.box_size = kBox;
  negative_count.target_nodes = -5;
  ExpectInvalid(negative_count, "target_nodes");

  BodyRecipe negative_volume(kMaterial);
  negative_volume.box_size = kBox;
  negative_volume.target_nodes = 10;
  negative_volume.target_volume = -1.0;
  ExpectInvalid(negative_volume, "target_volume");
}

TEST(BodyRecipe, PassesOnTheBuildersErrors) {
  BodyRecipe too_coarse(kMaterial);
  too_coarse.box_size = kBox;
  too_coarse.lattice.spacing = 1.0;
  EXPECT_THROW(BuildModel(too_coarse), std::invalid_argument);
  too_coarse.lattice_kind = LatticeKind::kBaudet;
  EXPECT_THROW(BuildModel(too_coarse), std::invalid_argument);
  too_coarse.lattice_kind = LatticeKind::kRandom;
  EXPECT_THROW(BuildModel(too_coarse), std::invalid_argument);

  BodyRecipe crowded(kMaterial);
  crowded.lattice_kind = LatticeKind::kRandom;
  crowded.box_size = kBox;
  crowded.lattice.spacing = 0.1;
  crowded.random_min_distance = 1.4;
  crowded.random_max_distance = 2.0;
  EXPECT_THROW(BuildModel(crowded), std::runtime_error);
}

// Absurd node counts are refused from the recipe alone: a builder asked for 10^17 nodes would
// exhaust memory (or take hours) instead of throwing.
TEST(BodyRecipe, RefusesMoreNodesThanTheLimitBeforeBuilding) {
  for (const LatticeKind kind : {LatticeKind::kCubic, LatticeKind::kRandom, LatticeKind::kBaudet}) {
    for (const bool in_solid : {false, true}) {
      if (in_solid && kind == LatticeKind::kBaudet) continue;  // Baudet fills boxes only
      BodyRecipe recipe(kMaterial);
      recipe.lattice_kind = kind;
      recipe.box_size = kBox;
      if (in_solid) recipe.solid = BoxSolid(kBox);
      recipe.lattice.spacing = 1e-6;
      try {
        BuildModel(recipe);
        ADD_FAILURE() << LatticeKindName(kind) << " built 10^17 nodes";
      } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("spacing 1e-06 m gives about 7.20005e+16"),
                  std::string::npos)
            << e.what();
      }
      recipe.target_nodes = kMaxBodyNodes + 1;
      EXPECT_THROW(BuildModel(recipe), std::invalid_argument) << LatticeKindName(kind);
    }
  }
}

}  // namespace
}  // namespace msm_sim::core
