#include "build/node_centred_lattice.h"

#include "msm_sim/material/extended_msm.h"
#include "msm_sim/model/model_builder.h"

namespace msm_sim::core::lattice {

Model BuildNodeCentredModel(const Material& material, const OccupiedCells& cells,
                            bool compensate_surface, SpringLaw spring_law) {
  const double a = cells.frame.unit;
  const double kappa = material.shear_modulus() * a;
  const double cell_mass = material.density() * a * a * a;
  const int n = static_cast<int>(cells.coords.size());
  LatticeIndex index(cells.lo, cells.hi);
  ModelBuilder builder(material);
  builder.SetSpringLaw(spring_law);
  builder.SetDispersionFraction(DispersionFraction(material.poisson_ratio()));
  double occupied = 0.0;
  for (int node = 0; node < n; ++node) {
    const double chi = cells.fractions[node];
    index.At(cells.coords[node]) =
        builder.AddNode(cells.frame.Position(cells.coords[node]), cell_mass * chi);
    occupied += chi;
  }

  // The stiffness each end contributes to each spring: half a bulk spring times its cell's chi.
  std::vector<double> share_a, share_b;
  std::vector<SpringIndex> spring_of(static_cast<std::size_t>(n) * kNumHalfOffsets, -1);
  for (int node = 0; node < n; ++node) {
    for (int o = 0; o < kNumHalfOffsets; ++o) {
      const int other = index.Find(cells.coords[node] + kHalfOffsets[o]);
      if (other < 0) continue;
      const double half_a = 0.5 * kappa * cells.fractions[node];
      const double half_b = 0.5 * kappa * cells.fractions[other];
      spring_of[node * kNumHalfOffsets + o] = builder.AddSpring(node, other, half_a + half_b);
      share_a.push_back(half_a);
      share_b.push_back(half_b);
    }
  }

  if (compensate_surface) {
    // A node whose neighbour i + d is missing loses the half-spring its own cell would have
    // contributed along d; it goes onto the collinear spring (i, i - d) of the same node.
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
          builder.AddStiffness(s, half);
          (builder.spring_node_a(s) == node ? share_a : share_b)[s] += half;
        }
      }
    }
  }
  // In node i's star a spring stands for the stiffness end i contributed to it. Its tension
  // k dL is shared by the ends in proportion: weight v = 2 share / (share_a + share_b), so each
  // end counts its own share (and receives that share of the dispersion, w = v k L0^2). With
  // full cells and no mirrored half-springs every v is 1: the eMSM paper's algorithm.
  for (SpringIndex s = 0; s < builder.num_springs(); ++s) {
    const double total = share_a[s] + share_b[s];
    builder.SetDispersionWeight(s, builder.spring_node_a(s), 2.0 * share_a[s] / total);
    builder.SetDispersionWeight(s, builder.spring_node_b(s), 2.0 * share_b[s] / total);
  }
  return builder.Build(occupied * a * a * a, a);
}

}  // namespace msm_sim::core::lattice
