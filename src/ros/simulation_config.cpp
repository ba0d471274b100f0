#include "simulation_config.h"

#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

#include <ros/names.h>
#include <ros/package.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include "object_config_reader.h"
#include "parameter_tree.h"

namespace msm_sim::ros_interface {
namespace {

using XmlRpc::XmlRpcValue;

using param::AtMost;
using param::Count;
using param::Fail;
using param::FailNotOneOf;
using param::Flag;
using param::Get;
using param::Has;
using param::KnownKeys;
using param::NonNegative;
using param::Number;
using param::OneOf;
using param::Positive;
using param::Text;
using param::Vector;

// The keys each dictionary of the configuration takes (README "msm_sim_node").
const std::set<std::string> kWorldKeys = {"frame",
                                          "gravity",
                                          "ground",
                                          "time_step",
                                          "publish_rate",
                                          "real_time",
                                          "publish_clock",
                                          "max_force",
                                          "time_step_safety",
                                          "max_substep_refinement",
                                          "integrator",
                                          "threads",
                                          "spring_precision",
                                          "penetration_recovery_time",
                                          "penetration_max_speed",
                                          "max_distance",
                                          "max_pending_pushes",
                                          "max_pending_force"};
const std::set<std::string> kRobotKeys = {"description_param", "friction", "tf_timeout",
                                          "tf_delay",          "links",    "link_friction",
                                          "max_link_speed"};
const std::set<std::string> kMarkerKeys = {"colour_by_strain", "strain_range", "nodes", "springs"};

// The world's scale: nothing a scene or message gives is farther than max_distance from the
// origin, and gravity and friction stay within what any robot scene holds (finite values beyond
// them overflowed contact forces or rejected every step; docs/robustness.md).
constexpr double kMaxDistanceLimit = 1e4;   // m; float spring loops keep 1 mm there
constexpr double kMaxGravity = 1000.0;      // m/s^2, about 100 g
constexpr double kMaxFriction = 10.0;       // Coulomb coefficient
constexpr double kMaxTimeStep = 0.1;        // s
constexpr double kMaxPublishRate = 1000.0;  // Hz
constexpr double kMaxForceLimit = 1e6;      // N
constexpr double kMaxPendingPushes = 10000.0;
constexpr double kMaxRecoveryTime = 10.0;   // s
constexpr double kMaxRecoverySpeed = 10.0;  // m/s

// frame, max_distance, gravity and the ground.
void ReadWorldScene(XmlRpcValue& world, const std::string& path, WorldConfig* config) {
  config->frame = Text(world, "frame", config->frame, path);
  if (config->frame.empty()) Fail(path + "/frame", "must not be empty");
  config->max_distance = AtMost(Positive(world, "max_distance", config->max_distance, path),
                                kMaxDistanceLimit, "max_distance", path,
                                "farther from the origin the float spring loops lose resolution");
  config->gravity = Vector(world, "gravity", config->gravity, path);
  AtMost(config->gravity.norm(), kMaxGravity, "gravity", path, "its magnitude (m/s^2) is absurd");
  if (Has(world, "ground")) {
    XmlRpcValue& ground = world["ground"];
    const std::string ground_path = path + "/ground";
    KnownKeys(ground, {"enabled", "height", "friction"}, ground_path);
    config->ground = Flag(ground, "enabled", true, ground_path);
    config->ground_height = Number(ground, "height", 0.0, ground_path);
    AtMost(std::abs(config->ground_height), config->max_distance, "height", ground_path,
           "|height| (m) is beyond ~world/max_distance");
    config->ground_friction =
        AtMost(NonNegative(ground, "friction", 0.5, ground_path), kMaxFriction, "friction",
               ground_path, "a Coulomb coefficient that large is absurd");
  }
}

// The step: its length, substeps, integrator, threads and precision.
void ReadWorldStepping(XmlRpcValue& world, const std::string& path, WorldConfig* config) {
  config->time_step = AtMost(Positive(world, "time_step", config->time_step, path), kMaxTimeStep,
                             "time_step", path, "a step (s) that long is absurd");
  config->time_step_safety = Positive(world, "time_step_safety", config->time_step_safety, path);
  AtMost(config->time_step_safety, 1.0, "time_step_safety", path,
         "a fraction of the stability limit, in (0, 1]");
  const double refinement =
      Positive(world, "max_substep_refinement", config->max_substep_refinement, path);
  if (refinement != std::floor(refinement) || refinement > 64.0 ||
      (static_cast<int>(refinement) & (static_cast<int>(refinement) - 1)) != 0) {
    Fail(path + "/max_substep_refinement",
         "must be a power of 2 from 1 (off) to 64; got " + std::to_string(refinement));
  }
  config->max_substep_refinement = static_cast<int>(refinement);
  const double threads = Positive(world, "threads", 1.0, path);
  if (threads != std::floor(threads) || threads > 64.0) {
    Fail(path + "/threads", "must be a whole number from 1 to 64; got " + std::to_string(threads));
  }
  config->threads = static_cast<int>(threads);
  const std::string integrator = Text(world, "integrator", "explicit", path);
  if (!core::ParseIntegrator(integrator, &config->integrator)) {
    FailNotOneOf(integrator, {"explicit", "implicit"}, path + "/integrator");
  }
  const std::string precision = Text(world, "spring_precision", "single", path);
  OneOf(precision, {"single", "double"}, path + "/spring_precision");
  config->spring_precision =
      precision == "single" ? core::SpringPrecision::kSingle : core::SpringPrecision::kDouble;
}

// Publishing, the bounds on input forces and penetration recovery.
void ReadWorldLimits(XmlRpcValue& world, const std::string& path, WorldConfig* config) {
  config->publish_rate = AtMost(Positive(world, "publish_rate", config->publish_rate, path),
                                kMaxPublishRate, "publish_rate", path, "Hz beyond any display");
  config->real_time = Flag(world, "real_time", config->real_time, path);
  config->publish_clock = Flag(world, "publish_clock", config->publish_clock, path);
  config->max_force = AtMost(Positive(world, "max_force", config->max_force, path), kMaxForceLimit,
                             "max_force", path, "a bound (N) that admits absurd forces");
  config->max_pending_pushes = static_cast<int>(
      Count(world, "max_pending_pushes", config->max_pending_pushes, kMaxPendingPushes, path));
  if (config->max_pending_pushes < 1) Fail(path + "/max_pending_pushes", "must be at least 1");
  config->max_pending_force =
      AtMost(Positive(world, "max_pending_force", config->max_pending_force, path), kMaxForceLimit,
             "max_pending_force", path, "a bound (N) that admits absurd forces");
  config->penetration_recovery_time = AtMost(
      Positive(world, "penetration_recovery_time", config->penetration_recovery_time, path),
      kMaxRecoveryTime, "penetration_recovery_time", path, "a recovery (s) that slow is absurd");
  config->penetration_max_speed = AtMost(
      NonNegative(world, "penetration_max_speed", config->penetration_max_speed, path),
      kMaxRecoverySpeed, "penetration_max_speed", path, "a recovery (m/s) that fast throws nodes");
}

WorldConfig ReadWorld(XmlRpcValue& world) {
  const std::string path = "~world";
  KnownKeys(world, kWorldKeys, path);
  WorldConfig config;
  ReadWorldScene(world, path, &config);
  ReadWorldStepping(world, path, &config);
  ReadWorldLimits(world, path, &config);
  return config;
}

// ~wrench_inputs, each applied to one of the objects.
std::vector<WrenchInputConfig> ReadWrenchInputs(XmlRpcValue& inputs,
                                                const std::vector<ObjectConfig>& objects) {
  std::set<std::string> names;
  for (const ObjectConfig& object : objects) names.insert(object.name);
  if (inputs.getType() != XmlRpcValue::TypeArray) Fail("~wrench_inputs", "expected a list");
  std::vector<WrenchInputConfig> configs;
  for (int i = 0; i < inputs.size(); ++i) {
    const std::string path = "~wrench_inputs[" + std::to_string(i) + "]";
    KnownKeys(inputs[i], {"topic", "object", "radius"}, path);
    WrenchInputConfig input;
    input.topic = Text(inputs[i], "topic", "", path);
    std::string invalid;
    if (!input.topic.empty() && !ros::names::validate(input.topic, invalid)) {
      Fail(path + "/topic", "'" + input.topic + "' is not a ROS topic name: " + invalid);
    }
    input.object = Text(inputs[i], "object", "", path);
    input.radius = NonNegative(inputs[i], "radius", input.radius, path);
    if (input.topic.empty()) Fail(path + "/topic", "missing");
    if (names.count(input.object) == 0) Fail(path + "/object", "no object '" + input.object + "'");
    configs.push_back(input);
  }
  return configs;
}

// ~robot: its presence enables the robot colliders.
RobotConfig ReadRobot(XmlRpcValue& robot) {
  KnownKeys(robot, kRobotKeys, "~robot");
  RobotConfig r;
  r.enabled = true;
  r.description_param = Text(robot, "description_param", r.description_param, "~robot");
  r.friction = AtMost(NonNegative(robot, "friction", r.friction, "~robot"), kMaxFriction,
                      "friction", "~robot", "a Coulomb coefficient that large is absurd");
  r.max_link_speed = Positive(robot, "max_link_speed", r.max_link_speed, "~robot");
  r.tf_timeout = Positive(robot, "tf_timeout", r.tf_timeout, "~robot");
  r.tf_delay = NonNegative(robot, "tf_delay", r.tf_delay, "~robot");
  if (Has(robot, "links")) {
    XmlRpcValue& links = robot["links"];
    if (links.getType() != XmlRpcValue::TypeArray) Fail("~robot/links", "expected a list");
    for (int i = 0; i < links.size(); ++i) {
      if (links[i].getType() != XmlRpcValue::TypeString) {
        Fail("~robot/links[" + std::to_string(i) + "]", "expected a link name");
      }
      r.links.push_back(static_cast<std::string>(links[i]));
    }
  }
  if (Has(robot, "link_friction")) {
    XmlRpcValue& table = robot["link_friction"];
    if (table.getType() != XmlRpcValue::TypeStruct) {
      Fail("~robot/link_friction", "expected {link: coefficient}");
    }
    for (auto& [link, value] : table) {
      r.link_friction[link] =
          AtMost(NonNegative(table, link, 0.0, "~robot/link_friction"), kMaxFriction, link,
                 "~robot/link_friction", "a Coulomb coefficient that large is absurd");
    }
  }
  return r;
}

MarkerConfig ReadMarkers(XmlRpcValue& markers) {
  KnownKeys(markers, kMarkerKeys, "~markers");
  MarkerConfig config;
  config.colour_by_strain = Flag(markers, "colour_by_strain", true, "~markers");
  config.strain_range = Positive(markers, "strain_range", 0.2, "~markers");
  config.nodes = Flag(markers, "nodes", false, "~markers");
  config.springs = Flag(markers, "springs", false, "~markers");
  return config;
}

}  // namespace

std::string MaterialProblem(double youngs, double poisson, double density) {
  std::ostringstream problem;
  if (!(youngs > 0.0 && youngs <= kMaxYoungs)) {
    problem << "Young's modulus " << youngs << " Pa is outside (0, " << kMaxYoungs << "]";
  } else if (!(poisson > -1.0 && poisson < 0.5)) {
    problem << "Poisson's ratio " << poisson << " is outside (-1, 0.5)";
  } else if (!(density > 0.0 && density <= kMaxDensity)) {
    problem << "density " << density << " kg/m^3 is outside (0, " << kMaxDensity << "]";
  }
  return problem.str();
}

std::set<std::string> ReservedNames(const WorldConfig& world) { return {world.frame, "ground"}; }

std::string ResolveUri(const std::string& uri, const std::string& parameter) {
  if (uri.empty()) Fail(parameter, "missing");
  const std::string package_prefix = "package://";
  const std::string file_prefix = "file://";
  if (uri.rfind(package_prefix, 0) == 0) {
    const std::string rest = uri.substr(package_prefix.size());
    const std::size_t slash = rest.find('/');
    const std::string package = rest.substr(0, slash);
    const std::string path = ros::package::getPath(package);
    if (path.empty()) Fail(parameter, "unknown package '" + package + "' in " + uri);
    return slash == std::string::npos ? path : path + rest.substr(slash);
  }
  if (uri.rfind(file_prefix, 0) == 0) return uri.substr(file_prefix.size());
  return uri;
}

SimulationConfig LoadSimulationConfig(const ros::NodeHandle& private_handle) {
  XmlRpcValue root;
  if (!private_handle.getParam(private_handle.getNamespace(), root) ||
      root.getType() != XmlRpcValue::TypeStruct) {
    root = XmlRpcValue();
  }
  return LoadSimulationConfig(root);
}

SimulationConfig LoadSimulationConfig(XmlRpc::XmlRpcValue root) {
  SimulationConfig config;
  XmlRpcValue world;
  if (Get(root, "world", &world)) {
    if (world.getType() != XmlRpcValue::TypeStruct) Fail("~world", "expected a dictionary");
    config.world = ReadWorld(world);
  }
  config.objects = ReadObjects(root, config.world);
  XmlRpcValue inputs;
  if (Get(root, "wrench_inputs", &inputs))
    config.wrench_inputs = ReadWrenchInputs(inputs, config.objects);
  XmlRpcValue robot;
  if (Get(root, "robot", &robot)) config.robot = ReadRobot(robot);
  XmlRpcValue markers;
  if (Get(root, "markers", &markers)) config.markers = ReadMarkers(markers);
  return config;
}

}  // namespace msm_sim::ros_interface
