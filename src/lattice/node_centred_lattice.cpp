#include "lattice/node_centred_lattice.h"

#include <cmath>
#include <map>
#include <optional>
#include <stdexcept>
#include <tuple>
#include <vector>

#include "lattice/free_face_bending.h"
#include "lattice/outer_layer_dispersion.h"
#include "lattice/selective_mass_scaling.h"
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
    // docs/physics.md §5, §7: the surface crosses a partial cell `inset` inside its outer face.
    const double flat_cut = chi < 1.0 ? (1.0 - chi) * cells.frame.unit : 0.0;
    const double inset = cells.insets.empty() ? flat_cut : cells.insets[node];
    index->At(cells.coords[node]) =
        builder->AddNode(cells.frame.Position(cells.coords[node]), cell_mass * chi, inset);
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

// The fraction t in (0, 1] of the way from `from` to `to` at which the segment leaves the body
// through one of `anchored`, or 0 if it leaves through none (the first plane crossed counts).
double AnchoredCrossing(const std::vector<AnchoredPlane>& anchored, const Eigen::Vector3d& from,
                        const Eigen::Vector3d& to) {
  double t_first = 0.0;
  for (const AnchoredPlane& plane : anchored) {
    const Eigen::Vector3d n = plane.normal.normalized();
    const double s_from = (from - plane.point).dot(n);
    const double s_to = (to - plane.point).dot(n);
    if (s_from > 0.0 || s_to <= 0.0) continue;  // not leaving the body through this plane
    const double t = s_from / (s_from - s_to);
    if (t_first == 0.0 || t < t_first) t_first = std::max(t, 1e-9);
  }
  return t_first;
}

// True if node + d is a missing neighbour whose spring would leave through an anchored plane.
bool IsAnchored(const OccupiedCells& cells, const LatticeIndex& index,
                const std::vector<AnchoredPlane>& anchored, int node, const Eigen::Vector3i& d) {
  if (anchored.empty() || index.Find(cells.coords[node] + d) >= 0) return false;
  return AnchoredCrossing(anchored, cells.frame.Position(cells.coords[node]),
                          cells.frame.Position(cells.coords[node] + d)) > 0.0;
}

// For every node whose neighbour i + d is missing across an anchored plane: a fixed node where the
// spring meets the plane (shared by the springs that meet there) and a spring to it standing for
// node i's half of the missing spring. Its rest length is t L0, so k = half / t^2 keeps
// k L^2 = half L0^2: under any uniform strain it stores what node i's half-spring would (at
// t = 1/2, k = 4 half: the inner half of a spring is twice as stiff as the whole). Node i counts
// it with v = 2 (share: all of it) so that w = v k L^2 = 2 half L0^2, the weight the bulk spring
// has in node i's star, and the anchor end disperses nothing (share 0, v = 0): the fixed anchor is
// not material, so node i's star, inflow and dispersed tension match a bulk node's.
void AddFaceAnchors(const OccupiedCells& cells, const LatticeIndex& index,
                    const std::vector<AnchoredPlane>& anchored, double kappa, bool compensate,
                    double anchor_mass, const std::optional<FreeFaceBending>& bending,
                    ModelBuilder* builder, EndShares* shares, std::vector<double>* factors) {
  const double a = cells.frame.unit;
  std::map<std::tuple<long, long, long>, NodeIndex> anchor_at;  // by position in 1e-6 a
  const int n = static_cast<int>(cells.coords.size());
  for (int node = 0; node < n; ++node) {
    const Eigen::Vector3d p = cells.frame.Position(cells.coords[node]);
    for (int o = 0; o < kNumHalfOffsets; ++o) {
      for (const int sign : {1, -1}) {
        const Eigen::Vector3i d = sign * kHalfOffsets[o];
        if (!IsAnchored(cells, index, anchored, node, d)) continue;
        const Eigen::Vector3d q = cells.frame.Position(cells.coords[node] + d);
        const double t = AnchoredCrossing(anchored, p, q);
        const Eigen::Vector3d point = p + t * (q - p);
        const auto key = std::make_tuple(std::lround(point.x() / (1e-6 * a)),
                                         std::lround(point.y() / (1e-6 * a)),
                                         std::lround(point.z() / (1e-6 * a)));
        auto found = anchor_at.find(key);
        if (found == anchor_at.end()) {
          found = anchor_at.emplace(key, builder->AddNode(point, anchor_mass)).first;
        }
        // With compensate_surface, a missing (not anchored) neighbour on the other side, i - d,
        // mirrors its half-spring onto this one, as onto any collinear spring.
        const bool mirrored = compensate && index.Find(cells.coords[node] - d) < 0 &&
                              !IsAnchored(cells, index, anchored, node, -d);
        const double half = 0.5 * kappa * cells.fractions[node] * (mirrored ? 2.0 : 1.0);
        // The anchor spring stands for the missing spring along d, so it takes that spring's
        // bending factor: an outer layer's stiffer springs must end on equally stiff anchors.
        const double factor = bending ? bending->Factor(cells.coords[node], d) : 1.0;
        builder->AddSpring(node, found->second, factor * half / (t * t));
        shares->a.push_back(half / (t * t));
        shares->b.push_back(0.0);
        factors->push_back(factor);
      }
    }
  }
}

// A node whose neighbour i + d is missing loses the half-spring its own cell would have
// contributed along d; it goes onto the collinear spring (i, i - d) of the same node.
// Neighbours across an anchored plane are left to AddFaceAnchors.
void MirrorMissingHalfSprings(const OccupiedCells& cells, const LatticeIndex& index, double kappa,
                              const std::vector<SpringIndex>& spring_of,
                              const std::vector<AnchoredPlane>& anchored, ModelBuilder* builder,
                              EndShares* shares) {
  const int n = static_cast<int>(cells.coords.size());
  for (int node = 0; node < n; ++node) {
    const double half = 0.5 * kappa * cells.fractions[node];
    for (int o = 0; o < kNumHalfOffsets; ++o) {
      for (const int sign : {1, -1}) {
        const Eigen::Vector3i d = sign * kHalfOffsets[o];
        if (index.Find(cells.coords[node] + d) >= 0) continue;  // neighbour present
        if (IsAnchored(cells, index, anchored, node, d)) continue;
        const int opposite = index.Find(cells.coords[node] - d);
        // One cell thick along d: nothing to carry it; or i - d is anchored: AddFaceAnchors.
        if (opposite < 0) continue;
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
// full cells and no mirrored half-springs every v is 1: the eMSM paper's algorithm. An anchor
// spring's anchor end has share 0: v = 0 there, 2 at the node. A spring whose stiffness was
// scaled by the free faces' bending factor f (shares unscaled) gets v / f: the dispersion, which
// only sees v k, stays exactly what it was.
void SetDispersionWeightsFromShares(const EndShares& shares, const std::vector<double>& factors,
                                    ModelBuilder* builder) {
  for (SpringIndex s = 0; s < builder->num_springs(); ++s) {
    const double total = shares.a[s] + shares.b[s];
    const double v = 2.0 / (total * factors[s]);
    builder->SetDispersionWeight(s, builder->spring_node_a(s), v * shares.a[s]);
    builder->SetDispersionWeight(s, builder->spring_node_b(s), v * shares.b[s]);
  }
}

// The free faces' bending factors of the lattice springs (docs/physics.md §2.1), applied to their
// stiffness (mirrored half-springs included); one factor per spring so far.
std::vector<double> ScaleForFreeFaceBending(const OccupiedCells& cells,
                                            const std::optional<FreeFaceBending>& bending,
                                            ModelBuilder* builder) {
  std::vector<double> factors(builder->num_springs(), 1.0);
  if (!bending) return factors;
  for (SpringIndex s = 0; s < builder->num_springs(); ++s) {
    const Eigen::Vector3i& from = cells.coords[builder->spring_node_a(s)];
    factors[s] = bending->Factor(from, cells.coords[builder->spring_node_b(s)] - from);
    builder->AddStiffness(s, (factors[s] - 1.0) * builder->spring_stiffness(s));
  }
  return factors;
}

// The correction applies to cells that fill a box completely (docs/physics.md §2.1).
std::optional<FreeFaceBending> FreeFaceBendingOf(const OccupiedCells& cells, double poisson) {
  // 1e-6: the clipping of a box mesh's cells reads whole cells as 1 - 4e-9.
  for (const double chi : cells.fractions) {
    if (chi < 1.0 - 1e-6) return std::nullopt;
  }
  return FreeFaceBending::ForBox(cells.coords, poisson);
}

// Whether node's cell misses one of its 18 A+B neighbours: the outer node layer.
bool IsOuter(const OccupiedCells& cells, const LatticeIndex& index, int node) {
  for (int o = 0; o < kNumHalfOffsets; ++o) {
    if (index.Find(cells.coords[node] + kHalfOffsets[o]) < 0 ||
        index.Find(cells.coords[node] - kHalfOffsets[o]) < 0) {
      return true;
    }
  }
  return false;
}

// The outer layer's nodes, each with the inner nodes among the 26 cells around it (which reach
// past the outer layer from an edge or a corner too).
OuterLayerNeighbourhoods OuterLayerOf(const OccupiedCells& cells, const LatticeIndex& index) {
  const int n = static_cast<int>(cells.coords.size());
  std::vector<char> outer(n);
  for (int node = 0; node < n; ++node) outer[node] = IsOuter(cells, index, node);
  OuterLayerNeighbourhoods layer;
  for (int node = 0; node < n; ++node) {
    if (!outer[node]) continue;
    for (int dz = -1; dz <= 1; ++dz) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int other = index.Find(cells.coords[node] + Eigen::Vector3i(dx, dy, dz));
          if (other >= 0 && !outer[other]) layer.recipients.push_back(other);
        }
      }
    }
    layer.givers.push_back(node);
    layer.offsets.push_back(static_cast<int>(layer.recipients.size()));
  }
  return layer;
}

}  // namespace

void ValidateAnchoredPlanes(const std::vector<AnchoredPlane>& anchored) {
  for (const AnchoredPlane& plane : anchored) {
    if (!plane.point.allFinite() || !plane.normal.allFinite() || plane.normal.norm() == 0.0) {
      throw std::invalid_argument("an anchored plane needs a finite point and a non-zero normal");
    }
  }
}

Model BuildNodeCentredModel(const Material& material, const OccupiedCells& cells,
                            const NodeCentredSurfaceOptions& surface, SpringLaw spring_law,
                            const PowerSpringLaw& power_law) {
  const double a = cells.frame.unit;
  const double kappa = material.shear_modulus() * a;
  const double cell_mass = material.density() * a * a * a;
  const double q = DispersionFraction(material.poisson_ratio());
  LatticeIndex index(cells.lo, cells.hi);
  ModelBuilder builder(material);
  builder.SetSpringLaw(spring_law, power_law);
  builder.SetDispersionFraction(q);
  const double occupied = AddCellNodes(cells, cell_mass, &index, &builder);
  EndShares shares;
  const std::vector<SpringIndex> spring_of =
      AddHalfOffsetSprings(cells, index, kappa, &builder, &shares);
  if (surface.compensate_surface) {
    MirrorMissingHalfSprings(cells, index, kappa, spring_of, surface.anchored_planes, &builder,
                             &shares);
  }
  const std::optional<FreeFaceBending> bending =
      surface.free_face_bending && surface.compensate_surface
          ? FreeFaceBendingOf(cells, material.poisson_ratio())
          : std::nullopt;
  std::vector<double> factors = ScaleForFreeFaceBending(cells, bending, &builder);
  AddFaceAnchors(cells, index, surface.anchored_planes, kappa, surface.compensate_surface,
                 1e-6 * cell_mass, bending, &builder, &shares, &factors);
  SetDispersionWeightsFromShares(shares, factors, &builder);
  if (surface.surface_dispersion < 1.0 && q > 0.0) {
    ShiftOuterLayerDispersion(OuterLayerOf(cells, index), surface.surface_dispersion, &builder);
  }
  Model model = builder.Build(occupied * a * a * a, a);
  // docs/physics.md §7 "Selective mass scaling": a box of whole cells stays exactly as built.
  if (!ScaleCutCells(model, cells, material, surface, spring_law, power_law, &builder)) {
    return model;
  }
  return builder.Build(occupied * a * a * a, a);
}

}  // namespace msm_sim::core::lattice
