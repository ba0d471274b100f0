#include "msm_sim/core/spring_forces.h"

namespace msm_sim::core {

void ComputeSpringTensions(const Model& model, const Eigen::Matrix3Xd& positions,
                           Eigen::VectorXd* tensions) {
  const int num_springs = model.num_springs();
  tensions->resize(num_springs);
  const auto& a = model.spring_node_a();
  const auto& b = model.spring_node_b();
  const auto& rest = model.spring_rest_length();
  const auto& k = model.spring_stiffness();
  for (int s = 0; s < num_springs; ++s) {
    const double length = (positions.col(b[s]) - positions.col(a[s])).norm();
    (*tensions)[s] = k[s] * (length - rest[s]);
  }
}

double AccumulateSpringForces(const Model& model, const Eigen::Matrix3Xd& positions,
                              Eigen::Matrix3Xd* forces) {
  const int num_springs = model.num_springs();
  const auto& a = model.spring_node_a();
  const auto& b = model.spring_node_b();
  const auto& rest = model.spring_rest_length();
  const auto& k = model.spring_stiffness();
  double energy = 0.0;
  for (int s = 0; s < num_springs; ++s) {
    const Eigen::Vector3d r = positions.col(b[s]) - positions.col(a[s]);
    const double length = r.norm();
    const double stretch = length - rest[s];
    const double tension = k[s] * stretch;
    const Eigen::Vector3d f = (tension / length) * r;  // pulls a towards b when stretched
    forces->col(a[s]) += f;
    forces->col(b[s]) -= f;
    energy += 0.5 * k[s] * stretch * stretch;
  }
  return energy;
}

void AppendTangentStiffness(const Model& model, const Eigen::Matrix3Xd& positions,
                            const std::vector<int>& dof_to_unknown,
                            std::vector<Eigen::Triplet<double>>* triplets) {
  const int num_springs = model.num_springs();
  const auto& a = model.spring_node_a();
  const auto& b = model.spring_node_b();
  const auto& rest = model.spring_rest_length();
  const auto& k = model.spring_stiffness();
  for (int s = 0; s < num_springs; ++s) {
    const Eigen::Vector3d r = positions.col(b[s]) - positions.col(a[s]);
    const double length = r.norm();
    const Eigen::Vector3d u = r / length;
    const double tension = k[s] * (length - rest[s]);
    const double geometric = tension / length;
    const Eigen::Matrix3d block =
        (k[s] - geometric) * u * u.transpose() + geometric * Eigen::Matrix3d::Identity();
    const int nodes[2] = {a[s], b[s]};
    for (int p = 0; p < 2; ++p) {
      for (int q = 0; q < 2; ++q) {
        const double sign = (p == q) ? 1.0 : -1.0;
        for (int i = 0; i < 3; ++i) {
          const int row = dof_to_unknown[3 * nodes[p] + i];
          if (row < 0) continue;
          for (int j = 0; j < 3; ++j) {
            const int col = dof_to_unknown[3 * nodes[q] + j];
            if (col < 0) continue;
            triplets->emplace_back(row, col, sign * block(i, j));
          }
        }
      }
    }
  }
}

}  // namespace msm_sim::core
