#pragma once
// msm_replay: the node's simulation run offline on a bag (README "msm_replay").

#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

namespace msm_sim::ros_interface {

/// An input the replay cannot use; what() is one line saying what and which file.
class ReplayError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ReplayOptions {
  /// Scene YAML files (the node's parameters), merged in order as rosparam load would.
  std::vector<std::string> config;
  std::string materials;  ///< materials YAML; empty: the package's config/materials.yaml
  std::string input;      ///< bag to read
  std::string output;     ///< bag to write
  std::string node_name = "msm_sim";  ///< the node whose topics are read and written
  bool progress = true;               ///< percentage and ETA on `log`
};

struct ReplaySummary {
  double seconds = 0.0;  ///< bag time replayed
  long inputs = 0;       ///< messages used
  long dropped = 0;      ///< messages dropped (with a warning on `log`)
  long outputs = 0;      ///< messages written
};

/// Reads what the node subscribes to from the input bag (tf, tf_static, robot_description if
/// recorded as a std_msgs/String topic, ~apply_force, the configured wrench topics), runs the
/// same Simulation as the node, stepping on bag time as fast as possible, and writes the
/// node's outputs (markers, contacts, per-link wrenches, state, tf, diagnostics without wall
/// timings) stamped in bag time. Deterministic: the same inputs give the same output bag.
/// Throws ReplayError (or ConfigError for the scene).
ReplaySummary RunReplay(const ReplayOptions& options, std::ostream& log);

}  // namespace msm_sim::ros_interface
