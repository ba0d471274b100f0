#include "build/node_centred_lattice.h"

#include <vector>

#include "msm_sim/material/extended_msm.h"
#include "msm_sim/model/model_builder.h"

namespace msm_sim::core::lattice {
namespace {

// The stiffness each end contributed to each spring, by spring index.
struct EndShares {
  std::vector<double> a, b;
};

// Adds a node of mass cell_mass chi at every cell centre, records it in `index`, and returns
// sum chi, the number of full cells the body occupies.
double AddCellNodes(const OccupiedCells& cells, double cell_mass, LatticeIndex* index,
                    ModelBuilder* builder) {
  const int n = static_cast<int>(cells.coords.size());
  double occupied = 0.0;
  for (int node = 0; node < n; ++node) {
    const double chi = cells.fractions[node];
    index->At(cells.coords[node]) =
        builder->AddNode(cells.frame.Position(cells.coords[node]), cell_mass * chi);
    occupied += chi;
  }
  return occupied;
}

// Adds the A+B spring from every node to each present neighbour along the half offsets: each end
// contributes half a bulk spring times its cell's chi. Returns the spring of (node, offset) at
// node * kNumHalfOffsets + offset (-1: none).
std::vector<SpringIndex> AddHalfOffsetSprings(const OccupiedCells& cells, const LatticeIndex& index,
                                              double kappa, ModelBuilder* builder,
                                              EndShares* shares) {
  const int n = static_cast<int>(cells.coords.size());
  std::vector<SpringIndex> spring_of(static_cast<std::size_t>(n) * kNumHalfOffsets, -1);
  for (int node = 0; node < n; ++node) {
    for (int o = 0; o < kNumHalfOffsets; ++o) {
      const int other = index.Find(cells.coords[node] + kHalfOffsets[o]);
      if (other < 0) continue;
      const double half_a = 0.5 * kappa * cells.fractions[node];
      const double half_b = 0.5 * kappa * cells.fractions[other];
      spring_of[node * kNumHalfOffsets + o] = builder->AddSpring(node, other, half_a + half_b);
      shares->a.push_back(half_a);
      shares->b.push_back(half_b);
    }
  }
  return spring_of;
}

// A node whose neighbour i + d is missing loses the half-spring its own cell would have
// contributed along d; it goes onto the collinear spring (i, i - d) of the same node.
void MirrorMissingHalfSprings(const OccupiedCells& cells, const LatticeIndex& index, double kappa,
                              const std::vector<SpringIndex>& spring_of, ModelBuilder* builder,
                              EndShares* shares) {
  const int n = static_cast<int>(cells.coords.size());
  for (int node = 0; node < n; ++node) {
    const double half = 0.5 * kappa * cells.fractions[node];
    for (int o = 0; o < kNumHalfOffsets; ++o) {
      for (const int sign : {1, -1}) {
        const Eigen::Vector3i d = sign * kHalfOffsets[o];
        if (index.Find(cells.coords[node] + d) >= 0) continue;  // neighbour present
        const int opposite = index.Find(cells.coords[node] - d);
        if (opposite < 0) continue;  // one cell thick along d: nothing to carry it
        // Spring (node, node - d): stored at the endpoint from which it points along +offset.
        const SpringIndex s = sign > 0 ? spring_of[opposite * kNumHalfOffsets + o]
                                       : spring_of[node * kNumHalfOffsets + o];
        builder->AddStiffness(s, half);
        (builder->spring_node_a(s) == node ? shares->a : shares->b)[s] += half;
      }
    }
  }
}

// In node i's star a spring stands for the stiffness end i contributed to it. Its tension
// k dL is shared by the ends in proportion: weight v = 2 share / (share_a + share_b), so each
// end counts its own share (and receives that share of the dispersion, w = v k L0^2). With
// full cells and no mirrored half-springs every v is 1: the eMSM paper's algorithm.
void SetDispersionWeightsFromShares(const EndShares& shares, ModelBuilder* builder) {
  for (SpringIndex s = 0; s < builder->num_springs(); ++s) {
    const double total = shares.a[s] + shares.b[s];
    builder->SetDispersionWeight(s, builder->spring_node_a(s), 2.0 * shares.a[s] / total);
    builder->SetDispersionWeight(s, builder->spring_node_b(s), 2.0 * shares.b[s] / total);
  }
}

}  // namespace

Model BuildNodeCentredModel(const Material& material, const OccupiedCells& cells,
                            bool compensate_surface, SpringLaw spring_law) {
  const double a = cells.frame.unit;
  const double kappa = material.shear_modulus() * a;
  const double cell_mass = material.density() * a * a * a;
  LatticeIndex index(cells.lo, cells.hi);
  ModelBuilder builder(material);
  builder.SetSpringLaw(spring_law);
  builder.SetDispersionFraction(DispersionFraction(material.poisson_ratio()));
  const double occupied = AddCellNodes(cells, cell_mass, &index, &builder);
  EndShares shares;
  const std::vector<SpringIndex> spring_of =
      AddHalfOffsetSprings(cells, index, kappa, &builder, &shares);
  if (compensate_surface) {
    MirrorMissingHalfSprings(cells, index, kappa, spring_of, &builder, &shares);
  }
  SetDispersionWeightsFromShares(shares, &builder);
  return builder.Build(occupied * a * a * a, a);
}

}  // namespace msm_sim::core::lattice
