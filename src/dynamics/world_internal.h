#pragma once
// Private to msm_sim's World (world.cpp, step_loop.cpp, implicit_integrator.cpp): the argument
// checks its API and its stages share.

#include <cmath>
#include <stdexcept>
#include <string>

namespace msm_sim::core::internal {

/// Throws std::invalid_argument with `message` unless `condition` holds.
inline void Require(bool condition, const std::string& message) {
  if (!condition) throw std::invalid_argument(message);
}

inline bool Finite(double value) { return std::isfinite(value); }

}  // namespace msm_sim::core::internal
