#include "lattice/selective_mass_scaling.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "msm_sim/mechanics/force_evaluator.h"

namespace msm_sim::core::lattice {
namespace {

// The mass added when every candidate i is brought to needed_i / multiple (never below its
// own mass m_i): the multiple of the full-cell figures it is left at.
double AddedAt(const std::vector<double>& needed, const std::vector<double>& mass,
               double multiple) {
  double added = 0.0;
  for (std::size_t i = 0; i < mass.size(); ++i) {
    added += std::max(0.0, needed[i] / multiple - mass[i]);
  }
  return added;
}

// The smallest multiple >= 1 whose added mass stays within budget (docs/physics.md §7
// "Selective mass scaling"): the added mass falls monotonically with the multiple, so bisect.
double MultipleWithinBudget(const std::vector<double>& needed, const std::vector<double>& mass,
                            double budget) {
  if (AddedAt(needed, mass, 1.0) <= budget) return 1.0;
  double lo = 1.0, hi = 2.0;
  while (AddedAt(needed, mass, hi) > budget) hi *= 2.0;
  for (int iteration = 0; iteration < 100 && hi - lo > 1e-12 * hi; ++iteration) {
    const double mid = 0.5 * (lo + hi);
    (AddedAt(needed, mass, mid) > budget ? lo : hi) = mid;
  }
  return hi;
}

// Whether each node's cell is cut by the surface (chi below 1; 1e-6: the clipping of a box
// mesh's cells reads whole cells as 1 - 4e-9); anchors, added after the cells, are not.
std::vector<char> CutCells(const OccupiedCells& cells, int num_nodes) {
  std::vector<char> cut(num_nodes, 0);
  for (std::size_t node = 0; node < cells.fractions.size(); ++node) {
    cut[node] = cells.fractions[node] < 1.0 - 1e-6;
  }
  return cut;
}

// The local stiffness figures (LocalStiffnessOf) of whole cells of this lattice: the largest
// over a block of 7^3 whole cells with the same material, spacing, springs and outer layer, whose
// stiffest cells (edges and corners) set a box's step (docs/physics.md §7 "Selective mass
// scaling"). One entry per figure.
LocalStiffness FullCellFigures(const Material& material, double a,
                               const NodeCentredSurfaceOptions& surface, SpringLaw spring_law,
                               const PowerSpringLaw& power_law) {
  OccupiedCells block;
  block.frame = {Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), a};
  block.lo = Eigen::Vector3i::Constant(-3);
  block.hi = Eigen::Vector3i::Constant(3);
  for (int k = -3; k <= 3; ++k) {
    for (int j = -3; j <= 3; ++j) {
      for (int i = -3; i <= 3; ++i) {
        block.coords.emplace_back(i, j, k);
        block.fractions.push_back(1.0);
      }
    }
  }
  NodeCentredSurfaceOptions plain;
  plain.compensate_surface = surface.compensate_surface;
  plain.surface_dispersion = surface.surface_dispersion;
  plain.mass_scaling = 0.0;
  const LocalStiffness all =
      LocalStiffnessOf(BuildNodeCentredModel(material, block, plain, spring_law, power_law));
  return {{*std::max_element(all.elastic.begin(), all.elastic.end())},
          {*std::max_element(all.damper.begin(), all.damper.end())}};
}

}  // namespace

void ValidateMassScaling(double bound) {
  if (!(bound >= 0.0 && bound <= kMaxMassScaling)) {
    throw std::invalid_argument(
        "mass_scaling must lie in [0, 0.1] (the most mass added to cut cells, a fraction of the "
        "body's; 0: off), got " +
        std::to_string(bound));
  }
}

LocalStiffness LocalStiffnessOf(const Model& model) {
  ForceEvaluator evaluator(model);
  evaluator.Linearize(model.rest_positions());
  const Eigen::Matrix3Xd elastic = evaluator.StiffnessDiagonal();
  Eigen::Matrix3Xd damper = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
  for (SpringIndex s = 0; s < model.num_springs(); ++s) {
    const NodeIndex a = model.spring_node_a()[s], b = model.spring_node_b()[s];
    const Eigen::Vector3d u =
        (model.rest_positions().col(b) - model.rest_positions().col(a)).normalized();
    const Eigen::Vector3d diagonal = model.spring_stiffness()[s] * u.cwiseAbs2();
    damper.col(a) += diagonal;
    damper.col(b) += diagonal;
  }
  LocalStiffness figures;
  for (int i = 0; i < model.num_nodes(); ++i) {
    figures.elastic.push_back(elastic.col(i).maxCoeff() / model.masses()[i]);
    figures.damper.push_back(damper.col(i).maxCoeff() / model.masses()[i]);
  }
  return figures;
}

double ScaleCutCellMasses(const Model& model, const std::vector<char>& cut,
                          const LocalStiffness& full_cell, double bound, ModelBuilder* builder) {
  const LocalStiffness figures = LocalStiffnessOf(model);
  // Per candidate, the mass (kg) that brings both figures down to the whole cells' (§7).
  std::vector<NodeIndex> nodes;
  std::vector<double> needed, mass;
  for (NodeIndex i = 0; i < model.num_nodes(); ++i) {
    const double m = model.masses()[i];
    const double need = m * std::max(figures.elastic[i] / full_cell.elastic[0],
                                     figures.damper[i] / full_cell.damper[0]);
    if (!cut[i] || need <= m) continue;
    nodes.push_back(i);
    mass.push_back(m);
    needed.push_back(need);
  }
  const double budget = bound * model.masses().sum();
  const double multiple = MultipleWithinBudget(needed, mass, budget);
  double added = 0.0;
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const double extra = std::max(0.0, needed[k] / multiple - mass[k]);
    if (extra > 0.0) builder->AddScaledMass(nodes[k], extra);
    added += extra;
  }
  builder->SetMassScaling(added, multiple > 1.0);
  return added;
}

bool ScaleCutCells(const Model& model, const OccupiedCells& cells, const Material& material,
                   const NodeCentredSurfaceOptions& surface, SpringLaw spring_law,
                   const PowerSpringLaw& power_law, ModelBuilder* builder) {
  const std::vector<char> cut = CutCells(cells, model.num_nodes());
  if (surface.mass_scaling == 0.0 || std::find(cut.begin(), cut.end(), 1) == cut.end()) {
    return false;
  }
  const LocalStiffness reference =
      FullCellFigures(material, cells.frame.unit, surface, spring_law, power_law);
  ScaleCutCellMasses(model, cut, reference, surface.mass_scaling, builder);
  return true;
}

}  // namespace msm_sim::core::lattice
