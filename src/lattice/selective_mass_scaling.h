#pragma once
// Private to msm_sim's lattice builders: selective mass scaling of the cut cells of node-centred
// lattices (docs/physics.md §7 "Selective mass scaling").

#include <vector>

#include "lattice/node_centred_lattice.h"
#include "msm_sim/lattice/lattice_options.h"
#include "msm_sim/model/model.h"
#include "msm_sim/model/model_builder.h"

namespace msm_sim::core::lattice {

/// The largest bound on the added mass, as a fraction of the body's, a builder accepts.
inline constexpr double kMaxMassScaling = 0.1;

/// Throws std::invalid_argument, one line naming mass_scaling, unless bound lies in [0, 0.1]
/// (kMaxMassScaling).
void ValidateMassScaling(double bound);

/// Each node's local stiffness figures (1/s^2), their largest diagonal entries over its mass of
/// the stiffness K at rest (eMSM dispersion included), which sets the undamped explicit step, and
/// of the springs' own stiffness sum k u u^T, which the spring dampers act on and which sets a
/// heavily damped step (docs/physics.md §7 "Dampers"). A node's local stable step is 2 / sqrt of
/// the first.
struct LocalStiffness {
  std::vector<double> elastic, damper;
};
LocalStiffness LocalStiffnessOf(const Model& model);

/// Adds mass to the nodes `cut` marks (cut cells) whose figures (LocalStiffnessOf `model`, built
/// from `builder`) exceed `full_cell`'s (one number per figure: the stiffest whole cell's), each
/// up to the mass that brings both down to them, so that cut cells no longer set the explicit
/// stable step, damped or not. The total added stays within bound times the body's mass (sum of
/// masses): if the full-cell figures need more, every scaled node stops at the same multiple of
/// them that spends exactly the bound, and the builder records the scaling as limited
/// (ModelBuilder::SetMassScaling). Returns the mass added (kg). Precondition: cut has one entry per
/// node of model; bound >= 0; full_cell's figures > 0.
double ScaleCutCellMasses(const Model& model, const std::vector<char>& cut,
                          const LocalStiffness& full_cell, double bound, ModelBuilder* builder);

/// Selective mass scaling of the node-centred model `model` that `builder` built from `cells`
/// (BuildNodeCentredModel): ScaleCutCellMasses with the cells whose fraction is below 1 as the
/// cut ones, the stiffest whole cell of a block of the same material, spacing, springs and
/// outer layer as the reference, and surface.mass_scaling as the bound. Returns false, changing
/// nothing, when there is nothing to scale (mass_scaling 0 or no cut cell), true when the
/// builder's masses changed and the model must be built again.
bool ScaleCutCells(const Model& model, const OccupiedCells& cells, const Material& material,
                   const NodeCentredSurfaceOptions& surface, SpringLaw spring_law,
                   const PowerSpringLaw& power_law, ModelBuilder* builder);

}  // namespace msm_sim::core::lattice
