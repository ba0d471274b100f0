#pragma once

#include <vector>

#include <Eigen/Core>

#include "msm_sim/material/material.h"
#include "msm_sim/material/spring_law.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// How a cubic lattice represents the body (docs/physics.md §2.1, thesis 2.3.2 and 3.2.6).
enum class CubicConstruction {
  /// One node per cell, at the cell centre (0.5 a inside the surface), mass rho a^3, A+B springs
  /// of stiffness kappa = 0.4 E a. Bends correctly at any resolution (preferred).
  kNodeCentred,
  /// Union of cubic elements; each element puts m/8 on its corners, 0.25 kappa on its edges and
  /// 0.5 kappa on its face diagonals, so interior values add up to m and kappa.
  kElementCorner,
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

/// A box [0, size] filled with a cubic lattice of spacing `spacing`, optionally rotated about the
/// box centre by `rotation_angle` (rad) about `rotation_axis`.
struct CubicLatticeOptions {
  Eigen::Vector3d size = Eigen::Vector3d::Ones();  ///< m, each > 0
  double spacing = 0.1;                            ///< m, > 0 and <= the smallest size
  CubicConstruction construction = CubicConstruction::kNodeCentred;
  Eigen::Vector3d rotation_axis = Eigen::Vector3d::UnitZ();  ///< non-zero when angle != 0
  double rotation_angle = 0.0;                               ///< rad
  /// Node-centred only: restore the springs the surface layer misses (see BuildCubicLattice).
  bool compensate_surface = true;
  /// Node-centred only: surface planes held by anchors (see AnchoredPlane). The anchors are added
  /// after the lattice's nodes, on their planes; the caller must freeze them (AnchorNodes): their
  /// mass is a token 1e-6 of a cell's, and a free anchor would make the dynamics stiff.
  std::vector<AnchoredPlane> anchored_planes;
  /// Node-centred only, with compensate_surface: restore the bending stiffness the free faces
  /// miss (docs/physics.md §2.1 "Free faces in bending"): along each axis at least 4 cells
  /// across, the springs lying in the two outer layers are stiffened and those lying in the
  /// interior layers softened so that every layer keeps its summed stiffness (the block's
  /// stiffness tensor is unchanged), and a cantilever 4 or 8 cells across bends as CalculiX's
  /// continuum does instead of too much. The price: a skin stiffer in its own plane, which changes
  /// contacts on coarse lattices, and interior layers softer in theirs, which a block compressed
  /// across them sees through its lateral expansion as a lower E; hence off by default
  /// (docs/design/free-face-bending.md). Applies to unrotated boxes (rotated lattices do not fill
  /// a box of cells).
  bool free_face_bending = false;
  /// Node-centred only: the share of its eMSM bulk (the dispersion, q > 0, nu > 1/4) that the
  /// outer node layer keeps, in (0, 1]; the rest goes to the layer beneath, so that a uniform
  /// strain meets the same summed bulk (docs/physics.md §7 "A softer outer layer"). Near nu = 1/2
  /// the outer layer's one-sided stars set the explicit stable step, which moving bulk inwards
  /// lengthens. The price: the surface is softer in bulk over one cell, which lowers a sphere's
  /// force on a coarse block (a few cells under the contact), and much less where the contact is
  /// resolved (docs/design/surface-dispersion.md). 1 (default): off.
  double surface_dispersion = 1.0;
  SpringLaw spring_law = SpringLaw::kLinear;
  /// Refuse to build more nodes than this: protects against absurd spacings (a static solve needs
  /// several kB per node).
  int max_nodes = 2'000'000;
};

/// Builds a calibrated A+B cubic lattice MSM of the box for `material`, as an extended MSM
/// (docs/physics.md §3): springs kappa = mu a, which alone make a Cauchy solid with the target
/// shear modulus, and dispersion fraction q = Q(nu) / 2 for the rest of the bulk modulus. At nu =
/// 1/4, q = 0 and kappa = 0.4 E a: the plain MSM of docs/physics.md §2.1.
///
/// Node-centred surface compensation: a node on the surface misses the springs to the cells
/// outside the body. Each such spring would have half its length inside the body (the node sits
/// half a cell inside the surface), so the body loses half a spring per missing neighbour; for a
/// block n cells across that is about 2/(3n) of E. For every node i whose neighbour i + d is
/// missing, we add kappa/2 to the collinear spring (i, i - d) on the opposite side of the same
/// node. Under any uniform strain a spring's energy only depends on its direction and k L^2, so
/// this restores exactly the bulk stiffness tensor per node (and thus E and nu of a homogeneously
/// strained block), without adding nodes or springs. A node missing both i + d and i - d (a layer
/// one cell thick) cannot be compensated along d. The eMSM dispersion sees the same picture: the
/// spring (i, i - d) counts twice in node i's star (Model::dispersion_weight_a), so a surface node
/// disperses like a bulk node under a homogeneous strain.
///
/// Throws std::invalid_argument on non-positive or non-finite sizes or spacing, a spacing larger
/// than the smallest box edge, a zero rotation axis, more than max_nodes nodes, or a
/// surface_dispersion outside (0, 1] (or other than 1 with the element-corner construction).
Model BuildCubicLattice(const Material& material, const CubicLatticeOptions& options);

/// The relative bending stiffness a node-centred lattice `cells_across` cells thick misses
/// without CubicLatticeOptions::free_face_bending (docs/physics.md §2.1, the exact midpoint sums
/// of its springs): (2/3)/n^2 + (1/3)(10/n^2 - 12/n^3), 0.1875 at n = 4, 0.055 at n = 8.
/// Precondition: cells_across >= 1.
double FreeFaceBendingDeficit(int cells_across);

/// The nodes of `model` that lie on `plane` (within 1e-9 of the characteristic length): the
/// anchors a builder put there. Precondition: no lattice node of the model lies on the plane
/// itself (true when the plane is a face of the box and the lattice is not rotated, the nodes
/// being half a cell inside). Precondition: plane.normal != 0.
std::vector<NodeIndex> AnchorNodes(const Model& model, const AnchoredPlane& plane);

}  // namespace msm_sim::core
