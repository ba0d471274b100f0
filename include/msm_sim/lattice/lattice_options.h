#pragma once
// The options the lattice builders share. Each builder's options embed them (`lattice`, and
// for the node-centred cubic builders `surface`), and so do a BodyRecipe and the node's object
// configuration, so that a front end's choice reaches the builder in one assignment.

#include <vector>

#include <Eigen/Core>

#include "msm_sim/material/power_spring_law.h"
#include "msm_sim/material/spring_law.h"

namespace msm_sim::core {

/// Options every lattice builder reads (BuildCubicLattice, BuildCubicLatticeInSolid,
/// BuildRandomLattice, BuildRandomLatticeInSolid, BuildBaudetLattice).
struct LatticeOptions {
  /// m, > 0 and at most the smallest box (or bounding-box) edge: the cubic lattice's spacing a,
  /// Baudet's brick edge a, or the random lattice's characteristic spacing l (the target node
  /// count is then N = V / l^3).
  double spacing = 0.1;
  SpringLaw spring_law = SpringLaw::kLinear;
  /// The law's alpha and beta when spring_law is kPower (docs/physics.md §4.1); else unread.
  PowerSpringLaw power_law;
  /// Refuse to build more nodes than this: protects against absurd spacings (a static solve needs
  /// several kB per node).
  int max_nodes = 2'000'000;
  /// Cubic and Baudet lattices: rotated by rotation_angle (rad) about rotation_axis (non-zero when
  /// the angle is not 0), about the box centre (box builders) or, in a solid, as the lattice's
  /// orientation in the solid's frame (BuildCubicLatticeInSolid). Default: no rotation. A random
  /// lattice has no orientation: its builders ignore both.
  Eigen::Vector3d rotation_axis = Eigen::Vector3d::UnitZ();
  double rotation_angle = 0.0;  ///< rad
};

/// A plane of the body's surface that a clamp holds fixed (docs/physics.md §2.1 "Face anchors"):
/// the body lies behind it, (x - point) . normal <= 0. Node-centred lattices put their outer
/// nodes half a cell inside the surface; a node whose neighbour across this plane is missing gets,
/// instead of the mirrored half-spring, an anchor: a fixed node where the missing spring meets the
/// plane, joined by the part of that spring inside the body. Freezing the anchors (and only them)
/// then clamps the surface itself, as a finite-element model clamps a face.
struct AnchoredPlane {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();     ///< m, any point of the plane
  Eigen::Vector3d normal = -Eigen::Vector3d::UnitX();  ///< outward; non-zero
};

/// How the node-centred cubic builders (BuildCubicLattice with CubicConstruction::kNodeCentred,
/// BuildCubicLatticeInSolid) treat the body's surface. The other lattices have their own surface
/// and take none of this.
struct NodeCentredSurfaceOptions {
  /// Restore the springs the surface layer misses: the missing half-springs of surface cells are
  /// mirrored onto the opposite spring of the same node (see BuildCubicLattice).
  bool compensate_surface = true;
  /// Surface planes held by anchors (see AnchoredPlane), in the builder's frame (the box's
  /// [0, size], the solid's frame). The anchors are added after the lattice's nodes, on their
  /// planes; the caller must freeze them (AnchorNodes): their mass is a token 1e-6 of a cell's,
  /// and a free anchor would make the dynamics stiff. Unrotated lattices only. In a solid, every
  /// missing neighbour whose segment leaves the body through a plane gets an anchor where it
  /// crosses; for a plane on a face of a box-shaped solid aligned with the lattice, whole cells
  /// along its normal (the nodes half a cell inside) give the box builder's anchors.
  std::vector<AnchoredPlane> anchored_planes;
  /// With compensate_surface: restore the bending stiffness the free faces miss
  /// (docs/physics.md §2.1 "Free faces in bending"): along each axis at least 4 cells across,
  /// the springs lying in the two outer layers are stiffened and those lying in the interior
  /// layers softened so that every layer keeps its summed stiffness (the block's stiffness tensor
  /// is unchanged), and a cantilever 4 or 8 cells across bends as CalculiX's continuum does
  /// instead of too much. The price: a skin stiffer in its own plane, which changes contacts on
  /// coarse lattices, and interior layers softer in theirs, which a block compressed across them
  /// sees through its lateral expansion as a lower E; hence off by default
  /// (docs/design/free-face-bending.md). Applies only when the lattice's cells fill a box of
  /// whole cells (an unrotated box, or a box mesh aligned with the lattice).
  bool free_face_bending = false;
  /// The share of its eMSM bulk (the dispersion, q > 0, nu > 1/4) that the outer node layer (the
  /// cells missing one of their 18 neighbours) keeps, in (0, 1]; the rest goes to the layer
  /// beneath, so that a uniform strain meets the same summed bulk (docs/physics.md §7 "A softer
  /// outer layer"). Near nu = 1/2 the outer layer's one-sided stars set the explicit stable step,
  /// which moving bulk inwards lengthens. The price: the surface is softer in bulk over one cell,
  /// which lowers a sphere's force on a coarse block (a few cells under the contact), and much
  /// less where the contact is resolved (docs/design/surface-dispersion.md). 1 (default): off.
  double surface_dispersion = 1.0;
  /// Selective mass scaling (docs/physics.md §7 "Selective mass scaling"): the most mass, as a
  /// fraction of the body's, that may be added to the nodes of cells the surface cuts (chi < 1)
  /// whose local stable step is shorter than a full interior cell's, each up to that cell's
  /// figure, so that cut cells do not set the explicit step. In [0, 0.1]; 0: off. Boxes of whole
  /// cells have no cut cells and are unchanged. The mass added is Model::added_mass.
  double mass_scaling = 0.01;
};

}  // namespace msm_sim::core
