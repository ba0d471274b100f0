#include "msm_sim/core/stable_time_step.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Core>

#include "msm_sim/core/force_evaluator.h"

namespace msm_sim::core {

double StableTimeStep(const Model& model, const StableTimeStepOptions& options) {
  if (!(options.safety > 0.0 && options.safety <= 1.0) ||
      !(options.min_compression > 0.0 && options.min_compression <= 1.0) ||
      !(options.damping_beta >= 0.0) || !std::isfinite(options.damping_beta)) {
    throw std::invalid_argument(
        "stable time step: need safety and min_compression in (0, 1] and damping >= 0");
  }
  const int n = model.num_nodes();
  // Free particles: nothing elastic limits the step.
  if (model.num_springs() == 0) return std::numeric_limits<double>::infinity();
  ForceEvaluator evaluator(model);
  evaluator.Linearize(model.rest_positions());
  const Eigen::Array<double, 1, Eigen::Dynamic> inverse_sqrt_mass =
      model.masses().transpose().array().rsqrt();
  // Power iteration on A = M^-1/2 K M^-1/2 from a deterministic start that has a component
  // along the highest modes (an alternating pattern).
  Eigen::Matrix3Xd v(3, n);
  for (int i = 0; i < n; ++i) {
    v.col(i) = Eigen::Vector3d(i % 2 ? 1.0 : -1.0, (i / 2) % 2 ? 1.0 : -0.7, (i % 3) - 1.1);
  }
  v /= v.norm();
  Eigen::Matrix3Xd kv(3, n);
  double lambda = 0.0;
  for (int iteration = 0; iteration < 200; ++iteration) {
    const Eigen::Matrix3Xd scaled = v.array().rowwise() * inverse_sqrt_mass;
    evaluator.ApplyStiffness(scaled, &kv);
    const Eigen::Matrix3Xd av = kv.array().rowwise() * inverse_sqrt_mass;
    const double next = av.norm();
    v = av / next;
    const bool converged = std::abs(next - lambda) <= 1e-4 * next;
    lambda = next;
    if (converged && iteration > 20) break;
  }
  // Carrier springs' tangent grows as (L0 / L)^2 under compression.
  const double stiffening = model.spring_law() == SpringLaw::kNonlinear
                                ? 1.0 / (options.min_compression * options.min_compression)
                                : 1.0;
  const double omega = std::sqrt(lambda * stiffening);
  const double zeta = 0.5 * options.damping_beta * omega;
  return options.safety * (2.0 / omega) * (std::sqrt(1.0 + zeta * zeta) - zeta);
}

}  // namespace msm_sim::core
