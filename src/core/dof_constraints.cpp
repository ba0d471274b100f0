#include "msm_sim/core/dof_constraints.h"

namespace msm_sim::core {

std::vector<int> DofConstraints::FreeDofNumbering(int* num_free) const {
  std::vector<int> numbering(fixed_.size(), -1);
  int next = 0;
  for (std::size_t dof = 0; dof < fixed_.size(); ++dof) {
    if (!fixed_[dof]) numbering[dof] = next++;
  }
  *num_free = next;
  return numbering;
}

}  // namespace msm_sim::core
