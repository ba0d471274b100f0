#pragma once

namespace msm_sim::core {

/// Energies of one body (J). Gravitational energy is -m g . x (zero at the world origin). The
/// kinetic energy counts the restitution still pending from the last contacts (a node that has
/// just hit a surface is stopped until the next substep and carries its rebound there).
struct Energies {
  double kinetic = 0.0;
  double elastic = 0.0;  ///< springs plus eMSM dispersion (ForceEvaluator::ElasticEnergy)
  double gravitational = 0.0;
  double total() const { return kinetic + elastic + gravitational; }
};

}  // namespace msm_sim::core
