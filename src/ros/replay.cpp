#include "replay.h"

#include <chrono>
#include <cmath>
#include <iomanip>
#include <set>
#include <vector>

#include <ros/package.h>
#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <rosbag/view.h>
#include <std_msgs/String.h>
#include <tf2/buffer_core.h>
#include <tf2_msgs/TFMessage.h>
#include <yaml-cpp/yaml.h>

#include "simulation.h"

namespace msm_sim::ros_interface {
namespace {

// A YAML tree as the parameter server would hold it.
XmlRpc::XmlRpcValue ToXmlRpc(const YAML::Node& node) {
  XmlRpc::XmlRpcValue value;
  if (node.IsMap()) {
    for (const auto& entry : node) value[entry.first.as<std::string>()] = ToXmlRpc(entry.second);
    if (node.size() == 0) value.begin();  // an empty dictionary, not "invalid"
  } else if (node.IsSequence()) {
    value.setSize(static_cast<int>(node.size()));
    for (std::size_t i = 0; i < node.size(); ++i) value[static_cast<int>(i)] = ToXmlRpc(node[i]);
  } else if (node.IsScalar()) {
    const std::string text = node.Scalar();
    // Quoted scalars stay text; otherwise the types rosparam would give.
    if (node.Tag() != "!") {
      int integer = 0;
      double number = 0.0;
      bool flag = false;
      if (YAML::convert<int>::decode(node, integer) &&
          text.find_first_of(".eE") == std::string::npos) {
        return XmlRpc::XmlRpcValue(integer);
      }
      if (YAML::convert<double>::decode(node, number)) return XmlRpc::XmlRpcValue(number);
      if (YAML::convert<bool>::decode(node, flag)) return XmlRpc::XmlRpcValue(flag);
    }
    return XmlRpc::XmlRpcValue(text);
  }
  return value;
}

YAML::Node LoadYaml(const std::string& path, const std::string& what) {
  try {
    return YAML::LoadFile(path);
  } catch (const std::exception& e) {
    throw ReplayError(what + " '" + path + "': " + e.what());
  }
}

// Later files override earlier ones key by key, as successive `rosparam load`s do.
void Merge(const YAML::Node& from, YAML::Node* into) {
  for (const auto& entry : from) {
    const std::string key = entry.first.as<std::string>();
    if (entry.second.IsMap() && (*into)[key] && (*into)[key].IsMap()) {
      YAML::Node child = (*into)[key];
      Merge(entry.second, &child);
    } else {
      (*into)[key] = YAML::Clone(entry.second);
    }
  }
}

std::string Absolute(const std::string& topic) {
  if (!topic.empty() && topic[0] == '/') return topic;
  return "/" + topic;
}

}  // namespace

ReplaySummary RunReplay(const ReplayOptions& options, std::ostream& log) {
  // The scene, with the materials library under `materials` as the launch files load it.
  YAML::Node scene(YAML::NodeType::Map);
  for (const std::string& path : options.config) {
    const YAML::Node part = LoadYaml(path, "config");
    if (!part.IsMap()) throw ReplayError("config '" + path + "': not a YAML dictionary");
    Merge(part, &scene);
  }
  const std::string materials_path =
      options.materials.empty() ? ros::package::getPath("msm_sim") + "/config/materials.yaml"
                                : options.materials;
  const YAML::Node materials = LoadYaml(materials_path, "materials");
  if (materials["materials"] && !scene["materials"]) scene["materials"] = materials["materials"];
  const SimulationConfig config = LoadSimulationConfig(ToXmlRpc(scene));

  rosbag::Bag input;
  try {
    input.open(options.input, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    throw ReplayError("input bag '" + options.input + "': cannot be read: " + e.what());
  }
  const std::string ns = "/" + options.node_name;
  const std::string apply_force = ns + "/apply_force";
  std::vector<std::string> wrench_topics;
  for (const WrenchInputConfig& w : config.wrench_inputs) {
    wrench_topics.push_back(Absolute(w.topic));
  }
  std::vector<std::string> topics = {"/tf", "/tf_static", "/robot_description", apply_force};
  topics.insert(topics.end(), wrench_topics.begin(), wrench_topics.end());

  std::string description;
  ros::Time start, end;
  try {
    rosbag::View all(input, rosbag::TopicQuery(topics));
    if (all.size() == 0) {
      std::string list;
      for (const std::string& t : topics) list += (list.empty() ? "" : ", ") + t;
      throw ReplayError("input bag '" + options.input +
                        "' has none of the topics msm_replay reads (" + list + ")");
    }
    start = all.getBeginTime();
    end = all.getEndTime();
    rosbag::View descriptions(input, rosbag::TopicQuery("/robot_description"));
    for (const rosbag::MessageInstance& m : descriptions) {
      if (const auto text = m.instantiate<std_msgs::String>()) {
        description = text->data;
        break;
      }
    }
  } catch (const rosbag::BagException& e) {
    throw ReplayError("input bag '" + options.input + "': corrupt: " + e.what());
  }
  if (config.robot.enabled && description.empty()) {
    log << "msm_replay: warning: the bag has no /robot_description (std_msgs/String); "
           "running without the robot\n";
  }
  Simulation simulation(config, description);

  rosbag::Bag output;
  try {
    output.open(options.output, rosbag::bagmode::Write);
  } catch (const rosbag::BagException& e) {
    throw ReplayError("output bag '" + options.output + "': cannot be written: " + e.what());
  }
  std::vector<std::string> link_topics;
  for (const RobotColliders::Link& link : simulation.robot().links()) {
    link_topics.push_back(ns + "/links/" + link.name + "/wrench");
  }

  ReplaySummary summary;
  const double period = 1.0 / config.world.publish_rate;
  const double length = std::max((end - start).toSec(), 0.0);
  tf2::BufferCore tf(ros::Duration(std::max(10.0, length + 10.0)));
  ros::Time next_tick = start + ros::Duration(period);
  const auto wall_start = std::chrono::steady_clock::now();
  auto last_progress = wall_start;
  const auto write = [&](const std::string& topic, const ros::Time& stamp, const auto& message) {
    output.write(topic, stamp, message);
    ++summary.outputs;
  };
  // Simulates up to `until`, writing the outputs at every publication tick on the way.
  const auto advance_to = [&](const ros::Time& until) {
    while (next_tick <= until) {
      simulation.UpdateRobot(tf, next_tick);
      simulation.Advance((next_tick - start).toSec() - simulation.time(), next_tick,
                         ros::WallTime());
      write(ns + "/markers", next_tick, simulation.Markers(next_tick));
      std::vector<geometry_msgs::WrenchStamped> links;
      write(ns + "/contacts", next_tick, simulation.Contacts(next_tick, &links));
      for (std::size_t l = 0; l < links.size(); ++l) write(link_topics[l], next_tick, links[l]);
      write(ns + "/state", next_tick, simulation.NodeCloud(next_tick));
      tf2_msgs::TFMessage frames;
      frames.transforms = simulation.Frames(next_tick);
      write("/tf", next_tick, frames);
      write("/diagnostics", next_tick, simulation.Diagnostics(next_tick, 0.0, false, false));
      next_tick += ros::Duration(period);
    }
    const auto now = std::chrono::steady_clock::now();
    if (options.progress && now - last_progress > std::chrono::seconds(1)) {
      last_progress = now;
      const double done = length > 0.0 ? (until - start).toSec() / length : 1.0;
      const double elapsed = std::chrono::duration<double>(now - wall_start).count();
      log << "\rmsm_replay: " << std::fixed << std::setprecision(0) << 100.0 * done << " % ("
          << std::setprecision(1) << (until - start).toSec() << " of " << length
          << " s of bag time), ETA " << std::setprecision(0)
          << (done > 0.0 ? elapsed * (1.0 - done) / done : 0.0) << " s   " << std::flush;
    }
  };
  const auto drop = [&](const std::string& topic, const std::string& reason) {
    ++summary.dropped;
    log << "msm_replay: warning: " << topic << ": " << reason << "; dropped\n";
  };

  try {
    rosbag::View view(input, rosbag::TopicQuery(topics));
    for (const rosbag::MessageInstance& m : view) {
      advance_to(m.getTime());
      const std::string& topic = m.getTopic();
      if (topic == "/tf" || topic == "/tf_static") {
        if (const auto frames = m.instantiate<tf2_msgs::TFMessage>()) {
          for (const auto& t : frames->transforms) {
            try {
              tf.setTransform(t, "bag", topic == "/tf_static");
            } catch (const std::exception& e) {
              drop(topic, e.what());
            }
          }
          ++summary.inputs;
        }
      } else if (topic == apply_force) {
        if (const auto force = m.instantiate<msm_sim::ContactForce>()) {
          const std::string problem = simulation.ApplyForce(*force, tf);
          problem.empty() ? void(++summary.inputs) : drop(topic, problem);
        }
      } else {
        for (std::size_t w = 0; w < wrench_topics.size(); ++w) {
          if (topic != wrench_topics[w]) continue;
          if (const auto wrench = m.instantiate<geometry_msgs::WrenchStamped>()) {
            const std::string problem = simulation.SetWrench(w, *wrench, m.getTime(), tf);
            problem.empty() ? void(++summary.inputs) : drop(topic, problem);
          }
        }
      }
    }
    advance_to(end);
  } catch (const rosbag::BagException& e) {
    throw ReplayError("input bag '" + options.input + "': corrupt: " + e.what());
  }
  if (options.progress) log << "\rmsm_replay: 100 %                                          \n";
  summary.seconds = length;
  output.close();
  return summary;
}

}  // namespace msm_sim::ros_interface
