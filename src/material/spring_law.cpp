#include "msm_sim/material/spring_law.h"

namespace msm_sim::core {

bool ParseSpringLaw(const std::string& name, SpringLaw* law) {
  if (name == "linear") {
    *law = SpringLaw::kLinear;
    return true;
  }
  if (name == "nonlinear") {
    *law = SpringLaw::kNonlinear;
    return true;
  }
  if (name == "power") {
    *law = SpringLaw::kPower;
    return true;
  }
  return false;
}

}  // namespace msm_sim::core
