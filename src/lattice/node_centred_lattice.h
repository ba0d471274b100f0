#pragma once
// Private to msm_sim's lattice builders: the node-centred A+B cubic MSM of a set of occupied
// lattice cells, shared by the box builder (every cell full) and the mesh builder (cells partly
// inside the surface, docs/physics.md §5 anti-aliasing).

#include <vector>

#include <Eigen/Core>

#include "lattice/lattice_geometry.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/material/material.h"
#include "msm_sim/material/power_spring_law.h"
#include "msm_sim/material/spring_law.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core::lattice {

/// Cells of a cubic lattice that become nodes, with the fraction of each cell's volume inside
/// the body (1 for a full cell).
struct OccupiedCells {
  LatticeFrame frame;      ///< maps integer cell coordinates to cell centres
  Eigen::Vector3i lo, hi;  ///< integer range covering every coordinate below
  std::vector<Eigen::Vector3i> coords;
  std::vector<double> fractions;  ///< chi in (0, 1], same order as coords
  /// Per coord (m, >= 0), Model::surface_insets: a / 2 less the cell centre's signed depth below
  /// the body's surface for a cell the surface cuts, 0 for a whole cell (docs/physics.md §7).
  /// Empty: (1 - chi) a for chi < 1, the flat-cut estimate.
  std::vector<double> insets;
};

/// Throws std::invalid_argument for an anchored plane with a non-finite point or normal, or a
/// zero normal.
void ValidateAnchoredPlanes(const std::vector<AnchoredPlane>& anchored);

/// Builds the calibrated node-centred model: a node at each cell centre with mass rho a^3 chi,
/// A+B springs k = (kappa / 2)(chi_i + chi_j) with kappa = mu a (each end cell contributes the
/// half of the spring that lies in it, weighted by how much of that cell is body), eMSM
/// dispersion fraction q(nu), springs of `spring_law` (its alpha, beta from `power_law`), and, if
/// surface.compensate_surface, the missing half-springs of surface cells mirrored onto the opposite
/// spring of the same node (see BuildCubicLattice). The model volume is a^3 sum chi. A missing
/// neighbour across one of surface.anchored_planes (positions in the frame's coordinates) gets a
/// face anchor instead of the mirrored half-spring (AnchoredPlane, docs/physics.md §2.1 "Face
/// anchors"), whether or not compensate_surface is set. With free_face_bending and
/// compensate_surface, cells that fill a box (all full) get FreeFaceBending's stiffness factors on
/// their springs and face anchors, and dispersion weights divided by the same factors so that the
/// eMSM dispersion (which weighs v k) is unchanged. The outer node layer (the cells missing one of
/// their 18 neighbours) keeps surface_dispersion of its eMSM bulk, the rest moved onto the layer
/// beneath (ShiftOuterLayerDispersion), where the dispersion adds bulk (q > 0). Precondition:
/// coords non-empty and unique, fractions in (0, 1], anchored normals non-zero, surface_dispersion
/// in (0, 1].
Model BuildNodeCentredModel(const Material& material, const OccupiedCells& cells,
                            const NodeCentredSurfaceOptions& surface, SpringLaw spring_law,
                            const PowerSpringLaw& power_law);

}  // namespace msm_sim::core::lattice
