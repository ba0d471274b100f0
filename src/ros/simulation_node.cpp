#include "simulation_node.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <rosgraph_msgs/Clock.h>

#include "msm_sim/material/shore_hardness.h"

namespace msm_sim::ros_interface {
namespace {

// With world/publish_clock, /clock advances in ticks of this much simulated time (s): fine
// enough for joint states published on it to move a robot smoothly (robot/tf_delay covers a
// few ticks), coarse enough to cost nothing beside the steps.
constexpr double kClockPeriod = 0.005;

// The ROS time at which the simulated time was 0, if `now` is the ROS time at `simulated`
// seconds (never before ROS time 0).
ros::Time OriginOf(const ros::Time& now, double simulated) {
  return now - ros::Duration(std::min(simulated, now.toSec()));
}

}  // namespace

std::string RobotDescriptionParameter(const RobotConfig& config) {
  if (!config.enabled) return {};
  ros::NodeHandle handle("~");
  std::string key, description;
  if (handle.searchParam(config.description_param, key)) handle.getParam(key, description);
  return description;
}

SimulationNode::SimulationNode(ros::NodeHandle handle, ros::NodeHandle private_handle)
    : handle_(handle), private_handle_(private_handle), tf_listener_(tf_buffer_) {
  const SimulationConfig config = LoadSimulationConfig(private_handle);
  simulation_ = std::make_unique<Simulation>(config, RobotDescriptionParameter(config.robot));

  markers_ = private_handle_.advertise<visualization_msgs::MarkerArray>("markers", 1);
  contacts_ = private_handle_.advertise<msm_sim::ContactArray>("contacts", 10);
  state_ = private_handle_.advertise<sensor_msgs::PointCloud2>("state", 1);
  contact_points_ = private_handle_.advertise<sensor_msgs::PointCloud2>("contact_points", 10);
  diagnostics_ = handle_.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10);
  if (config.world.publish_clock) {
    clock_ = handle_.advertise<rosgraph_msgs::Clock>("/clock", 10);
    if (!ros::Time::isSimTime()) {
      ROS_WARN(
          "msm_sim: world/publish_clock is on but /use_sim_time is not: set the parameter "
          "/use_sim_time to true before the nodes start, so that they follow the simulated time");
    }
  }
  for (const RobotColliders::Link& link : simulation_->robot().links()) {
    link_wrenches_.push_back(private_handle_.advertise<geometry_msgs::WrenchStamped>(
        "links/" + link.name + "/wrench", 10));
    link_pressures_.push_back(private_handle_.advertise<sensor_msgs::PointCloud2>(
        "links/" + link.name + "/pressure", 10));
  }
  apply_force_ = private_handle_.subscribe("apply_force", 100, &SimulationNode::OnApplyForce, this);
  for (std::size_t i = 0; i < config.wrench_inputs.size(); ++i) {
    wrench_subscribers_.push_back(handle_.subscribe<geometry_msgs::WrenchStamped>(
        config.wrench_inputs[i].topic, 10,
        [this, i](const geometry_msgs::WrenchStamped::ConstPtr& message) {
          OnWrench(i, message);
        }));
  }
  reset_ = private_handle_.advertiseService("reset", &SimulationNode::OnReset, this);
  pause_ = private_handle_.advertiseService("pause", &SimulationNode::OnPause, this);
  resume_ = private_handle_.advertiseService("resume", &SimulationNode::OnResume, this);
  set_material_ =
      private_handle_.advertiseService("set_material", &SimulationNode::OnSetMaterial, this);

  last_publish_wall_ = ros::WallTime::now();
  StartTimer();
  tuning_ = std::make_unique<RuntimeTuning>(
      private_handle_, simulation_.get(),
      [this](double rate, bool real_time) { return SetPublishing(rate, real_time); });
}

void SimulationNode::StartTimer() {
  timer_.stop();
  wall_timer_.stop();
  const WorldConfig& world = simulation_->config().world;
  if (world.publish_clock) {
    // The simulation owns the clock: a ROS timer would wait for the /clock it publishes.
    wall_timer_ =
        handle_.createWallTimer(ros::WallDuration(1e-3), &SimulationNode::OnClockTimer, this);
  } else if (world.real_time) {
    // ros::Timer follows ROS time, so with use_sim_time /clock drives the stepping.
    timer_ = handle_.createTimer(ros::Duration(1.0 / world.publish_rate), &SimulationNode::OnTimer,
                                 this);
  } else {
    wall_timer_ =
        handle_.createWallTimer(ros::WallDuration(1e-4), &SimulationNode::OnWallTimer, this);
  }
}

std::string SimulationNode::SetPublishing(double publish_rate, bool real_time) {
  const bool was_real_time = simulation_->config().world.real_time;
  const std::string problem = simulation_->SetPublishing(publish_rate, real_time);
  if (!problem.empty()) return problem;
  // Real-time pacing restarts from the simulated time reached (as after a pause).
  if (real_time && !was_real_time) started_ = false;
  StartTimer();
  ROS_INFO("msm_sim: publishing at %g Hz, %s", publish_rate,
           real_time ? "paced in real time" : "as fast as possible");
  return {};
}

void SimulationNode::OnTimer(const ros::TimerEvent& event) {
  const ros::Time now = event.current_real;
  if (!started_) {
    origin_ = OriginOf(now, simulation_->time());  // 0 unless it ran unpaced before
    started_ = true;
  }
  if (!paused_) {
    // Catch up, but within 80 % of a publication period of wall time: a simulation slower
    // than real time then falls behind (the diagnostics' real-time factor says by how much)
    // instead of delaying every output.
    double behind = (now - origin_).toSec() - simulation_->time();
    if (behind > 0.5) {  // far behind: let the rest go rather than race to catch up later
      origin_ += ros::Duration(behind - 0.5);
      behind = 0.5;
    }
    simulation_->Advance(
        behind, now,
        ros::WallTime::now() + ros::WallDuration(0.8 / simulation_->config().world.publish_rate),
        &tf_buffer_, origin_);
  } else {
    simulation_->PlaceRobot(tf_buffer_, now);
    origin_ = OriginOf(now, simulation_->time());  // paused time does not count
  }
  Publish(now);
}

void SimulationNode::OnWallTimer(const ros::WallTimerEvent&) {
  // As fast as possible: one publication interval of simulated time per call.
  const ros::Time now = ros::Time::now();
  const double seconds = 1.0 / simulation_->config().world.publish_rate;
  if (paused_) {
    simulation_->PlaceRobot(tf_buffer_, now);
  } else {
    // The robot's tf of the coming interval of ROS time drives these steps.
    simulation_->Advance(seconds, now, ros::WallTime(), &tf_buffer_,
                         OriginOf(now, simulation_->time()));
  }
  Publish(now);
}

void SimulationNode::OnClockTimer(const ros::WallTimerEvent&) {
  const ros::WallTime wall = ros::WallTime::now();
  const WorldConfig& world = simulation_->config().world;
  const double period = 1.0 / world.publish_rate;
  if (!started_ || paused_) {
    // Paused time does not count towards the real-time pacing.
    wall_origin_ = wall - ros::WallDuration(simulation_->time());
    started_ = true;
  }
  if (paused_) {
    if ((wall - last_publish_wall_).toSec() < period) return;
    simulation_->PlaceRobot(tf_buffer_, ros::Time(simulation_->time()));
    Publish(ros::Time(simulation_->time()));
    return;
  }
  // With real_time, never ahead of the wall clock; far behind, let the rest go.
  const double ahead = simulation_->time() + period - (wall - wall_origin_).toSec();
  if (world.real_time && ahead > 0.0) return;
  if (-ahead > 0.5) wall_origin_ = wall - ros::WallDuration(simulation_->time() + 0.5);
  const double step = world.time_step;
  const double clock_period = std::max(1.0, std::round(kClockPeriod / step)) * step;
  for (double done = 0.0; done < period - 1e-9;) {
    const double tick = std::min(clock_period, period - done);
    simulation_->Advance(tick, ros::Time(simulation_->time()), ros::WallTime(), &tf_buffer_,
                         ros::Time());
    done += tick;
    rosgraph_msgs::Clock clock;
    clock.clock = ros::Time(simulation_->time());
    clock_.publish(clock);
  }
  Publish(ros::Time(simulation_->time()));
}

void SimulationNode::Publish(const ros::Time& stamp) {
  if (markers_.getNumSubscribers() > 0) markers_.publish(simulation_->Markers(stamp));
  // The contact points before Contacts, which starts a new interval.
  sensor_msgs::PointCloud2 contact_points;
  std::vector<sensor_msgs::PointCloud2> link_pressures;
  simulation_->ContactPointClouds(stamp, &contact_points, &link_pressures);
  contact_points_.publish(contact_points);
  std::vector<geometry_msgs::WrenchStamped> link_wrenches;
  contacts_.publish(simulation_->Contacts(stamp, &link_wrenches));
  for (std::size_t l = 0; l < link_wrenches.size(); ++l) {
    link_wrenches_[l].publish(link_wrenches[l]);
    link_pressures_[l].publish(link_pressures[l]);
  }
  if (state_.getNumSubscribers() > 0) state_.publish(simulation_->NodeCloud(stamp));
  // With use_sim_time the timer can fire twice at one clock value; tf refuses repeated stamps.
  if (stamp > last_frame_stamp_) {
    last_frame_stamp_ = stamp;
    for (const auto& frame : simulation_->Frames(stamp)) tf_broadcaster_.sendTransform(frame);
  }
  const ros::WallTime now = ros::WallTime::now();
  diagnostics_.publish(
      simulation_->Diagnostics(stamp, (now - last_publish_wall_).toSec(), paused_));
  last_publish_wall_ = now;
}

void SimulationNode::WarnDropped(const std::string& source, const std::string& reason) {
  // Throttle per kind: the reason up to its first quote or parenthesis.
  const std::string kind = source + ": " + reason.substr(0, reason.find_first_of("'(|"));
  const ros::WallTime now = ros::WallTime::now();
  const auto it = last_warning_.find(kind);
  if (it != last_warning_.end() && (now - it->second).toSec() < 1.0) return;
  last_warning_[kind] = now;
  ROS_WARN("msm_sim: %s: %s; dropped", source.c_str(), reason.c_str());
}

void SimulationNode::OnApplyForce(const msm_sim::ContactForce::ConstPtr& message) {
  const std::string problem = simulation_->ApplyForce(*message, tf_buffer_);
  if (!problem.empty()) WarnDropped("~apply_force", problem);
}

void SimulationNode::OnWrench(std::size_t index,
                              const geometry_msgs::WrenchStamped::ConstPtr& message) {
  const std::string problem = simulation_->SetWrench(index, *message, ros::Time::now(), tf_buffer_);
  if (!problem.empty()) {
    WarnDropped(simulation_->config().wrench_inputs[index].topic, problem);
  }
}

bool SimulationNode::OnReset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& response) {
  simulation_->Reset();
  origin_ = ros::Time::now();
  started_ = false;  // publish_clock: the clock starts again from 0
  response.success = true;
  response.message = "every object is back at rest in its rest shape";
  return true;
}

bool SimulationNode::OnPause(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& response) {
  paused_ = true;
  response.success = true;
  response.message = "paused";
  return true;
}

bool SimulationNode::OnResume(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& response) {
  paused_ = false;
  origin_ = OriginOf(ros::Time::now(), simulation_->time());
  response.success = true;
  response.message = "running";
  return true;
}

namespace {

// E from the request: youngs, or a Shore hardness converted by the core (0 = unused). Returns
// the reason when it cannot be had (several given, a reading outside its conversion's range).
std::string RequestedYoungs(const msm_sim::SetMaterial::Request& request, double* youngs) {
  *youngs = request.youngs;
  const int given = (request.youngs != 0.0) + (request.shore_a != 0.0) + (request.shore_00 != 0.0);
  if (given > 1) return "give one of youngs (Pa), shore_a and shore_00 (the others 0), not several";
  try {
    if (request.shore_a != 0.0) *youngs = core::YoungsFromShoreA(request.shore_a).youngs;
    if (request.shore_00 != 0.0) *youngs = core::YoungsFromShore00(request.shore_00).youngs;
  } catch (const std::out_of_range& error) {
    return std::string(error.what()) + "; give youngs (Pa) instead";
  }
  return {};
}

}  // namespace

bool SimulationNode::OnSetMaterial(msm_sim::SetMaterial::Request& request,
                                   msm_sim::SetMaterial::Response& response) {
  std::string described;
  double youngs = 0.0;
  std::string problem = RequestedYoungs(request, &youngs);
  if (problem.empty()) {
    problem = simulation_->SetMaterial(request.object, youngs, request.poisson, request.density,
                                       request.damping, request.friction, &described);
  }
  response.success = problem.empty();
  response.message =
      problem.empty() ? "'" + request.object + "' recalibrated: " + described : problem;
  return true;
}

}  // namespace msm_sim::ros_interface
