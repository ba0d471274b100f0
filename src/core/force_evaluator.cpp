#include "msm_sim/core/force_evaluator.h"

namespace msm_sim::core {

ForceEvaluator::ForceEvaluator(const Model& model, DispersionPasses passes)
    : model_(model), passes_(passes) {
  const int n = model.num_nodes();
  inverse_spring_count_.resize(n);
  for (int i = 0; i < n; ++i) {
    const int b = model.num_incident_springs(i);
    inverse_spring_count_[i] = b > 0 ? 1.0 / b : 0.0;
  }
  const int s = model.num_springs();
  total_tensions_.setZero(s);
  accumulator_.setZero(n);
  previous_accumulator_.setZero(n);
  directions_.setZero(3, s);
  lengths_.setZero(s);
  tangent_stiffness_.setZero(s);
}

template <SpringLaw Law>
double ForceEvaluator::DirectPass(const Eigen::Matrix3Xd& positions, Eigen::Matrix3Xd* forces,
                                  bool one_pass_dispersion) {
  const auto& a = model_.spring_node_a();
  const auto& b = model_.spring_node_b();
  const auto& rest = model_.spring_rest_length();
  const auto& k = model_.spring_stiffness();
  const double q = model_.dispersion_fraction();
  const bool disperse = q != 0.0;
  if (disperse) accumulator_.setZero();
  double energy = 0.0;
  for (int s = 0; s < model_.num_springs(); ++s) {
    const Eigen::Vector3d r = positions.col(b[s]) - positions.col(a[s]);
    const double length = r.norm();
    const Eigen::Vector3d u = r / length;
    const double t = SpringTension<Law>(k[s], rest[s], length);
    energy += SpringEnergy<Law>(k[s], rest[s], length);
    double total = t;
    if (disperse) {
      const double inflow = q * rest[s] * t;
      accumulator_[a[s]] += inflow;
      accumulator_[b[s]] += inflow;
      if (one_pass_dispersion) {
        total += (previous_accumulator_[a[s]] * inverse_spring_count_[a[s]] +
                  previous_accumulator_[b[s]] * inverse_spring_count_[b[s]]) /
                 rest[s];
      }
    }
    total_tensions_[s] = total;
    if (disperse) directions_.col(s) = u;  // reused by the second pass
    const Eigen::Vector3d f = total * u;
    forces->col(a[s]) += f;
    forces->col(b[s]) -= f;
  }
  return energy;
}

void ForceEvaluator::DispersionPass(Eigen::Matrix3Xd* forces) {
  const auto& a = model_.spring_node_a();
  const auto& b = model_.spring_node_b();
  const auto& rest = model_.spring_rest_length();
  for (int s = 0; s < model_.num_springs(); ++s) {
    const double dispersed = (accumulator_[a[s]] * inverse_spring_count_[a[s]] +
                              accumulator_[b[s]] * inverse_spring_count_[b[s]]) /
                             rest[s];
    total_tensions_[s] += dispersed;
    const Eigen::Vector3d f = dispersed * directions_.col(s);
    forces->col(a[s]) += f;
    forces->col(b[s]) -= f;
  }
}

double ForceEvaluator::AccumulateForces(const Eigen::Matrix3Xd& positions,
                                        Eigen::Matrix3Xd* forces) {
  const bool disperse = model_.dispersion_fraction() != 0.0;
  const bool one_pass =
      disperse && passes_ == DispersionPasses::kOnePass && has_previous_accumulator_;
  const double energy = model_.spring_law() == SpringLaw::kLinear
                            ? DirectPass<SpringLaw::kLinear>(positions, forces, one_pass)
                            : DirectPass<SpringLaw::kNonlinear>(positions, forces, one_pass);
  if (disperse) {
    if (!one_pass) DispersionPass(forces);
    previous_accumulator_.swap(accumulator_);
    has_previous_accumulator_ = true;
  }
  return energy;
}

template <SpringLaw Law>
void ForceEvaluator::LinearizeImpl(const Eigen::Matrix3Xd& positions) {
  const auto& a = model_.spring_node_a();
  const auto& b = model_.spring_node_b();
  const auto& rest = model_.spring_rest_length();
  const auto& k = model_.spring_stiffness();
  for (int s = 0; s < model_.num_springs(); ++s) {
    const Eigen::Vector3d r = positions.col(b[s]) - positions.col(a[s]);
    lengths_[s] = r.norm();
    directions_.col(s) = r / lengths_[s];
    tangent_stiffness_[s] = SpringTangentStiffness<Law>(k[s], rest[s], lengths_[s]);
  }
}

void ForceEvaluator::Linearize(const Eigen::Matrix3Xd& positions) {
  // Two-pass forces at `positions` give directions, tensions and dispersed tensions.
  Eigen::Matrix3Xd scratch = Eigen::Matrix3Xd::Zero(3, model_.num_nodes());
  const DispersionPasses saved = passes_;
  passes_ = DispersionPasses::kTwoPass;
  const bool had_previous = has_previous_accumulator_;
  const Eigen::VectorXd previous = previous_accumulator_;
  AccumulateForces(positions, &scratch);
  passes_ = saved;
  // Keep the one-pass history of the caller's simulation untouched.
  previous_accumulator_ = previous;
  has_previous_accumulator_ = had_previous;
  if (model_.spring_law() == SpringLaw::kLinear) {
    LinearizeImpl<SpringLaw::kLinear>(positions);
  } else {
    LinearizeImpl<SpringLaw::kNonlinear>(positions);
  }
}

void ForceEvaluator::ApplyStiffness(const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd* out) const {
  const auto& a = model_.spring_node_a();
  const auto& b = model_.spring_node_b();
  const auto& rest = model_.spring_rest_length();
  const double q = model_.dispersion_fraction();
  out->setZero(3, model_.num_nodes());
  Eigen::VectorXd accumulator_change;
  if (q != 0.0) accumulator_change.setZero(model_.num_nodes());
  // The force on a is T u (T total tension, u from a to b); its change is dT u + T du with
  // du = (dv - u (u . dv)) / L. K v = -d(force).
  for (int s = 0; s < model_.num_springs(); ++s) {
    const Eigen::Vector3d dv = v.col(b[s]) - v.col(a[s]);
    const Eigen::Vector3d u = directions_.col(s);
    const double stretch_rate = u.dot(dv);
    const double dt = tangent_stiffness_[s] * stretch_rate;
    const Eigen::Vector3d df =
        dt * u + (total_tensions_[s] / lengths_[s]) * (dv - u * stretch_rate);
    out->col(a[s]) -= df;
    out->col(b[s]) += df;
    if (q != 0.0) {
      accumulator_change[a[s]] += q * rest[s] * dt;
      accumulator_change[b[s]] += q * rest[s] * dt;
    }
  }
  if (q == 0.0) return;
  for (int s = 0; s < model_.num_springs(); ++s) {
    const double dt_dispersed = (accumulator_change[a[s]] * inverse_spring_count_[a[s]] +
                                 accumulator_change[b[s]] * inverse_spring_count_[b[s]]) /
                                rest[s];
    const Eigen::Vector3d df = dt_dispersed * directions_.col(s);
    out->col(a[s]) -= df;
    out->col(b[s]) += df;
  }
}

Eigen::Matrix3Xd ForceEvaluator::StiffnessDiagonal() const {
  const auto& a = model_.spring_node_a();
  const auto& b = model_.spring_node_b();
  const auto& rest = model_.spring_rest_length();
  const double q = model_.dispersion_fraction();
  const int n = model_.num_nodes();
  Eigen::Matrix3Xd diagonal = Eigen::Matrix3Xd::Zero(3, n);
  // Dispersion couples node a to itself through J_a: (q / b_a) s1 s2^T with
  // s1 = sum u / L0 and s2 = sum L0 k' u over the springs at a (u pointing away from a).
  Eigen::Matrix3Xd s1 = Eigen::Matrix3Xd::Zero(3, n);
  Eigen::Matrix3Xd s2 = Eigen::Matrix3Xd::Zero(3, n);
  for (int s = 0; s < model_.num_springs(); ++s) {
    const Eigen::Vector3d u = directions_.col(s);
    const Eigen::Vector3d u2 = u.cwiseProduct(u);
    const double kt = tangent_stiffness_[s];
    const double geometric = total_tensions_[s] / lengths_[s];
    Eigen::Vector3d block = kt * u2 + geometric * (Eigen::Vector3d::Ones() - u2);
    diagonal.col(a[s]) += block;
    diagonal.col(b[s]) += block;
    if (q != 0.0) {
      // Through J of the other end node.
      diagonal.col(a[s]) += q * kt * inverse_spring_count_[b[s]] * u2;
      diagonal.col(b[s]) += q * kt * inverse_spring_count_[a[s]] * u2;
      s1.col(a[s]) += u / rest[s];
      s1.col(b[s]) -= u / rest[s];
      s2.col(a[s]) += rest[s] * kt * u;
      s2.col(b[s]) -= rest[s] * kt * u;
    }
  }
  if (q != 0.0) {
    for (int i = 0; i < n; ++i) {
      diagonal.col(i) += q * inverse_spring_count_[i] * s1.col(i).cwiseProduct(s2.col(i));
    }
  }
  return diagonal;
}

}  // namespace msm_sim::core
