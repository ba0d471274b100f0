#pragma once

#include <vector>

#include <Eigen/Core>

#include "msm_sim/lattice/lattice_options.h"
#include "msm_sim/material/material.h"
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

/// A box [0, size] filled with a cubic lattice of spacing `lattice.spacing`, optionally rotated
/// about the box centre by `lattice.rotation_angle` (rad) about `lattice.rotation_axis`.
struct CubicLatticeOptions {
  Eigen::Vector3d size = Eigen::Vector3d::Ones();  ///< m, each > 0
  /// Spacing (m, <= the smallest size), spring law, node limit and rotation (LatticeOptions).
  LatticeOptions lattice;
  CubicConstruction construction = CubicConstruction::kNodeCentred;
  /// Node-centred only (NodeCentredSurfaceOptions): surface compensation (see below), face
  /// anchors, the free faces' bending correction (unrotated boxes only: rotated lattices do not
  /// fill a box of cells) and the outer layer's dispersion. The element-corner construction
  /// refuses anchored planes and a surface_dispersion other than 1, and ignores the rest.
  NodeCentredSurfaceOptions surface;
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
/// without NodeCentredSurfaceOptions::free_face_bending (docs/physics.md §2.1, the exact midpoint
/// sums of its springs): (2/3)/n^2 + (1/3)(10/n^2 - 12/n^3), 0.1875 at n = 4, 0.055 at n = 8.
/// Precondition: cells_across >= 1.
double FreeFaceBendingDeficit(int cells_across);

/// The nodes of `model` that lie on `plane` (within 1e-9 of the characteristic length): the
/// anchors a builder put there. Precondition: no lattice node of the model lies on the plane
/// itself (true when the plane is a face of the box and the lattice is not rotated, the nodes
/// being half a cell inside). Precondition: plane.normal != 0.
std::vector<NodeIndex> AnchorNodes(const Model& model, const AnchoredPlane& plane);

}  // namespace msm_sim::core
