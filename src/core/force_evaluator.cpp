#include "msm_sim/core/force_evaluator.h"

namespace msm_sim::core {

ForceEvaluator::ForceEvaluator(const Model& model, DispersionPasses passes)
    : model_(model), passes_(passes) {
  const int n = model.num_nodes();
  // Star weight W of every node: the sum of its springs' outflow weights (the spring count b
  // when every weight is 1, as in the eMSM paper).
  Eigen::VectorXd star_weight = Eigen::VectorXd::Zero(n);
  for (int s = 0; s < model.num_springs(); ++s) {
    star_weight[model.spring_node_a()[s]] += model.outflow_weight_a()[s];
    star_weight[model.spring_node_b()[s]] += model.outflow_weight_b()[s];
  }
  inverse_star_weight_.resize(n);
  for (int i = 0; i < n; ++i) {
    inverse_star_weight_[i] = star_weight[i] > 0.0 ? 1.0 / star_weight[i] : 0.0;
  }
  const int s = model.num_springs();
  total_tensions_.setZero(s);
  accumulator_.setZero(n);
  previous_accumulator_.setZero(n);
  directions_.setZero(3, s);
  lengths_.setZero(s);
  tangent_stiffness_.setZero(s);
}

double ForceEvaluator::DispersedTension(const Eigen::VectorXd& accumulator, int s) const {
  const int a = model_.spring_node_a()[s];
  const int b = model_.spring_node_b()[s];
  return (model_.outflow_weight_a()[s] * accumulator[a] * inverse_star_weight_[a] +
          model_.outflow_weight_b()[s] * accumulator[b] * inverse_star_weight_[b]) /
         model_.spring_rest_length()[s];
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
      accumulator_[a[s]] += model_.inflow_weight_a()[s] * inflow;
      accumulator_[b[s]] += model_.inflow_weight_b()[s] * inflow;
      if (one_pass_dispersion) total += DispersedTension(previous_accumulator_, s);
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
  for (int s = 0; s < model_.num_springs(); ++s) {
    const double dispersed = DispersedTension(accumulator_, s);
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
      accumulator_change[a[s]] += model_.inflow_weight_a()[s] * q * rest[s] * dt;
      accumulator_change[b[s]] += model_.inflow_weight_b()[s] * q * rest[s] * dt;
    }
  }
  if (q == 0.0) return;
  for (int s = 0; s < model_.num_springs(); ++s) {
    const double dt_dispersed = DispersedTension(accumulator_change, s);
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
      // t*_s = (w_a J_a / W_a + w_b J_b / W_b) / L0 depends on x_a through J_b (this spring's
      // inflow at b) and through J_a (every spring at a): the latter is the outer product
      // (q / W_a) s1 s2^T with s1 = sum w u / L0, s2 = sum v L0 k' u (u pointing away).
      const double wa = model_.outflow_weight_a()[s] * inverse_star_weight_[a[s]];
      const double wb = model_.outflow_weight_b()[s] * inverse_star_weight_[b[s]];
      diagonal.col(a[s]) += q * kt * wb * model_.inflow_weight_b()[s] * u2;
      diagonal.col(b[s]) += q * kt * wa * model_.inflow_weight_a()[s] * u2;
      s1.col(a[s]) += model_.outflow_weight_a()[s] * u / rest[s];
      s1.col(b[s]) -= model_.outflow_weight_b()[s] * u / rest[s];
      s2.col(a[s]) += model_.inflow_weight_a()[s] * rest[s] * kt * u;
      s2.col(b[s]) -= model_.inflow_weight_b()[s] * rest[s] * kt * u;
    }
  }
  if (q != 0.0) {
    for (int i = 0; i < n; ++i) {
      diagonal.col(i) += q * inverse_star_weight_[i] * s1.col(i).cwiseProduct(s2.col(i));
    }
  }
  return diagonal;
}

}  // namespace msm_sim::core
