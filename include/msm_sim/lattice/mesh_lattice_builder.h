#pragma once

#include <vector>

#include <Eigen/Core>

#include "msm_sim/geometry/solid_mesh.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/lattice/lattice_options.h"
#include "msm_sim/material/material.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// A node-centred cubic lattice filling the body bounded by a closed mesh.
struct MeshCubicLatticeOptions {
  /// Spacing a (m, <= the smallest bounding-box edge), spring law, node limit, and the lattice's
  /// orientation in the mesh frame (LatticeOptions). The lattice is centred on the bounding box:
  /// a cell centre on its middle along axes with an odd number of cells across, cell faces along
  /// axes with an even number, so that an aligned box of whole cells is tiled exactly.
  LatticeOptions lattice;
  /// docs/physics.md §5 anti-aliasing: each cell's mass and springs scale with the fraction chi of
  /// its volume inside the surface, computed by exact clipping (VolumeInsideBox). Off: a cell is a
  /// full node if its centre is inside, else nothing.
  bool antialias = true;
  /// Cells with chi below this are dropped (thesis: 0.1): arbitrarily light nodes and weak
  /// springs would force a tiny time step.
  double min_fraction = 0.1;
  /// Surface compensation, face anchors (in the solid's frame, unrotated lattices only), the free
  /// faces' bending correction (when the kept cells fill a box of whole cells: a box mesh aligned
  /// with the lattice) and the outer layer's dispersion (the outer layer is the cells missing one
  /// of their 18 neighbours): NodeCentredSurfaceOptions.
  NodeCentredSurfaceOptions surface;
};

/// Builds the calibrated node-centred A+B cubic MSM of the solid (docs/physics.md §2.1, §3 and §5):
/// nodes at the centres of the lattice cells that are (partly) inside, m = rho a^3 chi,
/// k = (mu a / 2)(chi_i + chi_j), eMSM dispersion for the material's nu. The model volume is
/// a^3 sum chi (about the mesh volume, less the dropped slivers).
///
/// Throws std::invalid_argument for a non-positive or non-finite spacing, a spacing larger than
/// the smallest bounding-box edge, min_fraction outside [0, 1), a bad
/// rotation, anchored planes on a rotated lattice or with a non-finite point or zero normal, a
/// surface_dispersion outside (0, 1], no cell inside, or more than max_nodes nodes.
Model BuildCubicLatticeInSolid(const Material& material, const SolidMesh& solid,
                               const MeshCubicLatticeOptions& options);

}  // namespace msm_sim::core
