#include "msm_sim/build/baudet_lattice_builder.h"

#include <array>
#include <vector>

#include "build/lattice_geometry.h"
#include "msm_sim/model/model_builder.h"

namespace msm_sim::core {

BaudetStiffness ComputeBaudetStiffness(const Material& material, double spacing) {
  const double lambda = material.lame_lambda();
  const double mu = material.shear_modulus();
  return {(lambda + mu) * spacing / 4.0, 0.75 * mu * spacing, (lambda - mu) * spacing / 16.0};
}

Model BuildBaudetLattice(const Material& material, const BaudetLatticeOptions& options) {
  using namespace lattice;
  const BoxLattice box{options.size, options.spacing, options.rotation_axis, options.rotation_angle,
                       options.max_nodes};
  Validate(box);
  const ElementGrid grid = MakeElementGrid(box);
  const double a = options.spacing;
  const BaudetStiffness stiffness = ComputeBaudetStiffness(material, a);
  const int n = static_cast<int>(grid.corners.size());

  ModelBuilder builder(material);
  builder.SetSpringLaw(options.spring_law);
  std::vector<double> mass(n, 0.0);
  for (const Eigen::Vector3i& e : grid.elements) {
    for (int delta = 0; delta < 8; ++delta)
      mass[grid.Corner(e, delta)] += material.density() * a * a * a / 8.0;
  }
  for (int node = 0; node < n; ++node) {
    builder.AddNode(grid.corner_frame.Position(grid.corners[node]), mass[node]);
  }

  // Edges are shared by up to four bricks: accumulate per (start corner, axis) first.
  std::vector<double> edge_stiffness(3 * static_cast<std::size_t>(n), 0.0);
  const auto edge_key = [&](const Eigen::Vector3i& element, int start_delta, int axis) {
    return 3 * static_cast<std::size_t>(grid.Corner(element, start_delta)) + axis;
  };
  // Corner offsets (bits x, y, z) of the 4 edges along each axis start at delta with that bit 0.
  const auto edge_starts = [](int axis) {
    std::array<int, 4> starts{};
    int count = 0;
    for (int delta = 0; delta < 8; ++delta) {
      if (!(delta & (1 << axis))) starts[count++] = delta;
    }
    return starts;
  };
  for (const Eigen::Vector3i& e : grid.elements) {
    for (int axis = 0; axis < 3; ++axis) {
      for (int start : edge_starts(axis))
        edge_stiffness[edge_key(e, start, axis)] += stiffness.edge;
    }
  }
  std::vector<SpringIndex> edge_spring(3 * static_cast<std::size_t>(n), -1);
  for (int node = 0; node < n; ++node) {
    for (int axis = 0; axis < 3; ++axis) {
      const double k = edge_stiffness[3 * node + axis];
      if (k <= 0.0) continue;
      const int other = grid.corner_index.Find(grid.corners[node] + Eigen::Vector3i::Unit(axis));
      edge_spring[3 * node + axis] = builder.AddSpring(node, other, k);
    }
  }
  // Inner diagonals belong to one brick each; the correction element couples its 12 edges.
  for (const Eigen::Vector3i& e : grid.elements) {
    for (int delta = 0; delta < 4; ++delta) {
      builder.AddSpring(grid.Corner(e, delta), grid.Corner(e, 7 - delta), stiffness.diagonal);
    }
    if (!options.orthogonal_correction || stiffness.correction == 0.0) continue;
    std::array<SpringIndex, 12> edges{};
    for (int axis = 0; axis < 3; ++axis) {
      const std::array<int, 4> starts = edge_starts(axis);
      for (int i = 0; i < 4; ++i) edges[4 * axis + i] = edge_spring[edge_key(e, starts[i], axis)];
    }
    builder.AddCorrectionElement(edges, stiffness.correction);
  }
  return builder.Build(static_cast<double>(grid.elements.size()) * a * a * a, a);
}

}  // namespace msm_sim::core
