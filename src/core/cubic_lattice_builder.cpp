#include "msm_sim/core/cubic_lattice_builder.h"

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "lattice_geometry.h"
#include "msm_sim/core/extended_msm.h"
#include "msm_sim/core/model_builder.h"

namespace msm_sim::core {
namespace {

using namespace lattice;

BoxLattice Box(const CubicLatticeOptions& options) {
  return {options.size, options.spacing, options.rotation_axis, options.rotation_angle,
          options.max_nodes};
}

ModelBuilder MakeBuilder(const Material& material, const CubicLatticeOptions& options) {
  ModelBuilder builder(material);
  builder.SetSpringLaw(options.spring_law);
  builder.SetDispersionFraction(DispersionFraction(material.poisson_ratio()));
  return builder;
}

Model BuildNodeCentred(const Material& material, const CubicLatticeOptions& options) {
  const double a = options.spacing;
  const double kappa = material.shear_modulus() * a;
  const double node_mass = material.density() * a * a * a;
  const LatticeFrame frame = CellFrame(Box(options));
  Eigen::Vector3i lo, hi;
  frame.CoveringRange(options.size, &lo, &hi);
  LatticeIndex index(lo, hi);

  ModelBuilder builder = MakeBuilder(material, options);
  std::vector<Eigen::Vector3i> coords;
  const double tolerance = 1e-9 * a;
  for (int k = lo.z(); k <= hi.z(); ++k) {
    for (int j = lo.y(); j <= hi.y(); ++j) {
      for (int i = lo.x(); i <= hi.x(); ++i) {
        const Eigen::Vector3i c(i, j, k);
        const Eigen::Vector3d p = frame.Position(c);
        if (!InsideBox(p, options.size, tolerance)) continue;
        CheckNodeBudget(static_cast<long long>(coords.size()) + 1, options.max_nodes);
        index.At(c) = builder.AddNode(p, node_mass);
        coords.push_back(c);
      }
    }
  }
  if (coords.empty()) throw std::invalid_argument("no lattice node falls inside the box");

  const int n = static_cast<int>(coords.size());
  std::vector<SpringIndex> spring_of(static_cast<std::size_t>(n) * kNumHalfOffsets, -1);
  for (int node = 0; node < n; ++node) {
    for (int o = 0; o < kNumHalfOffsets; ++o) {
      const int other = index.Find(coords[node] + kHalfOffsets[o]);
      if (other >= 0) spring_of[node * kNumHalfOffsets + o] = builder.AddSpring(node, other, kappa);
    }
  }

  if (options.compensate_surface) {
    // Missing neighbours mirrored onto each spring end (a, b); see BuildCubicLattice.
    std::vector<int> mirrored(2 * static_cast<std::size_t>(builder.num_springs()), 0);
    for (int node = 0; node < n; ++node) {
      for (int o = 0; o < kNumHalfOffsets; ++o) {
        for (const int sign : {1, -1}) {
          const Eigen::Vector3i d = sign * kHalfOffsets[o];
          if (index.Find(coords[node] + d) >= 0) continue;  // neighbour present
          const int opposite = index.Find(coords[node] - d);
          if (opposite < 0) continue;  // one cell thick along d: nothing to carry it
          // Spring (node, node - d): stored at the endpoint from which it points along +offset.
          const SpringIndex s = sign > 0 ? spring_of[opposite * kNumHalfOffsets + o]
                                         : spring_of[node * kNumHalfOffsets + o];
          builder.AddStiffness(s, 0.5 * kappa);
          mirrored[2 * s + (builder.spring_node_a(s) == node ? 0 : 1)] += 1;
        }
      }
    }
    // In node i's star the spring (i, i - d) stands for itself and for each mirrored neighbour
    // (m copies at end i). Its tension k dL, with k = kappa (m_a + m_b) / 2, is shared by the
    // ends in proportion: weight v = 2 m / (m_a + m_b), so each end counts its own copies at the
    // nominal kappa dL (and receives m copies' share of the dispersion, w = v k L0^2).
    for (SpringIndex s = 0; s < builder.num_springs(); ++s) {
      const double ma = 1.0 + mirrored[2 * s];
      const double mb = 1.0 + mirrored[2 * s + 1];
      builder.SetDispersionWeight(s, builder.spring_node_a(s), 2.0 * ma / (ma + mb));
      builder.SetDispersionWeight(s, builder.spring_node_b(s), 2.0 * mb / (ma + mb));
    }
  }
  return builder.Build(n * a * a * a, a);
}

Model BuildElementCorner(const Material& material, const CubicLatticeOptions& options) {
  const double a = options.spacing;
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
  return options.construction == CubicConstruction::kNodeCentred
             ? BuildNodeCentred(material, options)
             : BuildElementCorner(material, options);
}

}  // namespace msm_sim::core
