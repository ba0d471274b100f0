#pragma once
// Private to msm_sim's lattice builders: the softer outer layer of the eMSM dispersion
// (docs/physics.md §7, "A softer outer layer").

#include <vector>

#include "msm_sim/model/model_builder.h"

namespace msm_sim::core::lattice {

/// Throws std::invalid_argument unless keep lies in (0, 1] (a builder's surface_dispersion).
void ValidateSurfaceDispersion(double keep);

/// The outer node layer and, for each of its nodes (a giver), the inner nodes that may take its
/// bulk: recipients[offsets[g] .. offsets[g + 1]) for givers[g].
struct OuterLayerNeighbourhoods {
  std::vector<NodeIndex> givers;
  std::vector<int> offsets{0};  ///< givers.size() + 1 entries
  std::vector<NodeIndex> recipients;
};

/// Moves part of the eMSM bulk of the outer node layer onto the nodes beneath it.
///
/// Node x's dispersion energy is Phi_x = J_x^2 / (2 q W_x) (Model::dispersion_weight_a), with J_x
/// and W_x both linear in the weights v of x's spring ends, so scaling every weight at x by r
/// scales x's bulk energy by r under any strain. Every giver x (with recipients and W > 0) gets
/// r = keep and gives up (1 - keep) W_x; a recipient j that receives E_j gets r = 1 + E_j / W_j.
/// How the given bulk is split is an iterative proportional fitting over the neighbourhoods: each
/// giver gives exactly its share, and each recipient receives as nearly as the neighbourhoods
/// allow the same multiple of its own W (docs/design/surface-dispersion.md). Under a uniform strain
/// every star reads the same dilatation J / W, so the body's summed bulk energy is unchanged.
///
/// Why: near nu = 1/2 the one-sided stars of the outer layer respond to the shortest waves as
/// interior stars do not, and set the explicit stable step (docs/physics.md §7).
/// Precondition: every node index < builder->num_nodes(); no recipient is a giver; keep in (0, 1].
void ShiftOuterLayerDispersion(const OuterLayerNeighbourhoods& layer, double keep,
                               ModelBuilder* builder);

}  // namespace msm_sim::core::lattice
