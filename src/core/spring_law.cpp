#include "msm_sim/core/spring_law.h"

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
  return false;
}

const char* SpringLawName(SpringLaw law) {
  return law == SpringLaw::kLinear ? "linear" : "nonlinear";
}

}  // namespace msm_sim::core
