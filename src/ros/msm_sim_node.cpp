// msm_sim_node: simulates the configured soft objects (README "msm_sim_node").
// Exit code 1 with one ROS_FATAL line for a configuration it cannot run.
#include <ros/ros.h>

#include "simulation_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "msm_sim");
  // The handles outlive the error report: when the last one goes, roscpp shuts down and with
  // it the logging a fatal configuration error is reported through.
  ros::NodeHandle handle, private_handle("~");
  try {
    msm_sim::ros_interface::SimulationNode node(handle, private_handle);
    ros::spin();
  } catch (const std::exception& error) {
    ROS_FATAL("msm_sim: %s", error.what());
    return 1;
  }
  return 0;
}
