#pragma once
// Private to msm_sim's lattice builders: the softer outer layer of the eMSM dispersion
// (docs/physics.md §7, "A softer outer layer").

#include <vector>

#include "msm_sim/model/model_builder.h"

namespace msm_sim::core::lattice {

/// Throws std::invalid_argument unless keep lies in (0, 1] (a builder's surface_dispersion).
void ValidateSurfaceDispersion(double keep);

/// Moves part of the eMSM bulk of the outer node layer onto the nodes beneath it.
///
/// Node x's dispersion energy is Phi_x = J_x^2 / (2 q W_x) (Model::dispersion_weight_a), with J_x
/// and W_x both linear in the weights v of x's spring ends, so scaling every weight at x by r
/// scales x's bulk energy by r under any strain. Every outer node x with recipients gets
/// r = keep, and the bulk (1 - keep) W_x it gives up is split among recipients[x] (inner nodes,
/// W > 0) in proportion to their W; a recipient j that receives E_j gets r = 1 + E_j / W_j. Under
/// a uniform strain every star reads the same dilatation J / W, so the body's summed bulk energy
/// is unchanged. An outer node without recipients keeps its weights.
///
/// Why: near nu = 1/2 the one-sided stars of the outer layer respond to the shortest waves as
/// interior stars do not, and set the explicit stable step (docs/physics.md §7).
/// Precondition: recipients.size() == builder->num_nodes(); recipients are nodes not listed as
/// givers (their own list empty) with W > 0; keep in (0, 1].
void ShiftOuterLayerDispersion(const std::vector<std::vector<NodeIndex>>& recipients, double keep,
                               ModelBuilder* builder);

}  // namespace msm_sim::core::lattice
