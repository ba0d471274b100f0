#pragma once
// The implicit integrator tests' blocks and World options (test_implicit_integrator.cpp,
// test_implicit_contacts.cpp).
#include <memory>

#include <Eigen/Core>

#include "msm_sim/dynamics/world_options.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

// The material (E 200 kPa, rho 1100) in a box from the origin.
inline std::shared_ptr<const Model> Block(const Eigen::Vector3d& size, double spacing,
                                          double poisson, SpringLaw law = SpringLaw::kLinear) {
  CubicLatticeOptions options;
  options.size = size;
  options.lattice.spacing = spacing;
  options.lattice.spring_law = law;
  return std::make_shared<Model>(
      BuildCubicLattice(Material::FromYoungsPoisson(2e5, poisson, 1100.0), options));
}

inline WorldOptions ImplicitOptions(double max_substep, double gravity = 0.0) {
  WorldOptions options;
  options.integrator = Integrator::kImplicit;
  options.implicit_max_substep = max_substep;
  options.gravity = Eigen::Vector3d(0.0, 0.0, -gravity);
  return options;
}

}  // namespace msm_sim::core
