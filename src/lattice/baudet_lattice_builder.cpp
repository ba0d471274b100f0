#include "msm_sim/lattice/baudet_lattice_builder.h"

#include <array>
#include <vector>

#include "lattice/lattice_geometry.h"
#include "msm_sim/model/model_builder.h"

namespace msm_sim::core {
namespace {

using lattice::ElementGrid;

// Adds a node at every element corner, each element lumping an eighth of its mass on each.
void AddLumpedNodes(const Material& material, const ElementGrid& grid, double a,
                    ModelBuilder* builder) {
  const int n = static_cast<int>(grid.corners.size());
  std::vector<double> mass(n, 0.0);
  for (const Eigen::Vector3i& e : grid.elements) {
    for (int delta = 0; delta < 8; ++delta)
      mass[grid.Corner(e, delta)] += material.density() * a * a * a / 8.0;
  }
  for (int node = 0; node < n; ++node) {
    builder->AddNode(grid.corner_frame.Position(grid.corners[node]), mass[node]);
  }
}

// Corner offsets (bits x, y, z) of the 4 edges along each axis start at delta with that bit 0.
std::array<int, 4> EdgeStarts(int axis) {
  std::array<int, 4> starts{};
  int count = 0;
  for (int delta = 0; delta < 8; ++delta) {
    if (!(delta & (1 << axis))) starts[count++] = delta;
  }
  return starts;
}

// An edge is named by its start corner and axis: 3 start + axis.
std::size_t EdgeKey(const ElementGrid& grid, const Eigen::Vector3i& element, int start_delta,
                    int axis) {
  return 3 * static_cast<std::size_t>(grid.Corner(element, start_delta)) + axis;
}

// Adds one spring per lattice edge with the edge stiffness of every brick sharing it, and
// returns the spring of each edge by EdgeKey (-1: no edge there).
std::vector<SpringIndex> AddEdgeSprings(const ElementGrid& grid, double edge_stiffness_per_brick,
                                        ModelBuilder* builder) {
  const int n = static_cast<int>(grid.corners.size());
  // Edges are shared by up to four bricks: accumulate per (start corner, axis) first.
  std::vector<double> edge_stiffness(3 * static_cast<std::size_t>(n), 0.0);
  for (const Eigen::Vector3i& e : grid.elements) {
    for (int axis = 0; axis < 3; ++axis) {
      for (int start : EdgeStarts(axis))
        edge_stiffness[EdgeKey(grid, e, start, axis)] += edge_stiffness_per_brick;
    }
  }
  std::vector<SpringIndex> edge_spring(3 * static_cast<std::size_t>(n), -1);
  for (int node = 0; node < n; ++node) {
    for (int axis = 0; axis < 3; ++axis) {
      const double k = edge_stiffness[3 * node + axis];
      if (k <= 0.0) continue;
      const int other = grid.corner_index.Find(grid.corners[node] + Eigen::Vector3i::Unit(axis));
      edge_spring[3 * node + axis] = builder->AddSpring(node, other, k);
    }
  }
  return edge_spring;
}

// Inner diagonals belong to one brick each; the correction element couples its 12 edges.
void AddDiagonalsAndCorrections(const ElementGrid& grid, const BaudetStiffness& stiffness,
                                bool orthogonal_correction,
                                const std::vector<SpringIndex>& edge_spring,
                                ModelBuilder* builder) {
  for (const Eigen::Vector3i& e : grid.elements) {
    for (int delta = 0; delta < 4; ++delta) {
      builder->AddSpring(grid.Corner(e, delta), grid.Corner(e, 7 - delta), stiffness.diagonal);
    }
    if (!orthogonal_correction || stiffness.correction == 0.0) continue;
    std::array<SpringIndex, 12> edges{};
    for (int axis = 0; axis < 3; ++axis) {
      const std::array<int, 4> starts = EdgeStarts(axis);
      for (int i = 0; i < 4; ++i)
        edges[4 * axis + i] = edge_spring[EdgeKey(grid, e, starts[i], axis)];
    }
    builder->AddCorrectionElement(edges, stiffness.correction);
  }
}

}  // namespace

BaudetStiffness ComputeBaudetStiffness(const Material& material, double spacing) {
  const double lambda = material.lame_lambda();
  const double mu = material.shear_modulus();
  return {(lambda + mu) * spacing / 4.0, 0.75 * mu * spacing, (lambda - mu) * spacing / 16.0};
}

Model BuildBaudetLattice(const Material& material, const BaudetLatticeOptions& options) {
  const lattice::BoxLattice box = lattice::BoxOf(options.size, options.lattice);
  lattice::Validate(box);
  const ElementGrid grid = lattice::MakeElementGrid(box);
  const double a = options.lattice.spacing;
  const BaudetStiffness stiffness = ComputeBaudetStiffness(material, a);

  ModelBuilder builder(material);
  builder.SetSpringLaw(options.lattice.spring_law, options.lattice.power_law);
  AddLumpedNodes(material, grid, a, &builder);
  const std::vector<SpringIndex> edge_spring = AddEdgeSprings(grid, stiffness.edge, &builder);
  AddDiagonalsAndCorrections(grid, stiffness, options.orthogonal_correction, edge_spring, &builder);
  return builder.Build(static_cast<double>(grid.elements.size()) * a * a * a, a);
}

}  // namespace msm_sim::core
