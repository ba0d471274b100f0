#pragma once

#include <cstdint>
#include <optional>

#include <Eigen/Core>

#include "msm_sim/geometry/solid_mesh.h"
#include "msm_sim/lattice/lattice_options.h"
#include "msm_sim/material/material.h"
#include "msm_sim/model/model.h"
#include "msm_sim/model/self_calibration.h"

namespace msm_sim::core {

/// How spring stiffness varies with rest length in a random lattice (docs/physics.md §2).
enum class RandomStiffnessLaw {
  kUniform,        ///< every spring has the same k
  kInverseSquare,  ///< k_i = c / L_i^2: every spring contributes equally to the moduli
};

/// The correction a random lattice's virtual measurement gives, with what it was measured for
/// (SelfCalibration, docs/physics.md §2.2).
using RandomSelfCalibration = SelfCalibration;

/// A box [0, size] filled by random sequential addition (thesis 2.3.3).
struct RandomLatticeOptions {
  Eigen::Vector3d size = Eigen::Vector3d::Ones();  ///< m, each > 0
  /// Characteristic spacing l (m; the target node count is N = V / l^3), spring law and node
  /// limit (LatticeOptions). A random lattice has no orientation: the rotation is ignored.
  LatticeOptions lattice;
  double min_distance = 0.8;  ///< minL as a multiple of l, in (0, max_distance)
  double max_distance = 1.7;  ///< maxL as a multiple of l: pairs closer than this get a spring
  std::uint64_t seed = 1;     ///< same seed, same model
  RandomStiffnessLaw stiffness_law = RandomStiffnessLaw::kInverseSquare;
  /// eMSM with nu > 1/4: weight each node's springs so that it disperses an isotropic pressure
  /// (see SetIsotropicDispersionWeights in the source). Off gives the eMSM paper's equal shares.
  bool isotropic_dispersion = true;
  /// Random sequential addition gives up after this many draws per requested node.
  int max_draws_per_node = 1000;
  /// Self-calibration (docs/physics.md §2.2): measure a representative block with the same l,
  /// minL, maxL, laws and nu but calibration_seed in the virtual compression test, and correct q
  /// and k so that it reads the target nu and E. Off by default: it costs a few builds and
  /// static solves of the representative block (docs/design/node-centred-lattices.md).
  bool self_calibrate = false;
  /// Representative block: 3w x w x w characteristic spacings (w = calibration_block_cells).
  int calibration_block_cells = 16;
  std::uint64_t calibration_seed = 0x5e1fca1;  ///< differs from the body's seed on purpose
  /// A correction measured before (MeasureRandomSelfCalibration, or a cached one): applied as is,
  /// nothing is measured. Takes precedence over self_calibrate. The caller answers for its
  /// conditions (BodyRecipe::random_calibration compares them with the recipe's).
  std::optional<RandomSelfCalibration> calibration;
};

/// What a self-calibration for `options` is measured for (its size, seed, self_calibrate and
/// calibration do not enter): lattice random, spacing, nu, minL, maxL, the stiffness and spring
/// laws, isotropic_dispersion, calibration_block_cells and calibration_seed.
SelfCalibrationConditions RandomSelfCalibrationConditions(const Material& material,
                                                          const RandomLatticeOptions& options);

/// Measures the self-calibration for `options` (its size, seed, self_calibrate and calibration
/// are ignored): builds the representative block, compresses it at strain 1e-3
/// (MeasureUniaxialCompression, the compression experiment's measurement), moves the dispersion
/// ratio Q by secant steps until the measured nu is within 0.002 of the target (at most 2 steps,
/// each changing 1 + Q by at most a factor 2), then sets stiffness_factor = E_target / E_measured
/// and the conditions to RandomSelfCalibrationConditions(material, options). Deterministic.
/// Throws as BuildRandomLattice, and std::runtime_error if a static solve does not converge.
RandomSelfCalibration MeasureRandomSelfCalibration(const Material& material,
                                                   const RandomLatticeOptions& options);

/// Builds a calibrated random MSM of the box: N = round(V / l^3) points at least minL apart
/// (spatial-hash rejection), a spring between every pair closer than maxL, node mass rho V / N,
/// and stiffnesses scaled so that sum k_i L_i^2 = 15 V mu, a Cauchy solid with the target shear
/// modulus, plus the eMSM dispersion q = Q(nu) / 2 (docs/physics.md §2-3; at nu = 1/4 this is the
/// plain calibration (1 / (6V)) sum k_i L_i^2 = E). With options.calibration (or
/// self_calibrate, which measures one first) the stiffnesses and q are corrected, and the model
/// keeps a measured correction (measurements > 0) as Model::self_calibration.
///
/// Throws std::invalid_argument for bad options (non-positive sizes, spacing larger than the box,
/// minL >= maxL, too many nodes) and std::runtime_error if random sequential addition cannot place
/// the requested nodes (minL too large for the density).
Model BuildRandomLattice(const Material& material, const RandomLatticeOptions& options);

/// The same for the body bounded by `solid` (options.size is ignored): N = round(V / l^3) with V
/// the mesh volume, nodes drawn inside the surface, and no spring whose segment crosses the
/// surface (it would tie together parts across a concave notch). Throws as BuildRandomLattice,
/// with the spacing checked against the smallest bounding-box edge.
Model BuildRandomLatticeInSolid(const Material& material, const SolidMesh& solid,
                                const RandomLatticeOptions& options);

}  // namespace msm_sim::core
