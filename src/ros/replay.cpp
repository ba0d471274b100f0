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

#include "msm_sim/io/regular_file.h"
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
  const std::string problem = core::RegularFileProblem(path);
  if (!problem.empty()) throw ReplayError(what + " '" + path + "': " + problem);
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

// The scene the node would run: the config files merged in order, with the materials library
// under `materials` as the launch files load it.
SimulationConfig LoadScene(const ReplayOptions& options) {
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
  return LoadSimulationConfig(ToXmlRpc(scene));
}

// `failure` starts the error message if the bag cannot be opened.
void OpenBag(const std::string& path, rosbag::bagmode::BagMode mode, const std::string& failure,
             rosbag::Bag* bag) {
  if (mode == rosbag::bagmode::Read) {
    const std::string problem = core::RegularFileProblem(path);
    if (!problem.empty()) throw ReplayError(failure + problem);
  }
  try {
    bag->open(path, mode);
  } catch (const rosbag::BagException& e) {
    throw ReplayError(failure + e.what());
  }
}

// What the node subscribes to, as absolute topics.
struct InputTopics {
  std::string apply_force;
  std::vector<std::string> wrenches;  // per configured wrench input
  std::vector<std::string> all;       // tf, tf_static, robot_description, the above
};

InputTopics TopicsOf(const SimulationConfig& config, const std::string& ns) {
  InputTopics topics;
  topics.apply_force = ns + "/apply_force";
  for (const WrenchInputConfig& w : config.wrench_inputs) {
    topics.wrenches.push_back(Absolute(w.topic));
  }
  topics.all = {"/tf", "/tf_static", "/robot_description", topics.apply_force};
  topics.all.insert(topics.all.end(), topics.wrenches.begin(), topics.wrenches.end());
  return topics;
}

// What the replay needs to know of the input bag before it starts.
struct InputSummary {
  ros::Time start, end;           // of the messages read
  std::string robot_description;  // the first recorded one; empty: none
};

// Throws ReplayError if the bag has none of `topics` or is corrupt.
InputSummary ScanInput(const rosbag::Bag& input, const InputTopics& topics,
                       const std::string& path) {
  InputSummary summary;
  try {
    rosbag::View all(input, rosbag::TopicQuery(topics.all));
    if (all.size() == 0) {
      std::string list;
      for (const std::string& t : topics.all) list += (list.empty() ? "" : ", ") + t;
      throw ReplayError("input bag '" + path + "' has none of the topics msm_replay reads (" +
                        list + ")");
    }
    summary.start = all.getBeginTime();
    summary.end = all.getEndTime();
    rosbag::View descriptions(input, rosbag::TopicQuery("/robot_description"));
    for (const rosbag::MessageInstance& m : descriptions) {
      if (const auto text = m.instantiate<std_msgs::String>()) {
        summary.robot_description = text->data;
        break;
      }
    }
  } catch (const rosbag::BagException& e) {
    throw ReplayError("input bag '" + path + "': corrupt: " + e.what());
  }
  return summary;
}

// The node's simulation on bag time: takes the input messages in order, simulates up to each
// and writes the outputs at every publication tick into the output bag.
class Replayer {
 public:
  /// Builds the simulation (throws ConfigError), then opens the output bag (throws ReplayError).
  Replayer(const ReplayOptions& options, const SimulationConfig& config, const InputTopics& topics,
           const InputSummary& input, std::ostream& log);

  /// Simulates up to `until`, writing the outputs at every publication tick on the way.
  void AdvanceTo(const ros::Time& until);
  /// Uses one input message (tf, an applied force or a wrench) or drops it with a warning.
  void Feed(const rosbag::MessageInstance& message);
  /// Closes the output bag; what was replayed.
  ReplaySummary Finish();

 private:
  void FeedTransforms(const rosbag::MessageInstance& message, bool is_static);
  void PublishOutputs(const ros::Time& tick);
  void ReportProgress(const ros::Time& until);
  void Drop(const std::string& topic, const std::string& reason);
  template <class Message>
  void Write(const std::string& topic, const ros::Time& stamp, const Message& message) {
    output_.write(topic, stamp, message);
    ++summary_.outputs;
  }

  const ReplayOptions& options_;
  const InputTopics& topics_;
  std::ostream& log_;
  const std::string ns_;  // the node's namespace
  Simulation simulation_;
  rosbag::Bag output_;
  std::vector<std::string> link_topics_;           // ~links/<link>/wrench
  std::vector<std::string> link_pressure_topics_;  // ~links/<link>/pressure
  ReplaySummary summary_;
  const double period_;  // s between publication ticks
  const ros::Time start_;
  const double length_;  // s of bag time
  tf2::BufferCore tf_;
  ros::Time next_tick_;
  const std::chrono::steady_clock::time_point wall_start_;
  std::chrono::steady_clock::time_point last_progress_;
};

Replayer::Replayer(const ReplayOptions& options, const SimulationConfig& config,
                   const InputTopics& topics, const InputSummary& input, std::ostream& log)
    : options_(options),
      topics_(topics),
      log_(log),
      ns_("/" + options.node_name),
      simulation_(config, input.robot_description),
      period_(1.0 / config.world.publish_rate),
      start_(input.start),
      length_(std::max((input.end - input.start).toSec(), 0.0)),
      tf_(ros::Duration(std::max(10.0, length_ + 10.0))),
      next_tick_(start_ + ros::Duration(period_)),
      wall_start_(std::chrono::steady_clock::now()),
      last_progress_(wall_start_) {
  OpenBag(options.output, rosbag::bagmode::Write,
          "output bag '" + options.output + "': cannot be written: ", &output_);
  for (const RobotColliders::Link& link : simulation_.robot().links()) {
    link_topics_.push_back(ns_ + "/links/" + link.name + "/wrench");
    link_pressure_topics_.push_back(ns_ + "/links/" + link.name + "/pressure");
  }
}

void Replayer::AdvanceTo(const ros::Time& until) {
  while (next_tick_ <= until) {
    const double seconds = (next_tick_ - start_).toSec() - simulation_.time();
    simulation_.Advance(seconds, next_tick_, ros::WallTime(), &tf_, start_);
    PublishOutputs(next_tick_);
    next_tick_ += ros::Duration(period_);
  }
  ReportProgress(until);
}

void Replayer::PublishOutputs(const ros::Time& tick) {
  Write(ns_ + "/markers", tick, simulation_.Markers(tick));
  sensor_msgs::PointCloud2 contact_points;  // before Contacts, which starts a new interval
  std::vector<sensor_msgs::PointCloud2> pressures;
  simulation_.ContactPointClouds(tick, &contact_points, &pressures);
  Write(ns_ + "/contact_points", tick, contact_points);
  std::vector<geometry_msgs::WrenchStamped> links;
  Write(ns_ + "/contacts", tick, simulation_.Contacts(tick, &links));
  for (std::size_t l = 0; l < links.size(); ++l) {
    Write(link_topics_[l], tick, links[l]);
    Write(link_pressure_topics_[l], tick, pressures[l]);
  }
  Write(ns_ + "/state", tick, simulation_.NodeCloud(tick));
  tf2_msgs::TFMessage frames;
  frames.transforms = simulation_.Frames(tick);
  Write("/tf", tick, frames);
  Write("/diagnostics", tick, simulation_.Diagnostics(tick, 0.0, false, false));
}

// At most once a second: the share of the bag replayed and the wall time still needed.
void Replayer::ReportProgress(const ros::Time& until) {
  const auto now = std::chrono::steady_clock::now();
  if (!options_.progress || now - last_progress_ <= std::chrono::seconds(1)) return;
  last_progress_ = now;
  const double done = length_ > 0.0 ? (until - start_).toSec() / length_ : 1.0;
  const double elapsed = std::chrono::duration<double>(now - wall_start_).count();
  log_ << "\rmsm_replay: " << std::fixed << std::setprecision(0) << 100.0 * done << " % ("
       << std::setprecision(1) << (until - start_).toSec() << " of " << length_
       << " s of bag time), ETA " << std::setprecision(0)
       << (done > 0.0 ? elapsed * (1.0 - done) / done : 0.0) << " s   " << std::flush;
}

void Replayer::Feed(const rosbag::MessageInstance& message) {
  const std::string& topic = message.getTopic();
  if (topic == "/tf" || topic == "/tf_static") {
    FeedTransforms(message, topic == "/tf_static");
  } else if (topic == topics_.apply_force) {
    if (const auto force = message.instantiate<msm_sim::ContactForce>()) {
      const std::string problem = simulation_.ApplyForce(*force, tf_);
      problem.empty() ? void(++summary_.inputs) : Drop(topic, problem);
    }
  } else {
    for (std::size_t w = 0; w < topics_.wrenches.size(); ++w) {
      if (topic != topics_.wrenches[w]) continue;
      if (const auto wrench = message.instantiate<geometry_msgs::WrenchStamped>()) {
        const std::string problem = simulation_.SetWrench(w, *wrench, message.getTime(), tf_);
        problem.empty() ? void(++summary_.inputs) : Drop(topic, problem);
      }
    }
  }
}

void Replayer::FeedTransforms(const rosbag::MessageInstance& message, bool is_static) {
  if (const auto frames = message.instantiate<tf2_msgs::TFMessage>()) {
    for (const auto& t : frames->transforms) {
      try {
        tf_.setTransform(t, "bag", is_static);
      } catch (const std::exception& e) {
        Drop(message.getTopic(), e.what());
      }
    }
    ++summary_.inputs;
  }
}

void Replayer::Drop(const std::string& topic, const std::string& reason) {
  ++summary_.dropped;
  log_ << "msm_replay: warning: " << topic << ": " << reason << "; dropped\n";
}

ReplaySummary Replayer::Finish() {
  if (options_.progress) log_ << "\rmsm_replay: 100 %                                          \n";
  summary_.seconds = length_;
  output_.close();
  return summary_;
}

}  // namespace

ReplaySummary RunReplay(const ReplayOptions& options, std::ostream& log) {
  const SimulationConfig config = LoadScene(options);
  rosbag::Bag input;
  OpenBag(options.input, rosbag::bagmode::Read,
          "input bag '" + options.input + "': cannot be read: ", &input);
  const InputTopics topics = TopicsOf(config, "/" + options.node_name);
  const InputSummary contents = ScanInput(input, topics, options.input);
  if (config.robot.enabled && contents.robot_description.empty()) {
    log << "msm_replay: warning: the bag has no /robot_description (std_msgs/String); "
           "running without the robot\n";
  }
  Replayer replayer(options, config, topics, contents, log);
  try {
    rosbag::View view(input, rosbag::TopicQuery(topics.all));
    for (const rosbag::MessageInstance& message : view) {
      replayer.AdvanceTo(message.getTime());
      replayer.Feed(message);
    }
    replayer.AdvanceTo(contents.end);
  } catch (const rosbag::BagException& e) {
    throw ReplayError("input bag '" + options.input + "': corrupt: " + e.what());
  }
  return replayer.Finish();
}

}  // namespace msm_sim::ros_interface
