// msm_sim_node: simulates the configured soft objects (README "msm_sim_node").
// Exit code 1 with one ROS_FATAL line for a configuration it cannot run.
#include <csignal>

#include <ros/ros.h>
#include <unistd.h>

#include "simulation_node.h"

namespace {

// Ctrl-C while the scene loads and builds (a large object takes seconds): nothing is running
// yet that needs an orderly shutdown, so leave at once, as an interrupted program does.
void ExitDuringStartUp(int signal) {
  constexpr char kMessage[] = "msm_sim: interrupted during start-up\n";
  const ssize_t written = ::write(STDERR_FILENO, kMessage, sizeof(kMessage) - 1);
  static_cast<void>(written);
  ::_exit(128 + signal);
}

// Afterwards what roscpp's own handler does: ros::spin returns and the node shuts down.
void ShutDown(int) { ros::requestShutdown(); }

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "msm_sim", ros::init_options::NoSigintHandler);
  std::signal(SIGINT, ExitDuringStartUp);
  // The handles outlive the error report: when the last one goes, roscpp shuts down and with
  // it the logging a fatal configuration error is reported through.
  ros::NodeHandle handle, private_handle("~");
  try {
    msm_sim::ros_interface::SimulationNode node(handle, private_handle);
    std::signal(SIGINT, ShutDown);
    ros::spin();
  } catch (const std::exception& error) {
    ROS_FATAL("msm_sim: %s", error.what());
    return 1;
  }
  return 0;
}
