#include "msm_sim/material/extended_msm.h"

namespace msm_sim::core {

double DispersionRatio(double poisson_ratio) {
  return 3.0 * (4.0 * poisson_ratio - 1.0) / (5.0 * (1.0 - 2.0 * poisson_ratio));
}

double PoissonFromDispersionRatio(double dispersion_ratio) {
  const double s = 5.0 * dispersion_ratio / 3.0;
  return (1.0 + s) / (2.0 * (2.0 + s));
}

}  // namespace msm_sim::core
