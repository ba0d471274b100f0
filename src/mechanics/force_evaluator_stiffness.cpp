// ForceEvaluator's elastic energy and linearisation (the stiffness K = -d(forces)/d(positions)
// and its diagonal). The force passes, the hot loop of every step, are in force_evaluator.cpp
// and the files it names.

#include "msm_sim/mechanics/force_evaluator.h"

#include <algorithm>
#include <cstddef>

#include "mechanics/force_kernels.h"
#include "mechanics/share_plan.h"
#include "mechanics/single_precision_kernels.h"
#include "mechanics/spring_law_dispatch.h"

namespace msm_sim::core {

template <class Law>
double ForceEvaluator::EnergyImpl(const Law& law, const Eigen::Matrix3Xd& positions) const {
  const auto& a = model_->spring_node_a();
  const auto& b = model_->spring_node_b();
  const auto& rest = model_->spring_rest_length();
  const auto& k = model_->spring_stiffness();
  const double q = model_->dispersion_fraction();
  Eigen::VectorXd accumulator = Eigen::VectorXd::Zero(q != 0.0 ? model_->num_nodes() : 0);
  double energy = 0.0;
  for (int s = 0; s < model_->num_springs(); ++s) {
    const double length = (positions.col(b[s]) - positions.col(a[s])).norm();
    energy += law.Energy(k[s], rest[s], length);
    if (q != 0.0) {
      const double t = law.Tension(k[s], rest[s], length);
      accumulator[a[s]] += dispersion_.inflow_a[s] * t;
      accumulator[b[s]] += dispersion_.inflow_b[s] * t;
    }
  }
  // Phi = sum J^2 / (2 q W); dispersion_.inverse_star_weight holds 1 / W.
  if (q != 0.0) {
    energy += 0.5 / q * accumulator.cwiseAbs2().dot(dispersion_.inverse_star_weight);
  }
  const auto& edges = model_->correction_edges();
  for (std::size_t e = 0; e < edges.size(); ++e) {
    double elongation[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < 12; ++i) {
      const SpringIndex s = edges[e][i];
      elongation[i / 4] += (positions.col(b[s]) - positions.col(a[s])).norm() - rest[s];
    }
    energy += model_->correction_coefficients()[e] *
              (elongation[0] * elongation[1] + elongation[1] * elongation[2] +
               elongation[2] * elongation[0]);
  }
  return energy;
}

double ForceEvaluator::ElasticEnergy(const Eigen::Matrix3Xd& positions) const {
  const double springs = internal::VisitSpringLaw(
      *model_, [&](const auto& law) { return EnergyImpl(law, positions); });
  return barrier_ ? springs + barrier_->Energy(positions) : springs;
}

// With a non-linear law and dispersion, also the dispersed tension's slope at fixed g (g of the
// evaluation at `positions`), dropped where negative unless `exact`, as compressed springs'
// geometric term is (docs/physics.md §3, §7.1).
template <class Law>
void ForceEvaluator::LinearizeImpl(const Law& law, const Eigen::Matrix3Xd& positions, bool exact) {
  const auto& a = model_->spring_node_a();
  const auto& b = model_->spring_node_b();
  const auto& rest = model_->spring_rest_length();
  const auto& k = model_->spring_stiffness();
  const bool slopes =
      model_->dispersion_fraction() != 0.0 && model_->spring_law() != SpringLaw::kLinear;
  per_spring_.dispersed_slopes.resize(slopes ? model_->num_springs() : 0);
  const Eigen::VectorXd& g = dispersion_.per_weight;
  for (int s = 0; s < model_->num_springs(); ++s) {
    const Eigen::Vector3d r = positions.col(b[s]) - positions.col(a[s]);
    per_spring_.lengths[s] = r.norm();
    per_spring_.directions.col(s) = r / per_spring_.lengths[s];
    per_spring_.tangent_stiffness[s] = law.TangentStiffness(k[s], rest[s], per_spring_.lengths[s]);
    if (!slopes) continue;
    const double slope = law.Curvature(k[s], rest[s], per_spring_.lengths[s]) / k[s] *
                         (dispersion_.outflow_a[s] * g[a[s]] + dispersion_.outflow_b[s] * g[b[s]]);
    per_spring_.dispersed_slopes[s] = exact ? slope : std::max(slope, 0.0);
  }
}

void ForceEvaluator::Linearize(const Eigen::Matrix3Xd& positions, GeometricStiffness geometric) {
  if (runs_.springs) {
    LinearizeScheduled(positions, geometric == GeometricStiffness::kDropCompression);
  } else {
    LinearizePerSpring(positions, geometric);
  }
  if (barrier_) {
    barrier_positions_ = positions;
    barrier_active_ = barrier_->ActiveCorners(positions, &barrier_reference_);
    // Like compressed springs' geometric term, the barrier's curvature can make K indefinite.
    barrier_curvature_ = geometric == GeometricStiffness::kExact;
  }
}

void ForceEvaluator::LinearizePerSpring(const Eigen::Matrix3Xd& positions,
                                        GeometricStiffness geometric) {
  // The total tensions at `positions`, keeping the dispersion g of the caller's last evaluation.
  // Without a schedule there are no single-precision springs: this evaluation is in double.
  const Eigen::VectorXd saved_dispersion = dispersion_.per_weight;
  Eigen::Matrix3Xd scratch = Eigen::Matrix3Xd::Zero(3, model_->num_nodes());
  AccumulateForces(positions, &scratch);
  const int count = model_->num_springs();
  per_spring_.directions.resize(3, count);
  per_spring_.lengths.resize(count);
  per_spring_.tangent_stiffness.resize(count);
  const bool exact = geometric == GeometricStiffness::kExact;
  internal::VisitSpringLaw(*model_, [&](const auto& law) { LinearizeImpl(law, positions, exact); });
  dispersion_.per_weight = saved_dispersion;
  per_spring_.geometric_tensions =
      geometric == GeometricStiffness::kExact ? total_tensions() : total_tensions().cwiseMax(0.0);
}

void ForceEvaluator::RoundLinearization() {
  // Per slot of the float schedule: k, inflow a and b, outflow a and b (once), then u and T / L,
  // each scattered from the double schedule's order; a phantom's stay zero.
  const ScheduledSprings springs = runs_.springs->View();
  const std::vector<int>& slots = single_loops_.springs->scheduled_slots;
  const Eigen::Index count = model_->num_springs();
  const Eigen::Index num_slots = single_loops_.springs->num_slots();
  if (single_loops_.stiffness.size() != 9 * num_slots) {
    single_loops_.stiffness.setZero(9 * num_slots);
    const double* fixed[5] = {springs.stiffness, springs.inflow_a, springs.inflow_b,
                              springs.outflow_a, springs.outflow_b};
    for (int block = 0; block < 5; ++block) {
      for (Eigen::Index s = 0; s < count; ++s) {
        single_loops_.stiffness[block * num_slots + slots[s]] = static_cast<float>(fixed[block][s]);
      }
    }
  }
  for (int block = 5; block < 9; ++block) {
    const double* from = runs_.linearization.data() + (block - 5) * count;
    float* to = single_loops_.stiffness.data() + block * num_slots;
    for (Eigen::Index s = 0; s < count; ++s) to[slots[s]] = static_cast<float>(from[s]);
  }
}

void ForceEvaluator::ApplySingleStiffnessRuns(const Eigen::Matrix3Xd& v,
                                              Eigen::Matrix3Xd* out) const {
  const Eigen::Index n = model_->num_nodes();
  const Eigen::Index slots = single_loops_.springs->num_slots();
  const std::vector<SingleRun>& runs = single_loops_.springs->runs;
  // As the force loops: up to max_threads shares for 1,000 nodes or more. Each share takes a
  // contiguous part of the float schedule's runs (about equal in slots) and sums into its own K dv
  // and dJ, added in share order: the sums depend on the thread count only.
  const int shares = plan_->NodeShareCount();
  std::vector<int> first_run(shares + 1, static_cast<int>(runs.size()));
  for (int t = 0, r = 0, taken = 0; t < shares; ++t) {
    for (; r < static_cast<int>(runs.size()) && taken < slots * t / shares; ++r) {
      taken += runs[r].count;
    }
    first_run[t] = r;
  }
  // dv as float x, y, z blocks of N, then per share its K dv at the a ends and at the b ends
  // (3 N each) and its dJ at the a ends and at the b ends (N each).
  constexpr int kPart = 8;
  single_loops_.stiffness_arrays.resize(3 * n + kPart * n * shares);
  float* dv = single_loops_.stiffness_arrays.data();
  const auto part = [dv, n](int t) { return dv + 3 * n + kPart * n * t; };
  const double zero[3] = {0.0, 0.0, 0.0};
  ToSingleNodeArrays(v.data(), n, 0, n, zero, dv);
  const float* data = single_loops_.stiffness.data();
  const SingleScheduledStiffness springs{runs.data(),      data,
                                         data + slots,     data + 2 * slots,
                                         data + 3 * slots, data + 4 * slots,
                                         data + 5 * slots, data + 6 * slots,
                                         data + 7 * slots, data + 8 * slots};
  const bool disperse = model_->dispersion_fraction() != 0.0;
  internal::SharePlan::Run(shares, [&](int t) {
    float* product = part(t);
    std::fill(product, product + kPart * n, 0.0f);
    SingleStiffnessRuns(springs, first_run[t], first_run[t + 1], dv, n, product,
                        disperse ? product + 6 * n : nullptr);
  });
  if (disperse) {
    float* dg = part(0) + 6 * n;
    for (Eigen::Index i = 0; i < n; ++i) dg[i] += dg[n + i];
    for (int t = 1; t < shares; ++t) {
      const float* dj = part(t) + 6 * n;
      for (Eigen::Index i = 0; i < n; ++i) dg[i] += dj[i] + dj[n + i];
    }
    for (Eigen::Index i = 0; i < n; ++i) {
      dg[i] = static_cast<float>(dg[i] * dispersion_.inverse_star_weight[i]);  // dg = dJ / W
    }
    internal::SharePlan::Run(shares, [&](int t) {
      SingleDispersedStiffnessRuns(springs, first_run[t], first_run[t + 1], dg, n, part(t));
    });
  }
  out->resize(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (int d = 0; d < 3; ++d) {
      float sum = part(0)[d * n + i] + part(0)[(3 + d) * n + i];
      for (int t = 1; t < shares; ++t) sum += part(t)[d * n + i] + part(t)[(3 + d) * n + i];
      (*out)(d, i) = sum;
    }
  }
}

void ForceEvaluator::ApplyStiffnessRuns(const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd* out) const {
  if (single_loops_.springs) {
    ApplySingleStiffnessRuns(v, out);
    return;
  }
  const Eigen::Index n = model_->num_nodes();
  // dv, then the product at the a ends and at the b ends, x, y, z blocks of N each.
  runs_.stiffness_arrays.resize(9 * n);
  double* dv = runs_.stiffness_arrays.data();
  double* product = dv + 3 * n;
  ToNodeArrays(v.data(), n, dv);
  std::fill(product, product + 6 * n, 0.0);
  const ScheduledSprings springs = runs_.springs->View();
  const int runs = static_cast<int>(runs_.springs->schedule.runs.size());
  const ScheduledLinearization linearization =
      ScheduledLinearization::Of(runs_.linearization.data(), model_->num_springs());
  const MutableNodeArrays a_ends{product, product + n, product + 2 * n};
  const MutableNodeArrays b_ends{product + 3 * n, product + 4 * n, product + 5 * n};
  const bool disperse = model_->dispersion_fraction() != 0.0;
  if (disperse) runs_.accumulator_change.setZero(2 * n);
  double* change = runs_.accumulator_change.data();
  StiffnessRuns(springs, 0, runs, linearization, {dv, dv + n, dv + 2 * n}, a_ends, b_ends,
                disperse ? change : nullptr, disperse ? change + n : nullptr);
  if (disperse) {
    for (Eigen::Index i = 0; i < n; ++i) {
      change[i] = (change[i] + change[n + i]) * dispersion_.inverse_star_weight[i];  // dg = dJ / W
    }
    DispersedStiffnessRuns(springs, 0, runs, linearization, change, a_ends, b_ends);
  }
  out->setZero(3, n);
  AddNodeArrays(product, n, out->data());
  AddNodeArrays(product + 3 * n, n, out->data());
}

void ForceEvaluator::ApplyStiffness(const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd* out) const {
  ApplySpringStiffness(v, out);
  if (barrier_ && !barrier_active_.empty()) {
    barrier_->AddStiffnessProduct(barrier_positions_, barrier_active_, barrier_curvature_, v, out);
  }
}

void ForceEvaluator::ApplySpringStiffness(const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd* out) const {
  if (runs_.springs) {
    ApplyStiffnessRuns(v, out);
    return;
  }
  const auto& a = model_->spring_node_a();
  const auto& b = model_->spring_node_b();
  const bool disperse = model_->dispersion_fraction() != 0.0;
  out->setZero(3, model_->num_nodes());
  Eigen::VectorXd accumulator_change;
  if (disperse) accumulator_change.setZero(model_->num_nodes());
  // The force on a is T u (T total tension, u from a to b); its change is dT u + T du with
  // du = (dv - u (u . dv)) / L. K v = -d(force).
  for (int s = 0; s < model_->num_springs(); ++s) {
    const Eigen::Vector3d dv = v.col(b[s]) - v.col(a[s]);
    const Eigen::Vector3d u = per_spring_.directions.col(s);
    const double stretch_rate = u.dot(dv);
    const double dt = per_spring_.tangent_stiffness[s] * stretch_rate;
    const Eigen::Vector3d df =
        dt * u +
        (per_spring_.geometric_tensions[s] / per_spring_.lengths[s]) * (dv - u * stretch_rate);
    out->col(a[s]) -= df;
    out->col(b[s]) += df;
    if (disperse) {
      accumulator_change[a[s]] += dispersion_.inflow_a[s] * dt;
      accumulator_change[b[s]] += dispersion_.inflow_b[s] * dt;
    }
  }
  ApplyCorrectionStiffness(v, out);
  if (!disperse) return;
  const Eigen::VectorXd dg = accumulator_change.cwiseProduct(dispersion_.inverse_star_weight);
  const bool weighted = per_spring_.dispersed_slopes.size() != 0;
  const auto& k = model_->spring_stiffness();
  for (int s = 0; s < model_->num_springs(); ++s) {
    double dt_dispersed = dispersion_.outflow_a[s] * dg[a[s]] + dispersion_.outflow_b[s] * dg[b[s]];
    if (weighted) {
      // t* = (t' / k) (outflow . g): dt* = (t' / k) (outflow . dg) + slope dL.
      const double stretch_rate = per_spring_.directions.col(s).dot(v.col(b[s]) - v.col(a[s]));
      dt_dispersed = per_spring_.tangent_stiffness[s] / k[s] * dt_dispersed +
                     per_spring_.dispersed_slopes[s] * stretch_rate;
    }
    const Eigen::Vector3d df = dt_dispersed * per_spring_.directions.col(s);
    out->col(a[s]) -= df;
    out->col(b[s]) += df;
  }
}

void ForceEvaluator::ApplyCorrectionStiffness(const Eigen::Matrix3Xd& v,
                                              Eigen::Matrix3Xd* out) const {
  // The correction tensions' change: d tension_j = c sum_{i != j} dS_i, dS_i = sum u . dv over the
  // edges along i, applied along each edge (their own direction change is in the geometric term
  // of ApplyStiffness, since the total tensions include them).
  const auto& a = model_->spring_node_a();
  const auto& b = model_->spring_node_b();
  const auto& edges = model_->correction_edges();
  for (std::size_t e = 0; e < edges.size(); ++e) {
    double rate[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < 12; ++i) {
      const SpringIndex s = edges[e][i];
      rate[i / 4] += per_spring_.directions.col(s).dot(v.col(b[s]) - v.col(a[s]));
    }
    const double sum = rate[0] + rate[1] + rate[2];
    for (int i = 0; i < 12; ++i) {
      const SpringIndex s = edges[e][i];
      const Eigen::Vector3d df = model_->correction_coefficients()[e] * (sum - rate[i / 4]) *
                                 per_spring_.directions.col(s);
      out->col(a[s]) -= df;
      out->col(b[s]) += df;
    }
  }
}

Eigen::Matrix3Xd ForceEvaluator::StiffnessDiagonal() const {
  Eigen::Matrix3Xd diagonal = SpringStiffnessDiagonal();
  if (barrier_) barrier_->AddStiffnessDiagonal(barrier_positions_, barrier_active_, &diagonal);
  return diagonal;
}

Eigen::Matrix3Xd ForceEvaluator::SpringStiffnessDiagonal() const {
  if (runs_.springs) return ScheduledStiffnessDiagonal();
  const auto& a = model_->spring_node_a();
  const auto& b = model_->spring_node_b();
  const bool disperse = model_->dispersion_fraction() != 0.0;
  const bool weighted = per_spring_.dispersed_slopes.size() != 0;
  const auto& k = model_->spring_stiffness();
  const int n = model_->num_nodes();
  Eigen::Matrix3Xd diagonal = Eigen::Matrix3Xd::Zero(3, n);
  // Dispersion couples node a to itself through J_a: (1 / W_a) s1 s2^T with s1 = sum (w / L0) u
  // and s2 = sum (q v L0) k' u over the springs at a (u pointing away from a).
  Eigen::Matrix3Xd s1 = Eigen::Matrix3Xd::Zero(3, n);
  Eigen::Matrix3Xd s2 = Eigen::Matrix3Xd::Zero(3, n);
  for (int s = 0; s < model_->num_springs(); ++s) {
    const Eigen::Vector3d u = per_spring_.directions.col(s);
    const Eigen::Vector3d u2 = u.cwiseProduct(u);
    const double kt = per_spring_.tangent_stiffness[s];
    const double geometric = per_spring_.geometric_tensions[s] / per_spring_.lengths[s];
    const Eigen::Vector3d block = kt * u2 + geometric * (Eigen::Vector3d::Ones() - u2);
    diagonal.col(a[s]) += block;
    diagonal.col(b[s]) += block;
    if (disperse) {
      // The outflow weighted by t' / k and the dispersed tension's own slope (non-linear laws).
      const double ratio = weighted ? kt / k[s] : 1.0;
      if (weighted) {
        diagonal.col(a[s]) += per_spring_.dispersed_slopes[s] * u2;
        diagonal.col(b[s]) += per_spring_.dispersed_slopes[s] * u2;
      }
      // And through J of the other end, which holds this spring's own inflow.
      diagonal.col(a[s]) += ratio * kt * dispersion_.outflow_b[s] * dispersion_.inflow_b[s] *
                            dispersion_.inverse_star_weight[b[s]] * u2;
      diagonal.col(b[s]) += ratio * kt * dispersion_.outflow_a[s] * dispersion_.inflow_a[s] *
                            dispersion_.inverse_star_weight[a[s]] * u2;
      s1.col(a[s]) += ratio * dispersion_.outflow_a[s] * u;
      s1.col(b[s]) -= ratio * dispersion_.outflow_b[s] * u;
      s2.col(a[s]) += dispersion_.inflow_a[s] * kt * u;
      s2.col(b[s]) -= dispersion_.inflow_b[s] * kt * u;
    }
  }
  if (disperse) {
    for (int i = 0; i < n; ++i) {
      diagonal.col(i) += dispersion_.inverse_star_weight[i] * s1.col(i).cwiseProduct(s2.col(i));
    }
  }
  AddCorrectionStiffnessDiagonal(&diagonal);
  return diagonal;
}

void ForceEvaluator::AddCorrectionStiffnessDiagonal(Eigen::Matrix3Xd* diagonal) const {
  // At a node, an edge along one axis responds to the elongation of the element's edges along
  // the other axes through the same node: c sum w_f w_e over such pairs (f, e), with w pointing
  // away from the node.
  const auto& a = model_->spring_node_a();
  const auto& b = model_->spring_node_b();
  const auto& edges = model_->correction_edges();
  for (std::size_t e = 0; e < edges.size(); ++e) {
    for (int f = 0; f < 12; ++f) {
      for (int g = 0; g < 12; ++g) {
        if (f / 4 == g / 4) continue;
        const SpringIndex sf = edges[e][f];
        const SpringIndex sg = edges[e][g];
        for (const NodeIndex node : {a[sf], b[sf]}) {
          if (node != a[sg] && node != b[sg]) continue;
          const Eigen::Vector3d wf = (node == a[sf] ? 1.0 : -1.0) * per_spring_.directions.col(sf);
          const Eigen::Vector3d wg = (node == a[sg] ? 1.0 : -1.0) * per_spring_.directions.col(sg);
          diagonal->col(node) += model_->correction_coefficients()[e] * wf.cwiseProduct(wg);
        }
      }
    }
  }
}

}  // namespace msm_sim::core
