// msm_replay: runs the node's simulation offline on a bag (README "msm_replay").
// Exit codes: 0 success, 1 the replay failed (unreadable or corrupt bag, bad scene), 2 bad
// arguments. Errors are one line on stderr starting with "msm_replay: error:".
#include <iostream>

#include <ros/time.h>
#include <CLI/CLI.hpp>

#include "replay.h"
#include "simulation_config.h"

int main(int argc, char** argv) {
  ros::Time::init();
  msm_sim::ros_interface::ReplayOptions options;
  CLI::App app{"msm_replay: the msm_sim simulation replayed offline on a bag, as fast as possible",
               "msm_replay"};
  app.add_option("--config", options.config,
                 "scene YAML (the node's parameters); repeat to merge several in order")
      ->required()
      ->take_all();
  app.add_option("--materials", options.materials,
                 "materials YAML (default: the package's config/materials.yaml)");
  app.add_option("--in", options.input, "input bag")->required();
  app.add_option("--out", options.output, "output bag")->required();
  app.add_option("--node-name", options.node_name, "node whose topics are read and written")
      ->capture_default_str();
  bool quiet = false;
  app.add_flag("--quiet", quiet, "no progress");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return 0;
  } catch (const CLI::ParseError& error) {
    const std::string text = error.what();
    std::cerr << "msm_replay: error: " << text.substr(0, text.find('\n'))
              << " (run 'msm_replay --help' for usage)\n";
    return 2;
  }
  options.progress = !quiet;
  try {
    const msm_sim::ros_interface::ReplaySummary summary =
        msm_sim::ros_interface::RunReplay(options, std::cerr);
    std::cout << "msm_replay: " << summary.seconds << " s of bag time, " << summary.inputs
              << " input messages used, " << summary.dropped << " dropped, " << summary.outputs
              << " output messages written to " << options.output << "\n";
    return 0;
  } catch (const std::exception& error) {
    const std::string text = error.what();
    std::cerr << "msm_replay: error: " << text.substr(0, text.find('\n')) << "\n";
    return 1;
  }
}
