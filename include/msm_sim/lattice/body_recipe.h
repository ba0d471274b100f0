#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "msm_sim/geometry/solid_mesh.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/lattice/lattice_options.h"
#include "msm_sim/lattice/random_lattice_builder.h"
#include "msm_sim/material/material.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// The lattices a body can be built from (docs/physics.md §2, thesis 2.3): the cubic A+B lattice
/// (BuildCubicLattice, BuildCubicLatticeInSolid), the random lattice (BuildRandomLattice,
/// BuildRandomLatticeInSolid) and Baudet's bricks (BuildBaudetLattice).
enum class LatticeKind { kCubic, kRandom, kBaudet };

/// Parses "cubic" / "random" / "baudet"; returns false (and leaves *kind) for anything else.
bool ParseLatticeKind(const std::string& name, LatticeKind* kind);

/// The name ParseLatticeKind reads back: "cubic", "random" or "baudet".
const char* LatticeKindName(LatticeKind kind);

/// Every name ParseLatticeKind accepts, in declaration order: cubic, random, baudet. Command
/// lines and configurations validate against this list.
const std::vector<std::string>& LatticeKindNames();

/// The most nodes a recipe may ask for: a target_nodes above it, or a spacing that gives more
/// lattice sites than this in the region's bounding box, is refused before anything is allocated
/// (what a model at the limit costs to build: docs/robustness.md).
inline constexpr int kMaxBodyNodes = 2'000'000;

/// Everything that makes a calibrated model of a body: the material, the region it fills and the
/// lattice that fills it. One recipe, built by BuildModel, serves every front end (the node's
/// objects, the lab's bodies), so that a body is built the same way whoever asks.
///
/// The region is the closed `solid` if one is given, else the box [0, box_size]. Fields a lattice
/// does not use are ignored (each says which lattice reads it).
struct BodyRecipe {
  explicit BodyRecipe(const Material& body_material) : material(body_material) {}

  /// What the springs are calibrated for (E, nu, rho).
  Material material;

  // --- Region ------------------------------------------------------------------------------
  /// Non-null: the body is this closed solid, in its own frame (cubic: node-centred, lattice
  /// centred on its bounding box; random). Baudet bricks and element-corner cubic lattices fill
  /// boxes only. Null (default): the body is the box [0, box_size].
  std::shared_ptr<const SolidMesh> solid;
  /// Box region: edge lengths (m), each > 0. Default 1 m each. Ignored with a solid.
  Eigen::Vector3d box_size = Eigen::Vector3d::Ones();
  /// Box region: move the built model by -box_size / 2, so that the box is centred on the origin
  /// like the primitives of BodyShape. Default false (the box starts at the origin). Must be
  /// false with a solid.
  bool centre_box = false;

  // --- Lattice -------------------------------------------------------------------------------
  /// Which lattice fills the region. Default cubic.
  LatticeKind lattice_kind = LatticeKind::kCubic;
  /// All lattices: the spacing (the lattice spacing a of cubic lattices, the brick edge of
  /// Baudet's, the characteristic spacing l of random ones; ignored when target_nodes > 0), the
  /// springs' tension law and the node limit. Cubic and Baudet: the rotation, about the box centre
  /// (box) or the bounding-box centre (solid). Handed to the builder as is (LatticeOptions, whose
  /// defaults are the recipe's: 0.1 m, linear, kMaxBodyNodes, no rotation).
  LatticeOptions lattice;
  /// All lattices: > 0 chooses the spacing for about this many nodes instead,
  /// spacing = cbrt(V / target_nodes), V as below. Default 0 (use `lattice.spacing`); >= 0.
  int target_nodes = 0;
  /// The volume V that target_nodes divides (m^3), >= 0. Default 0: the region's own volume
  /// (the solid's, or box_size.prod()). A front end that fills a box but knows the body as a
  /// solid passes the solid's volume here.
  double target_volume = 0.0;
  /// Cubic: node-centred (default) or element-corner; a solid takes node-centred only.
  CubicConstruction construction = CubicConstruction::kNodeCentred;
  /// Node-centred cubic in a solid, or in a box whose lattice is rotated (built through the box
  /// as a solid): docs/physics.md §5 anti-aliasing (cells weighted by the fraction inside the
  /// surface). Default on.
  bool antialias = true;
  /// Node-centred cubic: the surface options, handed to the builder as is
  /// (NodeCentredSurfaceOptions). Anchored planes need a lattice aligned with the body (not
  /// rotated), in a box or a solid, and lie in the region's frame (a box's [0, box_size];
  /// centre_box then moves the anchors with the body). The free faces' bending correction applies
  /// when the lattice's cells fill a box (an unrotated box, or a box-shaped solid aligned with the
  /// lattice). Anchored planes, the bending correction and a surface_dispersion other than 1 are
  /// refused for other lattices, which ignore compensate_surface. Defaults:
  /// NodeCentredSurfaceOptions's.
  NodeCentredSurfaceOptions surface;
  /// Random: the random sequential addition's seed; same seed, same model. Default 1.
  std::uint64_t seed = 1;
  /// Random: minL and maxL as multiples of l, 0 < min < max. Defaults 0.8 and 1.9 (what both
  /// front ends use; the builder's own default maxL is 1.7).
  double random_min_distance = 0.8;
  double random_max_distance = 1.9;
  /// Random: how stiffness varies with rest length. Default inverse-square.
  RandomStiffnessLaw stiffness_law = RandomStiffnessLaw::kInverseSquare;
  /// Random: correct k and q by a virtual measurement of a representative block
  /// (RandomLatticeOptions::self_calibrate, docs/physics.md §2.2). Default off.
  bool random_self_calibrate = false;
  /// Random with random_self_calibrate: a self-calibration measured before (Model::
  /// self_calibration of a model built or loaded earlier). Applied without measuring when it was
  /// measured for this recipe's conditions (RandomSelfCalibrationConditions); otherwise ignored
  /// and the recipe measures its own. Default none.
  std::optional<RandomSelfCalibration> random_calibration;
};

/// The spacing BuildModel uses: `lattice.spacing`, or with target_nodes > 0 cbrt(V / target_nodes)
/// for the volume V that target_nodes divides (target_volume, else the region's own). Not
/// validated.
double RecipeSpacing(const BodyRecipe& recipe);

/// Builds the recipe's model: the lattice's builder with the recipe's options, in the region's
/// frame (moved by -box_size / 2 with centre_box).
///
/// Throws std::invalid_argument for a combination no builder takes (a solid with Baudet bricks or
/// an element-corner lattice, centre_box with a solid, a negative target_nodes or target_volume,
/// more nodes than kMaxBodyNodes: target_nodes above it or a spacing giving more lattice sites),
/// and whatever the builder throws for bad geometry or options (std::invalid_argument), or
/// std::runtime_error when random sequential addition cannot place the nodes.
Model BuildModel(const BodyRecipe& recipe);

}  // namespace msm_sim::core
