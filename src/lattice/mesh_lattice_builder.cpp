#include "msm_sim/lattice/mesh_lattice_builder.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "geometry/box_clipping.h"
#include "lattice/lattice_geometry.h"
#include "lattice/node_centred_lattice.h"
#include "lattice/outer_layer_dispersion.h"
#include "lattice/selective_mass_scaling.h"

namespace msm_sim::core {
namespace {

using namespace lattice;

void Validate(const SolidMesh& solid, const MeshCubicLatticeOptions& options) {
  ValidateSizeAndSpacing(solid.max_corner() - solid.min_corner(), options.lattice.spacing);
  Validate(BoxOf(solid.max_corner() - solid.min_corner(), options.lattice));
  lattice::ValidateAnchoredPlanes(options.surface.anchored_planes);
  lattice::ValidateSurfaceDispersion(options.surface.surface_dispersion);
  lattice::ValidateMassScaling(options.surface.mass_scaling);
  if (!options.surface.anchored_planes.empty() && options.lattice.rotation_angle != 0.0) {
    throw std::invalid_argument("anchored planes need a lattice aligned with the solid's frame");
  }
  if (!(options.min_fraction >= 0.0 && options.min_fraction < 1.0)) {
    throw std::invalid_argument("minimum cell fraction must lie in [0, 1), got " +
                                std::to_string(options.min_fraction));
  }
}

// The integer cell coordinates [lo, hi] (inclusive) and the flat index of each in a dense
// per-cell array, x fastest.
struct CellRange {
  CellRange(const Eigen::Vector3i& lo_in, const Eigen::Vector3i& hi_in)
      : lo(lo_in), hi(hi_in), extent(hi_in - lo_in + Eigen::Vector3i::Ones()) {}

  std::size_t num_cells() const { return static_cast<std::size_t>(extent.cast<double>().prod()); }
  std::size_t Flat(const Eigen::Vector3i& c) const {
    const Eigen::Vector3i r = c - lo;
    return (static_cast<std::size_t>(r.z()) * extent.y() + r.y()) * extent.x() + r.x();
  }
  bool Contains(const Eigen::Vector3i& c) const {
    return (c.array() >= lo.array()).all() && (c.array() <= hi.array()).all();
  }
  // Calls visit(c) for every cell, x fastest.
  template <typename Visit>
  void ForEachCell(Visit visit) const {
    for (int k = lo.z(); k <= hi.z(); ++k) {
      for (int j = lo.y(); j <= hi.y(); ++j) {
        for (int i = lo.x(); i <= hi.x(); ++i) visit(Eigen::Vector3i(i, j, k));
      }
    }
  }

  Eigen::Vector3i lo, hi, extent;
};

Eigen::Matrix3d LatticeRotation(const MeshCubicLatticeOptions& options) {
  return options.lattice.rotation_angle == 0.0
             ? Eigen::Matrix3d::Identity()
             : Eigen::AngleAxisd(options.lattice.rotation_angle,
                                 options.lattice.rotation_axis.normalized())
                   .toRotationMatrix();
}

// As for boxes (CellFrame): with an even number of cells across an axis, put cell faces, not
// a cell centre, on the middle, so that a lattice-aligned box of a whole number of cells is
// tiled exactly. `local` is the mesh in the lattice frame.
Eigen::Vector3d CentringOffset(const SolidMesh& local, double a) {
  Eigen::Vector3d offset;
  for (int axis = 0; axis < 3; ++axis) {
    const double across = (local.max_corner()[axis] - local.min_corner()[axis]) / a;
    offset[axis] = std::lround(across) % 2 == 0 ? 0.5 : 0.0;
  }
  return offset;
}

// The fraction chi of every cell of `range` inside `local` (the mesh in the lattice frame): the
// clipped volume with anti-aliasing, else 1 or 0 as the cell centre falls inside or not.
std::vector<double> CellFractions(const SolidMesh& local, const LatticeFrame& frame,
                                  const CellRange& range, bool antialias) {
  const double a = frame.unit;
  const Eigen::Vector3d half = Eigen::Vector3d::Constant(0.5 * a);
  std::vector<double> fraction(range.num_cells(), 0.0);
  range.ForEachCell([&](const Eigen::Vector3i& c) {
    const Eigen::Vector3d centre = a * (c.cast<double>() + frame.offset);
    double& chi = fraction[range.Flat(c)];
    if (antialias) {
      chi = VolumeInsideBox(local, centre - half, centre + half) / (a * a * a);
    } else {
      chi = local.Contains(centre) ? 1.0 : 0.0;  // the centre decides
    }
  });
  return fraction;
}

// Whether a cell of fraction chi becomes a node.
bool Kept(double chi, double min_fraction) { return chi > 0.0 && chi >= min_fraction; }

// Adds the sliver chi of dropped cell c to the kept cells of its 26-neighbourhood, in proportion
// to their fractions: a first pass sums them, a second shares chi out. An isolated sliver has
// nothing to give it to and is lost.
void GiveSliverToNeighbours(const Eigen::Vector3i& c, double chi, const CellRange& range,
                            const std::vector<double>& fraction, double min_fraction,
                            std::vector<double>* absorbed) {
  double total = 0.0;
  for (int pass = 0; pass < 2; ++pass) {
    for (int d = 0; d < 27; ++d) {
      const Eigen::Vector3i n = c + Eigen::Vector3i(d % 3 - 1, (d / 3) % 3 - 1, d / 9 - 1);
      if (d == 13 || !range.Contains(n) || !Kept(fraction[range.Flat(n)], min_fraction)) continue;
      if (pass == 0) {
        total += fraction[range.Flat(n)];
      } else {
        (*absorbed)[range.Flat(n)] += chi * fraction[range.Flat(n)] / total;
      }
    }
    if (total <= 0.0) break;  // an isolated sliver: nothing to give it to
  }
}

// A dropped sliver's volume goes to the kept cells around it (26-neighbourhood, in proportion
// to their fractions), so the model keeps the body's mass, however the lattice falls
// (docs/meshes.md). A border cell may end up with chi > 1. Returns the volume fraction each cell
// absorbs.
std::vector<double> AbsorbedSlivers(const CellRange& range, const std::vector<double>& fraction,
                                    double min_fraction) {
  std::vector<double> absorbed(fraction.size(), 0.0);
  range.ForEachCell([&](const Eigen::Vector3i& c) {
    const double chi = fraction[range.Flat(c)];
    if (chi <= 0.0 || Kept(chi, min_fraction)) return;
    GiveSliverToNeighbours(c, chi, range, fraction, min_fraction, &absorbed);
  });
  return absorbed;
}

// How far the surface of `local` lies inside the outer face of the cell centred at `centre`
// (docs/physics.md §7): a / 2 less the centre's signed depth below the surface (negative
// outside), measured to the nearest surface point whatever the surface's slope; 0 where the
// centre lies half a cell or more inside.
double SurfaceInset(const SolidMesh& local, const Eigen::Vector3d& centre, double a) {
  const double distance = (local.ClosestPoint(centre, nullptr) - centre).norm();
  const double depth = local.Contains(centre) ? distance : -distance;
  return std::max(0.0, 0.5 * a - depth);
}

// Appends every kept cell to cells->coords with its fraction plus what it absorbed, and the
// surface inset of each cell the surface cuts (chi < 1 before absorbing). Throws
// std::invalid_argument past the node budget.
void CollectKeptCells(const SolidMesh& local, const CellRange& range,
                      const std::vector<double>& fraction, const std::vector<double>& absorbed,
                      const MeshCubicLatticeOptions& options, OccupiedCells* cells) {
  const double a = cells->frame.unit;
  range.ForEachCell([&](const Eigen::Vector3i& c) {
    const double chi = fraction[range.Flat(c)];
    if (!Kept(chi, options.min_fraction)) return;
    CheckNodeBudget(static_cast<long long>(cells->coords.size()) + 1, options.lattice.max_nodes);
    cells->coords.push_back(c);
    cells->fractions.push_back(chi + absorbed[range.Flat(c)]);
    const Eigen::Vector3d centre = a * (c.cast<double>() + cells->frame.offset);
    cells->insets.push_back(chi < 1.0 ? SurfaceInset(local, centre, a) : 0.0);
  });
}

OccupiedCells OccupiedCellsOf(const SolidMesh& solid, const MeshCubicLatticeOptions& options) {
  const double a = options.lattice.spacing;
  OccupiedCells cells;
  cells.frame.rotation = LatticeRotation(options);
  cells.frame.centre = 0.5 * (solid.min_corner() + solid.max_corner());
  cells.frame.unit = a;
  // Work in the lattice frame, where cells are axis-aligned boxes the AABB tree can test.
  const Eigen::Matrix3d to_lattice = cells.frame.rotation.transpose();
  const SolidMesh local = TransformedSolid(solid, to_lattice, -to_lattice * cells.frame.centre);
  cells.frame.offset = CentringOffset(local, a);
  cells.lo = (local.min_corner() / a - cells.frame.offset).array().floor().cast<int>() - 1;
  cells.hi = (local.max_corner() / a - cells.frame.offset).array().ceil().cast<int>() + 1;
  const CellRange range(cells.lo, cells.hi);
  const std::vector<double> fraction = CellFractions(local, cells.frame, range, options.antialias);
  const std::vector<double> absorbed = AbsorbedSlivers(range, fraction, options.min_fraction);
  CollectKeptCells(local, range, fraction, absorbed, options, &cells);
  if (cells.coords.empty()) {
    throw std::invalid_argument("no lattice cell of spacing " + std::to_string(a) +
                                " m is inside the mesh; use a smaller spacing");
  }
  return cells;
}

}  // namespace

Model BuildCubicLatticeInSolid(const Material& material, const SolidMesh& solid,
                               const MeshCubicLatticeOptions& options) {
  Validate(solid, options);
  return BuildNodeCentredModel(material, OccupiedCellsOf(solid, options), options.surface,
                               options.lattice.spring_law, options.lattice.power_law);
}

}  // namespace msm_sim::core
