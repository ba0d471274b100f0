#pragma once

#include <stdexcept>

#include "msm_sim/material/power_spring_law.h"
#include "msm_sim/material/spring_law.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core::internal {

/// Calls f with the model's spring law as a law type (LinearSpringLaw, CarrierSpringLaw or the
/// model's PowerSpringLaw; docs/physics.md §4, §4.1): the one place the per-spring loops choose
/// their law, so that each loop is compiled once per law with no test per spring.
template <class F>
decltype(auto) VisitSpringLaw(const Model& model, F&& f) {
  switch (model.spring_law()) {
    case SpringLaw::kLinear:
      return f(LinearSpringLaw{});
    case SpringLaw::kNonlinear:
      return f(CarrierSpringLaw{});
    case SpringLaw::kPower:
      return f(model.power_spring_law());
  }
  throw std::logic_error("VisitSpringLaw: unknown spring law");
}

}  // namespace msm_sim::core::internal
