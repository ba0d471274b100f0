// The same simulation as a nodelet, to share a process (and zero-copy messages) with a driver.
#include <memory>

#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include "simulation_node.h"

namespace msm_sim::ros_interface {

class SimulationNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    try {
      simulation_ = std::make_unique<SimulationNode>(getNodeHandle(), getPrivateNodeHandle());
    } catch (const std::exception& error) {
      NODELET_FATAL("msm_sim: %s", error.what());
      throw;  // the manager reports the nodelet as failed to load
    }
  }
  std::unique_ptr<SimulationNode> simulation_;
};

}  // namespace msm_sim::ros_interface

PLUGINLIB_EXPORT_CLASS(msm_sim::ros_interface::SimulationNodelet, nodelet::Nodelet)
