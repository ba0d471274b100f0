// What a hostile or careless publisher sends, driven into the node's Simulation without a ROS
// master (docs/robustness.md): a flood of long pushes keeps memory and the step's cost flat, and a
// link pose far outside the world never reaches its collider, so the wrench read afterwards is
// the clean press's.
#include <ctime>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <ros/time.h>
#include <tf2/buffer_core.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include "simulation.h"

namespace msm_sim::ros_interface {
namespace {

using XmlRpc::XmlRpcValue;

XmlRpcValue List(std::initializer_list<double> values) {
  XmlRpcValue list;
  int i = 0;
  for (const double v : values) list[i++] = v;
  return list;
}

// config/default.yaml's scene: the Ecoflex block 8 x 6 x 3 cm at 5 mm, its base clamped.
XmlRpcValue DefaultScene() {
  XmlRpcValue scene;
  scene["world"]["ground"]["friction"] = 0.6;
  XmlRpcValue& block = scene["objects"][0];
  block["name"] = std::string("soft_block");
  block["shape"]["type"] = std::string("box");
  block["shape"]["size"] = List({0.08, 0.06, 0.03});
  block["pose"]["position"] = List({0.0, 0.0, 0.015});
  block["spacing"] = 0.005;
  block["youngs"] = 1e5;
  block["poisson"] = 0.49;
  block["density"] = 1070.0;
  block["damping"] = 2e-4;
  block["friction"] = 0.6;
  block["clamps"][0]["name"] = std::string("table_clamp");
  block["clamps"][0]["half_space"]["point"] = List({0.0, 0.0, 0.005});
  block["clamps"][0]["half_space"]["normal"] = List({0.0, 0.0, 1.0});
  return scene;
}

class SimulationInputs : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { ros::Time::init(); }  // the throttled warnings read the clock
};

double ThreadSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Resident memory of this process (kB).
long ResidentKilobytes() {
  std::ifstream statm("/proc/self/statm");
  long size = 0, resident = 0;
  statm >> size >> resident;
  return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

// Thread CPU seconds per 1 ms step over `steps` steps.
double StepSeconds(Simulation* simulation, const tf2::BufferCore& tf, int steps) {
  const double start = ThreadSeconds();
  for (int k = 0; k < steps; ++k) simulation->Advance(1e-3, ros::Time(1.0), ros::WallTime(), &tf);
  return (ThreadSeconds() - start) / steps;
}

// `messages` pushes on the block's top, spread over `steps` steps of 1 ms.
void Flood(Simulation* simulation, const tf2::BufferCore& tf, const msm_sim::ContactForce& push,
           int messages, int steps) {
  for (int k = 0; k < messages; ++k) {
    ASSERT_EQ(simulation->ApplyForce(push, tf), "");
    if ((k + 1) % (messages / steps) == 0) {
      simulation->Advance(1e-3, ros::Time(1.0), ros::WallTime(), &tf);
    }
  }
}

msm_sim::ContactForce Push(double fx, double fz, double radius, double duration) {
  msm_sim::ContactForce push;
  push.header.frame_id = "world";
  push.object = "soft_block";
  push.point.z = 0.03;
  push.force.x = fx;
  push.force.z = fz;
  push.radius = radius;
  push.duration = duration;
  return push;
}

// The issue's flood (-1 mN pushes lasting 10^6 s, 60,000 of them: 30 s at 2 kHz) and a second
// one (0.5 N sideways on one node, 10,000, with a bound of 20 pushes): memory within 10 % and
// the step's cost within 2x of before.
TEST_F(SimulationInputs, AFloodOfLongPushesKeepsMemoryAndStepTimeFlat) {
  struct Case {
    msm_sim::ContactForce push;
    int messages;
    int max_pending;
  };
  const std::vector<Case> cases = {{Push(0.0, -1e-3, 0.01, 1e6), 60000, 100},
                                   {Push(0.5, 0.0, 0.0, 100.0), 10000, 20}};
  for (const Case& c : cases) {
    XmlRpcValue scene = DefaultScene();
    scene["world"]["max_pending_pushes"] = c.max_pending;
    Simulation simulation(LoadSimulationConfig(scene), "");
    tf2::BufferCore tf;
    StepSeconds(&simulation, tf, 200);  // warm up
    const double before = StepSeconds(&simulation, tf, 300);
    Flood(&simulation, tf, c.push, c.messages / 2, 500);
    const long memory = ResidentKilobytes();
    Flood(&simulation, tf, c.push, c.messages / 2, 500);
    const double after = StepSeconds(&simulation, tf, 300);
    EXPECT_LE(ResidentKilobytes(), memory * 1.1) << c.messages << " pushes";
    EXPECT_LE(after, 2.0 * before) << before << " s per step before, " << after << " s after";
    std::printf("  %d pushes: %.3f ms per step before, %.3f ms after; RSS %ld kB -> %ld kB\n",
                c.messages, 1e3 * before, 1e3 * after, memory, ResidentKilobytes());
  }
}

// A pose outside ~world/max_distance (and through it any frame) is refused for a push.
TEST_F(SimulationInputs, APushFarOutsideTheWorldIsRefused) {
  Simulation simulation(LoadSimulationConfig(DefaultScene()), "");
  tf2::BufferCore tf;
  msm_sim::ContactForce push = Push(0.0, -1.0, 0.01, 0.0);
  for (const double z : {1e30, 501.0}) {
    push.point.z = z;
    EXPECT_NE(simulation.ApplyForce(push, tf).find("~world/max_distance"), std::string::npos);
  }
  geometry_msgs::TransformStamped far;
  far.header.frame_id = "world";
  far.child_frame_id = "far";
  far.transform.translation.z = 1e30;
  far.transform.rotation.w = 1.0;
  tf.setTransform(far, "test", true);
  push.point.z = 0.0;
  push.header.frame_id = "far";
  EXPECT_NE(simulation.ApplyForce(push, tf).find("~world/max_distance"), std::string::npos);
}

// A robot of one link, a 1 cm sphere.
constexpr char kSphereRobot[] = R"(<robot name="prober">
  <link name="finger"><collision><geometry><sphere radius="0.01"/></geometry></collision></link>
</robot>)";

// The sphere's centre 4 mm into the block's top (z = 3 cm).
constexpr double kPressZ = 0.03 + 0.01 - 0.004;

geometry_msgs::TransformStamped FingerAt(double x, double z, const ros::Time& stamp) {
  geometry_msgs::TransformStamped t;
  t.header.frame_id = "world";
  t.header.stamp = stamp;
  t.child_frame_id = "finger";
  t.transform.translation.x = x;
  t.transform.translation.z = z;
  t.transform.rotation.w = 1.0;
  return t;
}

// The finger's wrench (world axes, N) averaged over the last 0.5 s of `seconds` of tf samples at
// 100 Hz, `hostile` before `settle` s of them and the clean press after.
Eigen::Vector3d PressWrench(
    double settle, double hostile_seconds,
    const std::function<geometry_msgs::TransformStamped(int, ros::Time)>& hostile) {
  XmlRpcValue scene = DefaultScene();
  scene["robot"]["links"][0] = std::string("finger");
  Simulation simulation(LoadSimulationConfig(scene), kSphereRobot);
  tf2::BufferCore tf(ros::Duration(10.0));
  const ros::Time origin(100.0);
  const int hostile_ticks = static_cast<int>(hostile_seconds * 100.0 + 0.5);
  const int ticks = hostile_ticks + static_cast<int>(settle * 100.0 + 0.5);
  std::vector<geometry_msgs::WrenchStamped> links;
  for (int k = 0; k <= ticks; ++k) {
    const ros::Time now = origin + ros::Duration(0.01 * k);
    tf.setTransform(k < hostile_ticks ? hostile(k, now) : FingerAt(0.0, kPressZ, now), "test");
    simulation.Advance(0.01 * k - simulation.time(), now, ros::WallTime(), &tf, origin);
    if (k == ticks - 50) simulation.Contacts(now, &links);  // the last 0.5 s from here
  }
  simulation.Contacts(origin + ros::Duration(0.01 * ticks), &links);
  const geometry_msgs::Vector3& f = links.at(0).wrench.force;
  return {f.x, f.y, f.z};
}

// The issue's link (tf alternating between z = 10^30 and the press at 100 Hz for 5 s, then the
// press) and a second (alternating between the press and 1 m aside, 100 m/s): the wrench after
// them is the clean press's within 5 %, as if the hostile poses had never come.
TEST_F(SimulationInputs, HugeOrFastLinkPosesNeverReachTheCollider) {
  const Eigen::Vector3d clean = PressWrench(1.5, 0.0, nullptr);
  ASSERT_GT(clean.z(), 1.0) << "the press must push the finger up";
  const std::vector<std::pair<std::string, double>> cases = {{"z = 1e30", 1e30},
                                                             {"1 m aside", 1.0}};
  for (const auto& [name, offset] : cases) {
    const Eigen::Vector3d wrench = PressWrench(1.5, 5.0, [&](int k, const ros::Time& stamp) {
      if (k % 2 == 0) return FingerAt(0.0, kPressZ, stamp);
      return offset > 100.0 ? FingerAt(0.0, offset, stamp) : FingerAt(offset, kPressZ, stamp);
    });
    EXPECT_LT((wrench - clean).norm(), 0.05 * clean.norm())
        << name << ": " << wrench.transpose() << " N against the clean " << clean.transpose();
    std::ostringstream report;
    report << name << ": " << wrench.transpose() << " N (clean " << clean.transpose() << " N)";
    std::printf("  %s\n", report.str().c_str());
  }
}

}  // namespace
}  // namespace msm_sim::ros_interface
