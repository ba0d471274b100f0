// Self-calibration of random lattices (docs/physics.md §2.2): the calibration sum k L^2 = 15 V mu
// plus q(nu) assumes affine deformation, which a disordered network does not follow; how far it
// misses depends on its connectivity <S>. Measuring a representative block with the same
// statistics and correcting q and k makes the result independent of <S>.

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "msm_sim/lattice/random_lattice_builder.h"
#include "msm_sim/material/extended_msm.h"
#include "msm_sim/mechanics/uniaxial_compression.h"

namespace msm_sim::core {
namespace {

// Strain of the virtual test: small enough that geometric non-linearity (an E deficit in
// proportion to the strain, docs/design/node-centred-lattices.md) does not enter the correction,
// which is for the small-strain moduli.
constexpr double kCalibrationStrain = 1e-3;
// Measured nu this close to the target ends the secant iteration.
constexpr double kPoissonTolerance = 0.002;
// Compression measurements at most: the first, then secant steps.
constexpr int kMaxMeasurements = 3;
// Largest change of log(1 + Q) per secant step.
const double kMaxLogStep = std::log(2.0);

struct Reading {
  double log_ratio;           // x = log(1 + Q) the block was built with
  double measured_log_ratio;  // y = log(1 + Q(nu measured))
  double youngs;
  double poisson;
};

// Builds the representative block with dispersion fraction q and no stiffness correction and
// measures it. Throws std::runtime_error if the static solve does not converge.
Reading Measure(const Material& material, const RandomLatticeOptions& block, double q) {
  RandomLatticeOptions options = block;
  options.calibration = RandomSelfCalibration{1.0, q};
  const Model model = BuildRandomLattice(material, options);
  UniaxialCompressionOptions compression;
  compression.body_size = options.size;
  compression.strain = kCalibrationStrain;
  const UniaxialCompression result = MeasureUniaxialCompression(model, compression);
  if (!result.solver.converged) {
    throw std::runtime_error(
        "random lattice self-calibration: the representative block's "
        "static solve did not converge: " +
        result.solver.message);
  }
  // nu of an isotropic solid lies in (-1, 1/2); a reading outside (noise) is clamped so that
  // Q(nu) stays finite.
  const double nu = std::clamp(result.poisson, -0.999, 0.4999);
  return Reading{std::log1p(2.0 * q), std::log1p(DispersionRatio(nu)), result.youngs,
                 result.poisson};
}

// The next x = log(1 + Q) to try: a secant step through the last two readings (the first step
// assumes slope 1: the network's bulk modulus moves in proportion to 1 + Q).
double NextLogRatio(const Reading& last, const Reading* previous, double target) {
  double slope = 1.0;
  if (previous != nullptr) {
    const double dx = last.log_ratio - previous->log_ratio;
    const double dy = last.measured_log_ratio - previous->measured_log_ratio;
    // A flat or reversed response (noise) would send the step far away; keep slope 1 then.
    if (dx != 0.0 && dy / dx > 0.2) slope = dy / dx;
  }
  // Near nu = 1/2, nu hardly moves with Q and a noisy reading would ask for a huge Q (q = 180
  // was seen, whose solve did not converge): at most a factor 2 in 1 + Q per step.
  const double step =
      std::clamp((target - last.measured_log_ratio) / slope, -kMaxLogStep, kMaxLogStep);
  return last.log_ratio + step;
}

}  // namespace

SelfCalibrationConditions RandomSelfCalibrationConditions(const Material& material,
                                                          const RandomLatticeOptions& options) {
  SelfCalibrationConditions conditions;
  conditions.lattice = SelfCalibrationConditions::kRandomLattice;
  conditions.spacing = options.lattice.spacing;
  conditions.poisson = material.poisson_ratio();
  conditions.min_distance = options.min_distance;
  conditions.max_distance = options.max_distance;
  conditions.stiffness_law = options.stiffness_law == RandomStiffnessLaw::kUniform
                                 ? SelfCalibrationConditions::kUniformStiffness
                                 : SelfCalibrationConditions::kInverseSquareStiffness;
  conditions.spring_law = options.lattice.spring_law;
  if (conditions.spring_law == SpringLaw::kPower) conditions.power_law = options.lattice.power_law;
  conditions.isotropic_dispersion = options.isotropic_dispersion;
  conditions.block_cells = options.calibration_block_cells;
  conditions.seed = options.calibration_seed;
  return conditions;
}

RandomSelfCalibration MeasureRandomSelfCalibration(const Material& material,
                                                   const RandomLatticeOptions& options) {
  if (options.calibration_block_cells < 1) {
    throw std::invalid_argument("the self-calibration block must be at least 1 cell wide, got " +
                                std::to_string(options.calibration_block_cells));
  }
  RandomLatticeOptions block = options;
  const double width = options.calibration_block_cells * options.lattice.spacing;
  block.size = Eigen::Vector3d(3.0 * width, width, width);
  block.seed = options.calibration_seed;
  block.self_calibrate = false;

  const double nu = material.poisson_ratio();
  const double target = std::log1p(DispersionRatio(nu));
  Reading last = Measure(material, block, DispersionFraction(nu));
  Reading previous = last;
  int measurements = 1;
  while (std::abs(last.poisson - nu) > kPoissonTolerance && measurements < kMaxMeasurements) {
    const double x = NextLogRatio(last, measurements > 1 ? &previous : nullptr, target);
    previous = last;
    last = Measure(material, block, 0.5 * std::expm1(x));
    ++measurements;
  }
  RandomSelfCalibration calibration;
  calibration.dispersion_fraction = 0.5 * std::expm1(last.log_ratio);
  calibration.stiffness_factor = material.youngs_modulus() / last.youngs;
  calibration.measured_youngs = last.youngs;
  calibration.measured_poisson = last.poisson;
  calibration.measurements = measurements;
  calibration.conditions = RandomSelfCalibrationConditions(material, options);
  return calibration;
}

}  // namespace msm_sim::core
