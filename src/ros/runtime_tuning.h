#pragma once
// dynamic_reconfigure for msm_sim_node (README "Runtime tuning"): one server per object at
// ~reconfigure/objects/<name> for its material, applied through Simulation::SetMaterial (the
// validation and in-place recalibration of ~set_material), and one at ~reconfigure/world for the
// publish rate and real-time pacing. The servers only convert; a refused value is reported with
// a warning and the unchanged values are sent back to the client.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <dynamic_reconfigure/server.h>
#include <msm_sim/ObjectMaterialConfig.h>
#include <msm_sim/WorldTuningConfig.h>
#include <ros/ros.h>
#include <boost/thread/recursive_mutex.hpp>

#include "simulation.h"

namespace msm_sim::ros_interface {

class RuntimeTuning {
 public:
  /// Applies the world's tuning (publish rate in Hz, real-time pacing); returns an empty string
  /// or why it was refused (then nothing changed).
  using WorldSetter = std::function<std::string(double publish_rate, bool real_time)>;

  /// Starts the servers with the simulation's current values. `simulation` must outlive this
  /// object; the callbacks run on the node's callback queue like every other service.
  RuntimeTuning(const ros::NodeHandle& private_handle, Simulation* simulation,
                WorldSetter set_world);

 private:
  using ObjectServer = dynamic_reconfigure::Server<msm_sim::ObjectMaterialConfig>;
  using WorldServer = dynamic_reconfigure::Server<msm_sim::WorldTuningConfig>;

  void OnObject(std::size_t index, msm_sim::ObjectMaterialConfig& config);
  void OnWorld(msm_sim::WorldTuningConfig& config);

  Simulation* simulation_;
  WorldSetter set_world_;
  // Shared by the servers: updateConfig on a server that owns its mutex may deadlock (the
  // library warns), and the callbacks run on the node's one callback queue anyway.
  boost::recursive_mutex mutex_;
  std::vector<std::unique_ptr<ObjectServer>> object_servers_;
  std::unique_ptr<WorldServer> world_server_;
};

}  // namespace msm_sim::ros_interface
