#pragma once

#include <vector>

namespace msm_sim::core {

/// Least-squares slope of y against x. Returns 0 when x has no spread (or fewer than 2 samples).
double LeastSquaresSlope(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace msm_sim::core
