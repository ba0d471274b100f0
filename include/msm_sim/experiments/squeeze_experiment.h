#pragma once

#include <memory>
#include <vector>

#include "msm_sim/dynamics/integrator.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// A body squeezed between two rigid flat plates (`msm_lab squeeze`, issue 61): what a
/// parallel gripper's pads read. No gravity, no ground: the body floats between two box plates,
/// their faces normal to z, wider than the body, that start `start_gap` outside its collision
/// spheres and close on it at `speed` each (a total closing rate of 2 speed) until their total
/// approach is `approach`. Approach is counted, as a measured curve's is, from the body's
/// surface: from the two planes through the highest (lowest) collision-sphere top (bottom)
/// within one characteristic length of the vertical axis through the centroid (the body at
/// rest), not from the first node either plate touches (docs/physics.md §7, the indentation
/// experiment's SurfaceContactHeight for the same reason).
///
/// Quasi-static: the plates move at a constant speed that is small against the body's wave
/// speed, and the force is a running mean over each row; docs/lab.md ("squeeze") gives the
/// check that halving the speed leaves the force where it is.
struct SqueezeExperimentOptions {
  double approach = 0.005;     ///< m, both plates together, finite, > 0, < the body's height
  double speed = 0.005;        ///< m/s, each plate, finite, > 0
  double friction = 0.0;       ///< Coulomb coefficient with the plates, finite, >= 0
  double step = 1e-3;          ///< s, finite, > 0: World::Step(step), subdivided inside
  double damping_beta = 1e-4;  ///< s, finite, >= 0: spring dampers c = beta k
  double start_gap = 2e-4;     ///< m, finite, >= 0
  int samples = 30;            ///< rows of the profile, >= 1
  /// BodyOptions::orientation_threshold, 0 (off) or in (0, 1) (docs/physics.md §4, "Orientation
  /// barrier"). Whatever it is, a lattice corner turned inside out (J <= 0) stops the run. 0.5,
  /// not the grasp's 0.2: at 0.2 a squeezed sphere folds corners before 30 % of its diameter, at
  /// 0.5 it does not, and the force up to the fold is the same (docs/lab.md "squeeze",
  /// docs/design/squeeze-vs-fem.md).
  double orientation_threshold = 0.5;
  Integrator integrator = Integrator::kExplicit;
  /// In (0, 1]: WorldOptions::time_step_safety. The explicit step's bound on a power-law
  /// spring's tangent holds down to 70 % of its length (docs/physics.md §4.1, §7); a squeeze
  /// compresses the springs under the plates further, so a stiffening law needs a smaller one.
  double time_step_safety = 0.8;
};

/// One profile row: the means over a run of consecutive steps covering approach / samples.
struct SqueezeSample {
  double approach = 0.0;        ///< m, total, both plates
  double force = 0.0;           ///< N, the mean of the two plates' normal forces
  double contact_radius = 0.0;  ///< m: the farthest node touching the top plate from the axis
  double contact_area = 0.0;    ///< m^2: the nodes touching the top plate times spacing^2
};

struct SqueezeExperimentResult {
  std::vector<SqueezeSample> profile;  ///< by increasing approach
  double height = 0.0;                 ///< m, between the two reference planes at rest
  int nodes = 0;
  /// The lattice corners turned inside out (J <= 0) at the end; the run stops at the first row
  /// that has any and `folded_at` is that row's approach (m), 0 when none folded.
  int folded_corners = 0;
  double folded_at = 0.0;
  double seconds_simulated = 0.0;
};

/// Runs the squeeze. Throws std::invalid_argument for bad options (among them an approach that
/// would make the plates meet) and std::runtime_error if a step is rejected.
SqueezeExperimentResult RunSqueezeExperiment(std::shared_ptr<const Model> model,
                                             const SqueezeExperimentOptions& options);

}  // namespace msm_sim::core
