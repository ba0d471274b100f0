#pragma once

namespace msm_sim::core {

/// The arithmetic of AccumulateForces' spring loops (docs/physics.md §9).
enum class SpringPrecision {
  kDouble,  ///< double throughout
  /// Where the run kernels apply (linear springs in rows: cubic lattices), the spring loops run
  /// in single precision: positions relative to node 0 and velocities rounded to float, tensions
  /// and forces summed in float, then added to the double forces. Twice the springs per SIMD
  /// register; positions are rounded to 6e-8 of the body's extent D, so a spring's strain to about
  /// 6e-8 D / L. The stiffness products (ApplyStiffness, the implicit integrator's conjugate
  /// gradient) also run in float, on the double linearisation rounded to float (a relative
  /// error of about 1e-6 against the double product). Energy, Linearize and the stiffness
  /// diagonal stay in double, and total_tensions is not recorded. Other models evaluate in
  /// double.
  kSingle,
};

}  // namespace msm_sim::core
