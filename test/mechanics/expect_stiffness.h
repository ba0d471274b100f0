#pragma once

#include <functional>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "msm_sim/mechanics/force_evaluator.h"

namespace msm_sim::core {

/// Linearizes `evaluator` at x and checks its ApplyStiffness and StiffnessDiagonal against
/// central differences of `forces` (the internal forces the evaluator computes, from a fresh
/// evaluation at the given positions) at the given DOFs.
inline void ExpectStiffnessIsTheForcesDerivative(
    ForceEvaluator* evaluator,
    const std::function<Eigen::Matrix3Xd(const Eigen::Matrix3Xd&)>& forces,
    const Eigen::Matrix3Xd& x, const std::vector<int>& dofs) {
  evaluator->Linearize(x);
  const Eigen::Matrix3Xd diagonal = evaluator->StiffnessDiagonal();
  const double h = 1e-7;
  for (const int dof : dofs) {
    Eigen::Matrix3Xd xp = x, xm = x;
    xp.data()[dof] += h;
    xm.data()[dof] -= h;
    const Eigen::Matrix3Xd column = -(forces(xp) - forces(xm)) / (2 * h);
    Eigen::Matrix3Xd unit = Eigen::Matrix3Xd::Zero(3, x.cols());
    unit.data()[dof] = 1.0;
    Eigen::Matrix3Xd analytic;
    evaluator->ApplyStiffness(unit, &analytic);
    ASSERT_LT((column - analytic).norm(), 1e-5 * (1.0 + analytic.norm())) << "dof " << dof;
    ASSERT_NEAR(diagonal.data()[dof], analytic.data()[dof], 1e-6 * (1.0 + analytic.norm()))
        << "dof " << dof;
  }
}

}  // namespace msm_sim::core
