// Message storm (issue "Hardening"), against msm_sim_node running test/ros/push.yaml paced to
// real time (message_storm.test): ContactForce and WrenchStamped messages with random, NaN, Inf,
// denormal and huge values at 1 kHz for 60 s while ~set_material, ~reset, ~pause and ~resume
// are called in a loop. The node must stay up, keep publishing (over the storm at least 60 % of
// the rate it kept in the 5 s before the storm, and at least 40 % of it in every 10 s: a node
// the storm stalls loses most of its ticks; the rate is compared with one measured in the same
// run, so that a machine another build keeps busy slows both alike), never publish a non-finite
// value (markers, contacts, state, contact points, tf), and its resident memory must grow by less
// than 5 % after the first 10 s.
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <mutex>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <geometry_msgs/WrenchStamped.h>
#include <gtest/gtest.h>
#include <msm_sim/ContactArray.h>
#include <msm_sim/ContactForce.h>
#include <msm_sim/SetMaterial.h>
#include <ros/master.h>
#include <ros/network.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_srvs/Trigger.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/MarkerArray.h>
#include <xmlrpcpp/XmlRpcClient.h>

namespace {

constexpr double kStormSeconds = 60.0;
constexpr double kWarmUpSeconds = 10.0;
constexpr double kWindowSeconds = 10.0;
constexpr double kBaselineSeconds = 5.0;  // the node's publish rate before the storm

// Field values: ordinary ones in [-scale, scale], or (one in two) the values that break
// arithmetic: NaN, +-Inf, denormals, huge, the largest double.
class FieldValues {
 public:
  explicit FieldValues(std::uint32_t seed) : random_(seed) {}
  double operator()(double scale) {
    const double sign = Uniform(-1.0, 1.0) < 0.0 ? -1.0 : 1.0;
    switch (std::uniform_int_distribution<int>(0, 13)(random_)) {
      case 0:
        return std::numeric_limits<double>::quiet_NaN();
      case 1:
        return sign * std::numeric_limits<double>::infinity();
      case 2:
        return sign * std::numeric_limits<double>::denorm_min();
      case 3:
        return sign * 1e-310;  // denormal
      case 4:
        return sign * 1e300;
      case 5:
        return sign * std::numeric_limits<double>::max();
      case 6:
        return sign * 1e6 * scale;
      default:
        return scale * Uniform(-1.0, 1.0);
    }
  }
  double Uniform(double low, double high) {
    return std::uniform_real_distribution<double>(low, high)(random_);
  }
  bool Chance(double p) { return Uniform(0.0, 1.0) < p; }

 private:
  std::mt19937 random_;
};

msm_sim::ContactForce StormForce(FieldValues& value) {
  msm_sim::ContactForce m;
  m.header.frame_id = value.Chance(0.9) ? "world" : (value.Chance(0.5) ? "" : "no_such_frame");
  m.object = value.Chance(0.95) ? "block" : "no_such_object";
  m.point.x = value(0.05);
  m.point.y = value(0.05);
  m.point.z = 0.05 + value(0.05);
  m.force.x = value(20.0);
  m.force.y = value(20.0);
  m.force.z = value(20.0);
  m.radius = std::abs(value(0.03));
  m.duration = std::abs(value(0.05));
  return m;
}

geometry_msgs::WrenchStamped StormWrench(FieldValues& value) {
  geometry_msgs::WrenchStamped w;
  w.header.frame_id = value.Chance(0.9) ? "world" : "no_such_frame";
  w.header.stamp = ros::Time::now();
  w.wrench.force.x = value(20.0);
  w.wrench.force.y = value(20.0);
  w.wrench.force.z = value(20.0);
  w.wrench.torque.x = value(0.5);
  w.wrench.torque.y = value(0.5);
  w.wrench.torque.z = value(0.5);
  return w;
}

bool Finite(double a, double b, double c) {
  return std::isfinite(a) && std::isfinite(b) && std::isfinite(c);
}

// Every float32 and float64 field of every point.
bool Finite(const sensor_msgs::PointCloud2& cloud) {
  const std::size_t points = static_cast<std::size_t>(cloud.width) * cloud.height;
  for (std::size_t p = 0; p < points; ++p) {
    for (const sensor_msgs::PointField& field : cloud.fields) {
      const std::uint8_t* at = cloud.data.data() + p * cloud.point_step + field.offset;
      if (field.datatype == sensor_msgs::PointField::FLOAT32) {
        float v;
        std::memcpy(&v, at, sizeof v);
        if (!std::isfinite(v)) return false;
      } else if (field.datatype == sensor_msgs::PointField::FLOAT64) {
        double v;
        std::memcpy(&v, at, sizeof v);
        if (!std::isfinite(v)) return false;
      }
    }
  }
  return true;
}

bool Finite(const visualization_msgs::MarkerArray& array) {
  for (const auto& m : array.markers) {
    const auto& p = m.pose;
    if (!Finite(p.position.x, p.position.y, p.position.z) ||
        !Finite(p.orientation.x, p.orientation.y, p.orientation.z + p.orientation.w) ||
        !Finite(m.scale.x, m.scale.y, m.scale.z)) {
      return false;
    }
    for (const auto& q : m.points) {
      if (!Finite(q.x, q.y, q.z)) return false;
    }
    for (const auto& c : m.colors) {
      if (!Finite(c.r, c.g, c.b + c.a)) return false;
    }
  }
  return true;
}

bool Finite(const msm_sim::ContactArray& array) {
  for (const auto& c : array.contacts) {
    const auto& w = c.wrench;
    if (!Finite(w.force.x, w.force.y, w.force.z) || !Finite(w.torque.x, w.torque.y, w.torque.z) ||
        !Finite(c.centroid.x, c.centroid.y, c.centroid.z) ||
        !Finite(c.normal.x, c.normal.y, c.normal.z) || !Finite(c.area, c.mean_pressure, 0.0)) {
      return false;
    }
  }
  return true;
}

bool Finite(const tf2_msgs::TFMessage& message) {
  for (const auto& t : message.transforms) {
    const auto& v = t.transform.translation;
    const auto& r = t.transform.rotation;
    if (!Finite(v.x, v.y, v.z) || !Finite(r.x, r.y, r.z + r.w)) return false;
  }
  return true;
}

// The node's outputs, counted and checked for non-finite values as they come (callbacks run on
// an AsyncSpinner thread).
class OutputWatch {
 public:
  OutputWatch() {
    Watch<msm_sim::ContactArray>("/msm_sim/contacts", 0);
    Watch<visualization_msgs::MarkerArray>("/msm_sim/markers", 1);
    Watch<sensor_msgs::PointCloud2>("/msm_sim/state", 2);
    Watch<sensor_msgs::PointCloud2>("/msm_sim/contact_points", 3);
    Watch<tf2_msgs::TFMessage>("/tf", 4);
  }
  static constexpr int kTopics = 5;
  std::array<std::string, kTopics> topics;
  std::array<std::atomic<long>, kTopics> received{}, non_finite{};
  std::array<std::string, kTopics> first_non_finite;  // the first one, printed
  long contacts() const { return received[0]; }
  long TotalReceived() const { return Sum(received); }
  long TotalNonFinite() const { return Sum(non_finite); }

  // Prints the counts per topic; fails for a topic that published nothing or a non-finite value.
  void ExpectEachTopicFinite() {
    for (int t = 0; t < kTopics; ++t) {
      std::printf("  %s: %ld messages, %ld non-finite\n", topics[t].c_str(), received[t].load(),
                  non_finite[t].load());
      EXPECT_GT(received[t], 0) << topics[t];
      EXPECT_EQ(non_finite[t], 0) << topics[t] << ", the first:\n" << first_non_finite[t];
    }
  }

 private:
  template <class Message>
  void Watch(const std::string& topic, int index) {
    topics[index] = topic;
    subscribers_.push_back(handle_.subscribe<Message>(
        topic, 100, [this, index](const typename Message::ConstPtr& message) {
          ++received[index];
          if (Finite(*message)) return;
          if (non_finite[index]++ > 0) return;
          std::ostringstream text;
          text << *message;
          std::lock_guard<std::mutex> lock(mutex_);
          first_non_finite[index] = text.str().substr(0, 3000);
        }));
  }
  static long Sum(const std::array<std::atomic<long>, kTopics>& counts) {
    long sum = 0;
    for (const auto& c : counts) sum += c;
    return sum;
  }

  std::mutex mutex_;
  ros::NodeHandle handle_;
  std::vector<ros::Subscriber> subscribers_;
};

// The node's process id, from its XML-RPC server (ROS master API getPid); 0 if unknown.
int NodePid(const std::string& node) {
  XmlRpc::XmlRpcValue request, response, payload;
  request[0] = ros::this_node::getName();
  request[1] = node;
  if (!ros::master::execute("lookupNode", request, response, payload, true)) return 0;
  std::string host;
  std::uint32_t port = 0;
  if (!ros::network::splitURI(static_cast<std::string>(payload), host, port)) return 0;
  XmlRpc::XmlRpcClient client(host.c_str(), static_cast<int>(port), "/");
  XmlRpc::XmlRpcValue pid_request, pid_response;
  pid_request[0] = ros::this_node::getName();
  if (!client.execute("getPid", pid_request, pid_response)) return 0;
  return static_cast<int>(pid_response[2]);
}

// VmRSS of a process (kB), 0 if it is gone.
long ResidentKilobytes(int pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  }
  return 0;
}

// ~set_material (valid and invalid requests), ~reset, ~pause, ~resume, round and round until
// `stop`; counts the calls that did not reach the node.
void CallServicesInALoop(const std::atomic<bool>& stop, std::atomic<long>* calls,
                         std::atomic<long>* failures) {
  ros::NodeHandle handle;
  ros::ServiceClient material = handle.serviceClient<msm_sim::SetMaterial>("/msm_sim/set_material");
  std::vector<ros::ServiceClient> triggers;
  for (const char* name : {"/msm_sim/reset", "/msm_sim/pause", "/msm_sim/resume"}) {
    triggers.push_back(handle.serviceClient<std_srvs::Trigger>(name));
  }
  FieldValues value(7);
  for (int round = 0; !stop; ++round) {
    msm_sim::SetMaterial request;
    request.request.object = value.Chance(0.9) ? "block" : "no_such_object";
    request.request.youngs = round % 2 == 0 ? value.Uniform(2e4, 1e5) : value(1e5);
    request.request.poisson = round % 2 == 0 ? value.Uniform(0.1, 0.45) : value(0.5);
    request.request.density = round % 2 == 0 ? value.Uniform(500.0, 2000.0) : value(1e3);
    request.request.damping = std::abs(value.Uniform(0.0, 0.004));
    request.request.friction = value.Uniform(0.0, 1.0);
    *failures += material.call(request) ? 0 : 1;
    ++*calls;
    for (ros::ServiceClient& trigger : triggers) {
      ros::WallDuration(0.05).sleep();
      std_srvs::Trigger call;
      *failures += trigger.call(call) ? 0 : 1;
      ++*calls;
    }
  }
}

// The node's contacts rate (Hz) over kBaselineSeconds of wall time from now.
double BaselineRate(const OutputWatch& outputs) {
  const long baseline_contacts = outputs.contacts();
  const ros::WallTime baseline_start = ros::WallTime::now();
  ros::WallDuration(kBaselineSeconds).sleep();
  return (outputs.contacts() - baseline_contacts) / (ros::WallTime::now() - baseline_start).toSec();
}

// What the storm's publishing loop saw.
struct StormFigures {
  ros::WallTime start;
  long storm_contacts = 0;  // contacts received before the storm
  long sent = 0, rss_after_warm_up = 0, rss_peak = 0;
  double worst_window_rate = 1e30;  // Hz, in the slowest kWindowSeconds
};

// The storm at 1 kHz for kStormSeconds, measuring the contacts' rate and the node's memory.
StormFigures PublishStorm(ros::Publisher& forces, ros::Publisher& wrenches,
                          const OutputWatch& outputs, int pid) {
  StormFigures f;
  FieldValues value(42);
  f.start = ros::WallTime::now();
  ros::WallRate rate(1000.0);
  double window_start = 0.0;
  f.storm_contacts = outputs.contacts();
  long window_contacts = f.storm_contacts;
  for (double t = 0.0; t < kStormSeconds; t = (ros::WallTime::now() - f.start).toSec()) {
    forces.publish(StormForce(value));
    wrenches.publish(StormWrench(value));
    f.sent += 2;
    if (t - window_start >= kWindowSeconds) {
      const double measured = (outputs.contacts() - window_contacts) / (t - window_start);
      f.worst_window_rate = std::min(f.worst_window_rate, measured);
      std::printf("  t %4.1f s: contacts at %.2f Hz, RSS %ld kB\n", t, measured,
                  ResidentKilobytes(pid));
      window_start = t;
      window_contacts = outputs.contacts();
    }
    if (t >= kWarmUpSeconds) {
      const long rss = ResidentKilobytes(pid);
      if (f.rss_after_warm_up == 0) f.rss_after_warm_up = rss;
      f.rss_peak = std::max(f.rss_peak, rss);
    }
    rate.sleep();
  }
  return f;
}

TEST(MessageStorm, NodeStaysUpAtItsRateFiniteAndFlat) {
  ros::NodeHandle handle;
  ros::AsyncSpinner spinner(1);
  spinner.start();
  OutputWatch outputs;
  ros::Publisher forces = handle.advertise<msm_sim::ContactForce>("/msm_sim/apply_force", 1000);
  ros::Publisher wrenches = handle.advertise<geometry_msgs::WrenchStamped>("/pusher/wrench", 1000);
  ASSERT_TRUE(ros::service::waitForService("/msm_sim/set_material", 30000));
  const ros::WallTime ready = ros::WallTime::now() + ros::WallDuration(10.0);
  while (outputs.contacts() == 0 && ros::WallTime::now() < ready) ros::WallDuration(0.01).sleep();
  ASSERT_GT(outputs.contacts(), 0) << "the node publishes no contacts";
  const int pid = NodePid("/msm_sim");
  ASSERT_GT(pid, 0);
  const double baseline_rate = BaselineRate(outputs);
  ASSERT_GT(baseline_rate, 0.0) << "the node publishes no contacts before the storm";

  std::atomic<bool> stop{false};
  std::atomic<long> calls{0}, failures{0};
  std::thread services(CallServicesInALoop, std::cref(stop), &calls, &failures);
  const StormFigures f = PublishStorm(forces, wrenches, outputs, pid);
  stop = true;
  services.join();
  const double seconds = (ros::WallTime::now() - f.start).toSec();
  const double mean_rate = (outputs.contacts() - f.storm_contacts) / seconds;
  std::printf(
      "  %ld messages in %.1f s (%.0f /s), %ld service calls (%ld unanswered), %ld outputs "
      "checked, %ld non-finite; contacts at %.1f Hz before the storm, %.1f Hz over it, %.1f Hz "
      "in its slowest 10 s; RSS %ld kB at 10 s, peak %ld kB after (%.2f %%)\n",
      f.sent, seconds, f.sent / seconds, calls.load(), failures.load(), outputs.TotalReceived(),
      outputs.TotalNonFinite(), baseline_rate, mean_rate, f.worst_window_rate, f.rss_after_warm_up,
      f.rss_peak, 100.0 * (f.rss_peak - f.rss_after_warm_up) / f.rss_after_warm_up);
  EXPECT_GT(ResidentKilobytes(pid), 0) << "the node is gone";
  EXPECT_EQ(failures, 0);
  outputs.ExpectEachTopicFinite();
  EXPECT_GT(mean_rate, 0.6 * baseline_rate);
  EXPECT_GT(f.worst_window_rate, 0.4 * baseline_rate);
  EXPECT_LT(f.rss_peak, 1.05 * f.rss_after_warm_up);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "message_storm_test");
  return RUN_ALL_TESTS();
}
