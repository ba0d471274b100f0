#pragma once

#include <Eigen/Core>

#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// Hardy's stress estimate at `point` (docs/physics.md §6, thesis 3.1.2): with a spherical probe of
/// radius R and volume V_p = 4/3 pi R^3,
///   sigma = (1 / V_p) sum_s t_s (r_s ⊗ r̂_s) B_s,
/// r_s the current spring vector, t_s its tension (> 0 stretched) and B_s the fraction of the
/// current spring segment inside the probe (linear bond). Tension is positive (Pa).
/// The thesis uses R = 1.3 ã. `tensions` are the springs' total tensions
/// (ForceEvaluator::total_tensions()). Preconditions: radius > 0; positions has N columns,
/// tensions one entry per spring.
Eigen::Matrix3d HardyStress(const Model& model, const Eigen::Matrix3Xd& positions,
                            const Eigen::VectorXd& tensions, const Eigen::Vector3d& point,
                            double radius);

/// Fraction of the segment [p0, p1] that lies inside the ball (centre, radius); 0 for a
/// degenerate segment.
double SegmentFractionInsideBall(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                 const Eigen::Vector3d& centre, double radius);

}  // namespace msm_sim::core
