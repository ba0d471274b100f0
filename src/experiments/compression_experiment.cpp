#include "msm_sim/experiments/compression_experiment.h"

#include <cmath>

#include "msm_sim/experiments/hardy_stress.h"
#include "msm_sim/experiments/strain_probe.h"

namespace msm_sim::core {

namespace {

// Stress-corrected values from point probes at the centre (thesis 3.1): the Hardy stress and,
// where the probe finds a strain, E and nu from both (else NaN).
void MeasureAtCentre(const Model& model, const CompressionExperimentOptions& options,
                     const UniaxialCompression& compression, CompressionExperimentResult* result) {
  const auto& rest = model.rest_positions();
  const Eigen::Matrix3Xd& positions = compression.positions;
  const Eigen::Vector3d centre = 0.5 * options.body_size;
  const double a = model.characteristic_length();
  const StrainProbe probe(rest);
  const auto centre_strain = probe.StrainAt(centre, positions - rest, 0.5 * a);
  result->centre_stress = HardyStress(model, positions, compression.tensions, centre, 1.3 * a);
  if (!centre_strain) {
    result->poisson_stress_corrected = std::nan("");
    result->youngs_stress_corrected = std::nan("");
    return;
  }
  result->centre_strain = *centre_strain;
  // The formulas below take the compressed axis first: permute (ax, lat1, lat2) -> (x, y, z).
  const int ax = options.axis, lat1 = (ax + 1) % 3, lat2 = (ax + 2) % 3;
  Eigen::Matrix3d to_axis_first = Eigen::Matrix3d::Zero();
  to_axis_first(0, ax) = to_axis_first(1, lat1) = to_axis_first(2, lat2) = 1.0;
  const Eigen::Matrix3d e = to_axis_first * result->centre_strain * to_axis_first.transpose();
  const Eigen::Matrix3d s = to_axis_first * result->centre_stress * to_axis_first.transpose();
  result->poisson_stress_corrected = StressCorrectedPoisson(e, s);
  result->youngs_stress_corrected =
      (s(0, 0) - result->poisson_stress_corrected * (s(1, 1) + s(2, 2))) / e(0, 0);
}

}  // namespace

double StressCorrectedPoisson(const Eigen::Matrix3d& e, const Eigen::Matrix3d& s) {
  // From e_xx = (s_xx - nu (s_yy + s_zz)) / E and e_yy = (s_yy - nu (s_xx + s_zz)) / E.
  const double numerator = e(0, 0) * s(1, 1) - e(1, 1) * s(0, 0);
  const double denominator = e(0, 0) * (s(0, 0) + s(2, 2)) - e(1, 1) * (s(1, 1) + s(2, 2));
  return numerator / denominator;
}

CompressionExperimentResult RunCompressionExperiment(const Model& model,
                                                     const CompressionExperimentOptions& options) {
  const UniaxialCompression compression = MeasureUniaxialCompression(model, options);
  CompressionExperimentResult result;
  result.youngs_measured = compression.youngs;
  result.poisson_measured = compression.poisson;
  result.axial_force = compression.axial_force;
  result.end_nodes = compression.end_nodes;
  result.central_nodes = compression.central_nodes;
  result.solver = compression.solver;
  MeasureAtCentre(model, options, compression, &result);
  return result;
}

}  // namespace msm_sim::core
