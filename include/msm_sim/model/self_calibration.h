#pragma once

#include <cstdint>

#include "msm_sim/material/power_spring_law.h"
#include "msm_sim/material/spring_law.h"

namespace msm_sim::core {

/// Everything a random lattice's self-calibration (docs/physics.md §2.2) depends on: the
/// statistics of the representative block it measures and the target nu. E and the density are
/// not among them: they scale every stiffness and mass alike, so the factors are the same for
/// every E. Two calibrations measured for equal conditions are equal (the measurement is
/// deterministic), so a correction whose conditions equal a recipe's may be applied to it
/// without measuring again.
///
/// The codes are part of the model file format (model_file.h): never renumber them.
struct SelfCalibrationConditions {
  static constexpr std::uint32_t kRandomLattice = 1;  ///< LatticeKind::kRandom
  static constexpr std::uint32_t kUniformStiffness = 0;
  static constexpr std::uint32_t kInverseSquareStiffness = 1;

  std::uint32_t lattice = kRandomLattice;  ///< the lattice that was measured
  double spacing = 0.0;                    ///< characteristic spacing l (m)
  double poisson = 0.0;                    ///< target nu
  double min_distance = 0.0;               ///< minL / l
  double max_distance = 0.0;               ///< maxL / l
  std::uint32_t stiffness_law = kInverseSquareStiffness;
  SpringLaw spring_law = SpringLaw::kLinear;
  /// The law's alpha and beta when spring_law is kPower (docs/physics.md §4.1); else unread.
  PowerSpringLaw power_law;
  bool isotropic_dispersion = true;  ///< isotropic dispersion weights (docs/physics.md §3)
  int block_cells = 0;               ///< the representative block is 3w x w x w spacings
  std::uint64_t seed = 0;            ///< the representative block's seed

  /// Equal in every field, doubles bit for bit (power_law for kPower only).
  bool operator==(const SelfCalibrationConditions& other) const {
    const bool same_power_law =
        spring_law != SpringLaw::kPower ||
        (power_law.alpha == other.power_law.alpha && power_law.beta == other.power_law.beta);
    return same_power_law && lattice == other.lattice && spacing == other.spacing &&
           poisson == other.poisson && min_distance == other.min_distance &&
           max_distance == other.max_distance && stiffness_law == other.stiffness_law &&
           spring_law == other.spring_law && isotropic_dispersion == other.isotropic_dispersion &&
           block_cells == other.block_cells && seed == other.seed;
  }
  bool operator!=(const SelfCalibrationConditions& other) const { return !(*this == other); }
};

/// The correction a random lattice's virtual measurement gives (docs/physics.md §2.2): every k
/// is multiplied by stiffness_factor and the eMSM runs with dispersion_fraction instead of
/// q(nu) = DispersionFraction(nu). The identity is {1, DispersionFraction(nu)}. A model built
/// with a self-calibration keeps it (Model::self_calibration), and model files store it, so that
/// a saved or cached model is not measured again.
struct SelfCalibration {
  double stiffness_factor = 1.0;     ///< > 0
  double dispersion_fraction = 0.0;  ///< q actually used, > -1/2
  double measured_youngs = 0.0;      ///< Pa, E of the representative block before the k scaling
  double measured_poisson = 0.0;     ///< nu of the representative block at the final q
  int measurements = 0;              ///< compression experiments it took; 0: not measured
  SelfCalibrationConditions conditions = {};  ///< what it was measured for (measurements > 0)
};

}  // namespace msm_sim::core
