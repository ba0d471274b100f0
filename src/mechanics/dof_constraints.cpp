#include "msm_sim/mechanics/dof_constraints.h"

namespace msm_sim::core {

std::vector<int> DofConstraints::FreeDofs() const {
  std::vector<int> free_dofs;
  for (std::size_t dof = 0; dof < fixed_.size(); ++dof) {
    if (!fixed_[dof]) free_dofs.push_back(static_cast<int>(dof));
  }
  return free_dofs;
}

}  // namespace msm_sim::core
