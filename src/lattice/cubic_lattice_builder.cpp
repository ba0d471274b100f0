#include "msm_sim/lattice/cubic_lattice_builder.h"

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "lattice/lattice_geometry.h"
#include "lattice/node_centred_lattice.h"
#include "lattice/outer_layer_dispersion.h"
#include "lattice/selective_mass_scaling.h"
#include "msm_sim/material/extended_msm.h"
#include "msm_sim/model/model_builder.h"

namespace msm_sim::core {
namespace {

using namespace lattice;

BoxLattice Box(const CubicLatticeOptions& options) { return BoxOf(options.size, options.lattice); }

ModelBuilder MakeBuilder(const Material& material, const CubicLatticeOptions& options) {
  ModelBuilder builder(material);
  builder.SetSpringLaw(options.lattice.spring_law, options.lattice.power_law);
  builder.SetDispersionFraction(DispersionFraction(material.poisson_ratio()));
  return builder;
}

Model BuildNodeCentred(const Material& material, const CubicLatticeOptions& options) {
  OccupiedCells cells;
  cells.frame = CellFrame(Box(options));
  cells.frame.CoveringRange(options.size, &cells.lo, &cells.hi);
  const double tolerance = 1e-9 * options.lattice.spacing;
  for (int k = cells.lo.z(); k <= cells.hi.z(); ++k) {
    for (int j = cells.lo.y(); j <= cells.hi.y(); ++j) {
      for (int i = cells.lo.x(); i <= cells.hi.x(); ++i) {
        const Eigen::Vector3i c(i, j, k);
        if (!InsideBox(cells.frame.Position(c), options.size, tolerance)) continue;
        CheckNodeBudget(static_cast<long long>(cells.coords.size()) + 1, options.lattice.max_nodes);
        cells.coords.push_back(c);
        cells.fractions.push_back(1.0);
      }
    }
  }
  if (cells.coords.empty()) throw std::invalid_argument("no lattice node falls inside the box");
  return BuildNodeCentredModel(material, cells, options.surface, options.lattice.spring_law,
                               options.lattice.power_law);
}

Model BuildElementCorner(const Material& material, const CubicLatticeOptions& options) {
  const double a = options.lattice.spacing;
  const double kappa = material.shear_modulus() * a;
  const ElementGrid grid = MakeElementGrid(Box(options));
  const int n = static_cast<int>(grid.corners.size());
  std::vector<double> corner_mass(n, 0.0);
  const double corner_share = material.density() * a * a * a / 8.0;
  for (const Eigen::Vector3i& e : grid.elements) {
    for (int delta = 0; delta < 8; ++delta) corner_mass[grid.Corner(e, delta)] += corner_share;
  }

  // Accumulate per (node, half offset) stiffness from every element sharing the spring.
  std::vector<double> stiffness(static_cast<std::size_t>(n) * kNumHalfOffsets, 0.0);
  for (const Eigen::Vector3i& e : grid.elements) {
    for (int p = 0; p < 8; ++p) {
      for (int q = p + 1; q < 8; ++q) {
        const Eigen::Vector3i cp = e + ElementGrid::CornerOffset(p);
        const Eigen::Vector3i cq = e + ElementGrid::CornerOffset(q);
        const Eigen::Vector3i d = cq - cp;
        const int nonzero = (d.array() != 0).count();
        if (nonzero == 3) continue;  // body diagonal: not part of the A+B model
        bool negated = false;
        const int o = HalfOffsetIndex(d, &negated);
        const int from = grid.corner_index.Find(negated ? cq : cp);
        stiffness[from * kNumHalfOffsets + o] += (nonzero == 1 ? 0.25 : 0.5) * kappa;
      }
    }
  }

  ModelBuilder builder = MakeBuilder(material, options);
  for (int node = 0; node < n; ++node) {
    builder.AddNode(grid.corner_frame.Position(grid.corners[node]), corner_mass[node]);
  }
  for (int node = 0; node < n; ++node) {
    for (int o = 0; o < kNumHalfOffsets; ++o) {
      const double k = stiffness[node * kNumHalfOffsets + o];
      if (k <= 0.0) continue;
      const int other = grid.corner_index.Find(grid.corners[node] + kHalfOffsets[o]);
      // A spring shared by fewer elements than in the bulk stands for that fraction of a bulk
      // spring in both end stars: its tension and k already carry the fraction into the inflow
      // and (through w = v k L0^2) into the share of dispersed momentum it receives, so v = 1.
      builder.AddSpring(node, other, k);
    }
  }
  return builder.Build(static_cast<double>(grid.elements.size()) * a * a * a, a);
}

}  // namespace

Model BuildCubicLattice(const Material& material, const CubicLatticeOptions& options) {
  Validate(Box(options));
  lattice::ValidateAnchoredPlanes(options.surface.anchored_planes);
  lattice::ValidateSurfaceDispersion(options.surface.surface_dispersion);
  lattice::ValidateMassScaling(options.surface.mass_scaling);
  if (options.surface.surface_dispersion != 1.0 &&
      options.construction != CubicConstruction::kNodeCentred) {
    throw std::invalid_argument("surface_dispersion needs the node-centred construction");
  }
  if (!options.surface.anchored_planes.empty() &&
      options.construction != CubicConstruction::kNodeCentred) {
    // Element-corner nodes already lie on the surface: freezing them clamps the face.
    throw std::invalid_argument("anchored planes need the node-centred construction");
  }
  return options.construction == CubicConstruction::kNodeCentred
             ? BuildNodeCentred(material, options)
             : BuildElementCorner(material, options);
}

std::vector<NodeIndex> AnchorNodes(const Model& model, const AnchoredPlane& plane) {
  const Eigen::Vector3d n = plane.normal.normalized();
  const double tolerance = 1e-9 * model.characteristic_length();
  std::vector<NodeIndex> nodes;
  const auto& rest = model.rest_positions();
  for (int i = 0; i < rest.cols(); ++i) {
    if (std::abs((rest.col(i) - plane.point).dot(n)) <= tolerance) nodes.push_back(i);
  }
  return nodes;
}

}  // namespace msm_sim::core
