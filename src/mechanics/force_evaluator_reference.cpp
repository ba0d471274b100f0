// ForceEvaluator's per-spring loops: the reference that the run kernels are checked against, and
// the evaluation of every model the run kernels do not take (random lattices, carrier springs,
// Baudet elements; docs/physics.md §3).

#include <cmath>
#include <type_traits>

#include "mechanics/share_plan.h"
#include "mechanics/spring_law_dispatch.h"
#include "msm_sim/mechanics/force_evaluator.h"

namespace msm_sim::core {

// The hot loops below work on raw, non-aliasing pointers: through Eigen column blocks of a
// matrix passed by pointer the compiler must assume every force store may change the positions
// or the model arrays, and reloads them (docs/design/speed-against-bullet.md).
namespace {

struct SpringArrays {
  const NodeIndex* __restrict a;
  const NodeIndex* __restrict b;
  const double* __restrict rest;
  const double* __restrict k;
};

SpringArrays Arrays(const Model& model) {
  return {model.spring_node_a().data(), model.spring_node_b().data(),
          model.spring_rest_length().data(), model.spring_stiffness().data()};
}

// Adds f * (x_b - x_a) to node a and subtracts it from node b.
inline void ApplyPair(double* __restrict forces, int a, int b, double f, const double r[3]) {
  for (int i = 0; i < 3; ++i) {
    forces[3 * a + i] += f * r[i];
    forces[3 * b + i] -= f * r[i];
  }
}

inline double Separation(const double* __restrict x, int a, int b, double r[3]) {
  for (int i = 0; i < 3; ++i) r[i] = x[3 * b + i] - x[3 * a + i];
  return std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
}

// The dashpot's tension beta k (v_b - v_a) . r / L (positive when the spring lengthens).
inline double DampingTension(const ForceEvaluator::Damping& damping, const SpringArrays& springs,
                             int s, const double r[3], double length) {
  const double* __restrict v = damping.velocities;
  const int a = springs.a[s], b = springs.b[s];
  double rate = 0.0;
  for (int i = 0; i < 3; ++i) rate += (v[3 * b + i] - v[3 * a + i]) * r[i];
  return damping.beta * springs.k[s] * rate / length;
}

}  // namespace

template <bool Damped, class Law>
void ForceEvaluator::PlainPass(const Law& law, const Eigen::Matrix3Xd& positions,
                               const Damping& damping, Eigen::Matrix3Xd* forces) {
  const SpringArrays springs = Arrays(*model_);
  const double* __restrict x = positions.data();
  double* __restrict total = totals_.model_order.data();
  plan_->ForSpringShares(model_->num_springs(), forces->data(), forces->size(),
                         [&](int begin, int end, double* __restrict f) {
                           for (int s = begin; s < end; ++s) {
                             double r[3];
                             const double length = Separation(x, springs.a[s], springs.b[s], r);
                             double t = law.Tension(springs.k[s], springs.rest[s], length);
                             if constexpr (Damped)
                               t += DampingTension(damping, springs, s, r, length);
                             total[s] = t;
                             ApplyPair(f, springs.a[s], springs.b[s], t / length, r);
                           }
                         });
}

template <class Law>
void ForceEvaluator::InflowPass(const Law& law, const Eigen::Matrix3Xd& positions) {
  const SpringArrays springs = Arrays(*model_);
  const double* __restrict x = positions.data();
  const double* __restrict inflow_a = dispersion_.inflow_a.data();
  const double* __restrict inflow_b = dispersion_.inflow_b.data();
  double* __restrict tensions = per_spring_.tensions.data();
  double* __restrict inverse_lengths = per_spring_.inverse_lengths.data();
  constexpr bool kWeighted = !std::is_same_v<Law, LinearSpringLaw>;
  if (kWeighted) per_spring_.tangent_ratios.resize(model_->num_springs());
  double* __restrict ratios = per_spring_.tangent_ratios.data();
  dispersion_.accumulator.setZero();
  plan_->ForSpringShares(
      model_->num_springs(), dispersion_.accumulator.data(), dispersion_.accumulator.size(),
      [&](int begin, int end, double* __restrict accumulator) {
        for (int s = begin; s < end; ++s) {
          double r[3];
          const double length = Separation(x, springs.a[s], springs.b[s], r);
          const double t = law.Tension(springs.k[s], springs.rest[s], length);
          tensions[s] = t;
          inverse_lengths[s] = 1.0 / length;
          if constexpr (kWeighted) {
            ratios[s] = law.TangentStiffness(springs.k[s], springs.rest[s], length) / springs.k[s];
          }
          accumulator[springs.a[s]] += inflow_a[s] * t;
          accumulator[springs.b[s]] += inflow_b[s] * t;
        }
      });
}

// Weighted (non-linear laws): the dispersed tension scaled by t' / k, which makes it the
// gradient of Phi = sum J^2 / (2 q W) for any law (docs/physics.md §3).
template <bool Damped, bool Weighted>
void ForceEvaluator::OutflowPass(const Eigen::Matrix3Xd& positions, const Damping& damping,
                                 Eigen::Matrix3Xd* forces) {
  const SpringArrays springs = Arrays(*model_);
  const double* __restrict x = positions.data();
  const double* __restrict g = dispersion_.per_weight.data();
  const double* __restrict outflow_a = dispersion_.outflow_a.data();
  const double* __restrict outflow_b = dispersion_.outflow_b.data();
  const double* __restrict tensions = per_spring_.tensions.data();
  const double* __restrict inverse_lengths = per_spring_.inverse_lengths.data();
  const double* __restrict ratios = per_spring_.tangent_ratios.data();
  double* __restrict total = totals_.model_order.data();
  plan_->ForSpringShares(
      model_->num_springs(), forces->data(), forces->size(),
      [&](int begin, int end, double* __restrict f) {
        for (int s = begin; s < end; ++s) {
          const int a = springs.a[s];
          const int b = springs.b[s];
          double t;
          if constexpr (Weighted) {
            t = tensions[s] + ratios[s] * (outflow_a[s] * g[a] + outflow_b[s] * g[b]);
          } else {
            t = tensions[s] + outflow_a[s] * g[a] + outflow_b[s] * g[b];
          }
          // Recomputing r from positions still in cache is cheaper than
          // streaming stored directions.
          double r[3];
          for (int i = 0; i < 3; ++i) r[i] = x[3 * b + i] - x[3 * a + i];
          if constexpr (Damped)
            t += DampingTension(damping, springs, s, r, 1.0 / inverse_lengths[s]);
          total[s] = t;
          ApplyPair(f, a, b, t * inverse_lengths[s], r);
        }
      });
}

void ForceEvaluator::CorrectionPass(const Eigen::Matrix3Xd& positions, Eigen::Matrix3Xd* forces) {
  const auto& a = model_->spring_node_a();
  const auto& b = model_->spring_node_b();
  const auto& rest = model_->spring_rest_length();
  const auto& edges = model_->correction_edges();
  const auto& coefficient = model_->correction_coefficients();
  for (std::size_t e = 0; e < edges.size(); ++e) {
    double r[12][3];
    double length[12];
    double elongation[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < 12; ++i) {
      const SpringIndex s = edges[e][i];
      length[i] = Separation(positions.data(), a[s], b[s], r[i]);
      elongation[i / 4] += length[i] - rest[s];
    }
    const double sum = elongation[0] + elongation[1] + elongation[2];
    for (int i = 0; i < 12; ++i) {
      const SpringIndex s = edges[e][i];
      const double tension = coefficient[e] * (sum - elongation[i / 4]);
      totals_.model_order[s] += tension;
      ApplyPair(forces->data(), a[s], b[s], tension / length[i], r[i]);
    }
  }
}

template <bool Damped>
void ForceEvaluator::AccumulatePerSpringImpl(const Eigen::Matrix3Xd& positions,
                                             const Damping& damping, Eigen::Matrix3Xd* forces) {
  totals_.scheduled = false;
  if (model_->dispersion_fraction() == 0.0) {
    internal::VisitSpringLaw(
        *model_, [&](const auto& law) { PlainPass<Damped>(law, positions, damping, forces); });
    if (!model_->correction_edges().empty()) CorrectionPass(positions, forces);
    if (barrier_) barrier_->AccumulateForces(positions, forces, &barrier_reference_);
    return;
  }
  // Two passes: the direct tensions fill the accumulators, then every spring applies its direct
  // plus dispersed tension at once.
  internal::VisitSpringLaw(*model_, [&](const auto& law) { InflowPass(law, positions); });
  dispersion_.per_weight = dispersion_.accumulator.cwiseProduct(dispersion_.inverse_star_weight);
  if (model_->spring_law() == SpringLaw::kLinear) {
    OutflowPass<Damped, false>(positions, damping, forces);
  } else {
    OutflowPass<Damped, true>(positions, damping, forces);
  }
  if (!model_->correction_edges().empty()) CorrectionPass(positions, forces);
  if (barrier_) barrier_->AccumulateForces(positions, forces, &barrier_reference_);
}

void ForceEvaluator::AccumulatePerSpring(const Eigen::Matrix3Xd& positions, const Damping& damping,
                                         Eigen::Matrix3Xd* forces) {
  if (damping.velocities != nullptr) {
    AccumulatePerSpringImpl<true>(positions, damping, forces);
  } else {
    AccumulatePerSpringImpl<false>(positions, damping, forces);
  }
}

}  // namespace msm_sim::core
