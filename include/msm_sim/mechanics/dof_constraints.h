#pragma once

#include <cstdint>
#include <vector>

#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// Which degrees of freedom (node, axis) a static solve must keep where they are.
///
/// A prescribed displacement is expressed by moving the node to its target position before the
/// solve and fixing the corresponding DOFs. DOFs are numbered dof = 3 * node + axis.
class DofConstraints {
 public:
  explicit DofConstraints(int num_nodes) : fixed_(3 * static_cast<std::size_t>(num_nodes), 0) {}

  void FixNode(NodeIndex node) {
    for (int axis = 0; axis < 3; ++axis) FixDof(node, axis);
  }
  /// Precondition: 0 <= node < num_nodes, 0 <= axis < 3.
  void FixDof(NodeIndex node, int axis) { fixed_[3 * static_cast<std::size_t>(node) + axis] = 1; }

  bool is_fixed(int dof) const { return fixed_[dof] != 0; }

  /// The free DOFs in increasing order.
  std::vector<int> FreeDofs() const;

 private:
  std::vector<std::uint8_t> fixed_;
};

}  // namespace msm_sim::core
