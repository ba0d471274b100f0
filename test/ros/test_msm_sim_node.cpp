// rostests of msm_sim_node (issue "The ROS node"): each .test file starts the node with a scene
// from this directory and runs one suite of this executable against it.
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <geometry_msgs/WrenchStamped.h>
#include <gtest/gtest.h>
#include <msm_sim/SetMaterial.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <visualization_msgs/MarkerArray.h>

#include <Eigen/Core>
#include "node_test_support.h"

namespace msm_sim_test {
std::vector<std::string> g_expected_errors;
}  // namespace msm_sim_test

namespace {

using msm_sim_test::Finite;
using msm_sim_test::g_expected_errors;
using msm_sim_test::NodeOutputs;
using msm_sim_test::StampedRate;
using msm_sim_test::WaitFor;

// 1. A known force on a block clamped at its base (no gravity): after settling, the clamp's
// contact force equals the applied force within 2 %.
TEST(Push, ClampForceEqualsTheAppliedForce) {
  NodeOutputs node;
  ASSERT_TRUE(node.WaitForNode());
  const Eigen::Vector3d force(2.0, -1.0, -3.0);
  node.Push("block", Eigen::Vector3d(0.0, 0.0, 0.1), force, 0.03, 1000.0);
  ASSERT_TRUE(node.WaitSimulated(3.0));
  const std::size_t before = node.contacts.size();
  ASSERT_TRUE(node.WaitSimulated(0.5));
  const Eigen::Vector3d clamp = node.MeanForce("base", node.contacts.size() - before);
  std::printf("  clamp force (%.4f, %.4f, %.4f) N, applied (%.1f, %.1f, %.1f) N\n", clamp.x(),
              clamp.y(), clamp.z(), force.x(), force.y(), force.z());
  EXPECT_LT((clamp - force).norm(), 0.02 * force.norm());
}

// A configured WrenchStamped topic pushes at the origin of its frame (tf2) while messages come,
// and lets go half a second after they stop.
TEST(WrenchInput, PushesAtItsFrameWhileMessagesCome) {
  NodeOutputs node;
  ros::NodeHandle handle;
  ASSERT_TRUE(node.WaitForNode());
  tf2_ros::StaticTransformBroadcaster frames;
  geometry_msgs::TransformStamped pusher;
  pusher.header.stamp = ros::Time::now();
  pusher.header.frame_id = "world";
  pusher.child_frame_id = "pusher";
  pusher.transform.translation.z = 0.1;  // the block's top face
  pusher.transform.rotation.z = 1.0;     // turned half a turn about z: x becomes -x
  frames.sendTransform(pusher);
  ros::Publisher wrench = handle.advertise<geometry_msgs::WrenchStamped>("/pusher/wrench", 10);
  ASSERT_TRUE(WaitFor([&] { return wrench.getNumSubscribers() > 0; }, 10.0));
  geometry_msgs::WrenchStamped message;
  message.header.frame_id = "pusher";
  message.wrench.force.x = 1.5;  // -1.5 N along the world's x
  message.wrench.force.z = -2.0;
  const double start = node.simulated_time;
  const auto push_until = [&](double simulated) {
    while (node.simulated_time < simulated && ros::ok()) {
      message.header.stamp = ros::Time::now();
      wrench.publish(message);
      WaitFor([] { return false; }, 0.02);
    }
  };
  push_until(start + 2.5);  // settle
  const std::size_t settled = node.contacts.size();
  // Then 20 more publications (0.4 s of simulation) while the wrench still comes.
  while (node.contacts.size() < settled + 20 && ros::ok()) {
    message.header.stamp = ros::Time::now();
    wrench.publish(message);
    WaitFor([] { return false; }, 0.005);
  }
  const Eigen::Vector3d clamp = node.MeanForce("base", node.contacts.size() - settled);
  std::printf("  clamp force (%.4f, %.4f, %.4f) N for a wrench of (-1.5, 0, -2) N in the world\n",
              clamp.x(), clamp.y(), clamp.z());
  EXPECT_LT((clamp - Eigen::Vector3d(-1.5, 0.0, -2.0)).norm(), 0.05 * 2.5);
  // Messages stop: the push ends after the hold time and the clamp unloads.
  WaitFor([] { return false; }, 1.5);
  ASSERT_TRUE(node.WaitSimulated(1.0));
  EXPECT_LT(node.MeanForce("base", 10).norm(), 0.05);
}

// 2. A block resting on the ground loads it with its weight within 2 %.
TEST(Ground, RestingBlockLoadsTheGroundWithItsWeight) {
  NodeOutputs node;
  ASSERT_TRUE(node.WaitForNode());
  ASSERT_TRUE(node.WaitSimulated(3.0));
  const std::size_t before = node.contacts.size();
  ASSERT_TRUE(node.WaitSimulated(1.0));
  const Eigen::Vector3d ground = node.MeanForce("ground", node.contacts.size() - before);
  const double weight = 1000.0 * 0.1 * 0.1 * 0.05 * 9.81;
  std::printf("  ground force (%.4f, %.4f, %.4f) N, weight %.4f N\n", ground.x(), ground.y(),
              ground.z(), weight);
  EXPECT_NEAR(-ground.z() / weight, 1.0, 0.02);
  EXPECT_LT(ground.head<2>().norm(), 0.02 * weight);
}

// 3. Markers: the visual mesh's triangles, finite, in the world frame, at the configured rate.
TEST(Markers, SurfaceMatchesTheVisualMeshAtTheConfiguredRate) {
  ros::NodeHandle handle;
  std::vector<visualization_msgs::MarkerArray> received;
  ros::Subscriber subscriber = handle.subscribe<visualization_msgs::MarkerArray>(
      "/msm_sim/markers", 100, [&](const visualization_msgs::MarkerArray::ConstPtr& message) {
        received.push_back(*message);
      });
  ASSERT_TRUE(WaitFor([&] { return received.size() >= 3; }, 30.0));
  const std::size_t first = received.size();
  WaitFor([] { return false; }, 5.0);
  std::vector<ros::Time> stamps;
  for (std::size_t m = first; m < received.size(); ++m) {
    if (!received[m].markers.empty()) stamps.push_back(received[m].markers[0].header.stamp);
  }
  const double rate = StampedRate(stamps);
  std::printf("  markers at %.2f Hz by their stamps (configured 20 Hz)\n", rate);
  EXPECT_NEAR(rate / 20.0, 1.0, 0.10);
  const int kBeanTriangles = 5120;  // meshes/soft_bean.obj
  for (const auto& array : received) {
    ASSERT_EQ(array.markers.size(), 1u);
    const visualization_msgs::Marker& marker = array.markers[0];
    EXPECT_EQ(marker.header.frame_id, "world");
    EXPECT_EQ(marker.ns, "bean");
    EXPECT_EQ(marker.type, visualization_msgs::Marker::TRIANGLE_LIST);
    ASSERT_EQ(marker.points.size(), 3u * kBeanTriangles);
    EXPECT_EQ(marker.colors.size(), marker.points.size());
    for (const auto& p : marker.points) ASSERT_TRUE(Finite(p));
    for (const auto& c : marker.colors) ASSERT_TRUE(std::isfinite(c.r + c.g + c.b + c.a));
  }
}

// 4. Bad messages are dropped with a warning naming the problem; the node keeps going.
TEST(BadMessages, AreDroppedWithAWarningAndTheNodeKeepsRunning) {
  NodeOutputs node;
  ASSERT_TRUE(node.WaitForNode());
  const double nan = std::nan("");
  const double inf = std::numeric_limits<double>::infinity();
  node.Push("block", Eigen::Vector3d(nan, 0.0, 0.1), Eigen::Vector3d(0, 0, -1), 0.03, 1.0);
  node.Push("block", Eigen::Vector3d(0.0, 0.0, 0.1), Eigen::Vector3d(inf, 0, 0), 0.03, 1.0);
  ros::WallDuration(1.1).sleep();  // the warnings are throttled per kind
  node.Push("no_such_object", Eigen::Vector3d(0, 0, 0.1), Eigen::Vector3d(0, 0, -1), 0.03, 1.0);
  node.Push("block", Eigen::Vector3d(0, 0, 0.1), Eigen::Vector3d(0, 0, -1), 0.03, 1.0,
            "no_such_frame");
  node.Push("block", Eigen::Vector3d(0, 0, 0.1), Eigen::Vector3d(0, 0, -1e9), 0.03, 1.0);
  const std::vector<std::string> expected = {"NaN or Inf", "unknown object", "unknown frame",
                                             "absurd"};
  const auto all_warned = [&] {
    for (const std::string& text : expected) {
      bool found = false;
      for (const std::string& w : node.warnings) found = found || w.find(text) != std::string::npos;
      if (!found) return false;
    }
    return true;
  };
  EXPECT_TRUE(WaitFor(all_warned, 10.0));
  for (const std::string& w : node.warnings) std::printf("  warning: %s\n", w.c_str());
  // Still stepping and publishing, and nothing was applied: the clamp feels no force.
  const double before = node.simulated_time;
  ASSERT_TRUE(node.WaitSimulated(1.0));
  EXPECT_GT(node.simulated_time, before);
  EXPECT_LT(node.MeanForce("base", 10).norm(), 1e-6);
}

Eigen::Vector3d MeanDisplacement(const std::vector<Eigen::Vector3d>& now,
                                 const std::vector<Eigen::Vector3d>& rest,
                                 const Eigen::Vector3d& centre, double radius) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int count = 0;
  for (std::size_t i = 0; i < rest.size(); ++i) {
    if ((rest[i] - centre).norm() > radius) continue;
    sum += now[i] - rest[i];
    ++count;
  }
  return sum / count;
}

// The mean downward displacement near `top` in the next state the node publishes (m).
double ReadDeflection(NodeOutputs& node, const std::vector<Eigen::Vector3d>& rest,
                      const Eigen::Vector3d& top) {
  node.has_state = false;
  EXPECT_TRUE(WaitFor([&] { return node.has_state; }, 10.0));
  return -MeanDisplacement(node.Points(), rest, top, 0.025).z();
}

// Pushes the block at `top` and returns its settled deflection there.
// The node runs as fast as it can, so when the push starts acting (its message's arrival) is
// not tied to the simulated clock: wait 3 s, then until two readings 0.5 s apart agree.
double SettledDeflection(NodeOutputs& node, const std::vector<Eigen::Vector3d>& rest,
                         const Eigen::Vector3d& top, const Eigen::Vector3d& force) {
  node.Push("block", top, force, 0.025, 1000.0);
  EXPECT_TRUE(node.WaitSimulated(3.0));
  double previous = ReadDeflection(node, rest, top);
  for (int k = 0; k < 20; ++k) {
    EXPECT_TRUE(node.WaitSimulated(0.5));
    const double current = ReadDeflection(node, rest, top);
    if (std::abs(current - previous) <= 0.002 * std::abs(current)) return current;
    previous = current;
  }
  return previous;
}

// Calls a std_srvs/Trigger service, which must answer with success.
void CallTrigger(const std::string& service) {
  std_srvs::Trigger trigger;
  EXPECT_TRUE(ros::service::waitForService(service, 10000));
  EXPECT_TRUE(ros::service::call(service, trigger));
  EXPECT_TRUE(trigger.response.success) << trigger.response.message;
}

// The largest distance between corresponding points (m).
double LargestDistance(const std::vector<Eigen::Vector3d>& a,
                       const std::vector<Eigen::Vector3d>& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < b.size(); ++i) worst = std::max(worst, (a[i] - b[i]).norm());
  return worst;
}

// Calls ~set_material with `material`, expecting it refused with a reason naming `reason`;
// false if the call itself failed.
bool CallRefused(msm_sim::SetMaterial& material, const std::string& reason) {
  if (!ros::service::call("/msm_sim/set_material", material)) return false;
  EXPECT_FALSE(material.response.success);
  EXPECT_NE(material.response.message.find(reason), std::string::npos) << material.response.message;
  return true;
}

// Variants of the valid request `material`: each answered as docs/materials.md says.
void ExpectSetMaterialChecksItsRequest(msm_sim::SetMaterial& material) {
  // A bad request is refused with a reason and changes nothing.
  material.request.poisson = 0.7;
  ASSERT_TRUE(CallRefused(material, "Poisson"));
  // A Shore hardness instead of youngs (docs/materials.md): converted, or refused with a reason.
  material.request.poisson = 0.3;
  material.request.youngs = 0.0;
  material.request.shore_00 = 90.0;  // Shore A 50: Gent's E = 2.456 MPa
  ASSERT_TRUE(ros::service::call("/msm_sim/set_material", material));
  EXPECT_TRUE(material.response.success) << material.response.message;
  EXPECT_NE(material.response.message.find("2.45"), std::string::npos) << material.response.message;
  material.request.shore_a = 50.0;
  ASSERT_TRUE(CallRefused(material, "not several"));
  material.request.shore_00 = 0.0;
  material.request.shore_a = 95.0;
  ASSERT_TRUE(CallRefused(material, "[10, 90]"));
}

// 5. ~reset restores the rest shape; after ~set_material halves E the same push deflects twice
// as far within 5 %.
TEST(ResetAndMaterial, ResetRestoresRestShapeAndHalfTheModulusDoublesTheDeflection) {
  NodeOutputs node;
  ros::NodeHandle handle;
  ASSERT_TRUE(node.WaitForNode());
  ASSERT_TRUE(WaitFor([&] { return node.has_state; }, 10.0));
  const std::vector<Eigen::Vector3d> rest = node.Points();  // no gravity: at rest
  const Eigen::Vector3d top(0.0, 0.0, 0.09);
  const Eigen::Vector3d force(0.0, 0.0, -4.0);
  const double first = SettledDeflection(node, rest, top, force);
  ASSERT_GT(first, 1e-4);
  CallTrigger("/msm_sim/reset");
  // A state published before the reset may still be on its way: read one from later.
  ASSERT_TRUE(node.WaitSimulated(0.2));
  node.has_state = false;
  ASSERT_TRUE(WaitFor([&] { return node.has_state; }, 10.0));
  const double worst = LargestDistance(node.Points(), rest);
  EXPECT_LT(worst, 1e-6) << "reset did not restore the rest shape";

  msm_sim::SetMaterial material;
  material.request.object = "block";
  material.request.youngs = 2.5e4;  // half of push.yaml's
  material.request.poisson = 0.3;
  material.request.density = 1000.0;
  material.request.damping = 0.002;
  material.request.friction = 0.5;
  ASSERT_TRUE(ros::service::waitForService("/msm_sim/set_material", 10000));
  ASSERT_TRUE(ros::service::call("/msm_sim/set_material", material));
  ASSERT_TRUE(material.response.success) << material.response.message;
  const double second = SettledDeflection(node, rest, top, force);
  std::printf("  deflection %.6f m at E, %.6f m at E/2: ratio %.4f\n", first, second,
              second / first);
  EXPECT_NEAR(second / first, 2.0, 0.1);
  ExpectSetMaterialChecksItsRequest(material);
}

// 6. With use_sim_time, stepping follows /clock: no steps while the clock is stopped.
TEST(SimTime, SteppingFollowsTheClock) {
  ros::NodeHandle handle;
  ros::Publisher clock = handle.advertise<rosgraph_msgs::Clock>("/clock", 10);
  NodeOutputs node;
  double now = 1.0;
  auto tick = [&](double until) {
    for (; now < until - 1e-9; now += 0.01) {
      rosgraph_msgs::Clock message;
      message.clock = ros::Time(now);
      clock.publish(message);
      ros::WallDuration(0.004).sleep();
      ros::spinOnce();
    }
  };
  // Start the clock until the node reports.
  ASSERT_TRUE(WaitFor(
      [&] {
        tick(now + 0.05);
        return node.simulated_time >= 0.0;
      },
      30.0));
  const double start_clock = now;
  const double start_simulated = node.simulated_time;
  tick(now + 1.0);
  WaitFor([] { return false; }, 0.5);
  const double advanced = node.simulated_time - start_simulated;
  std::printf("  clock advanced %.3f s, simulation %.3f s\n", now - start_clock, advanced);
  EXPECT_NEAR(advanced, now - start_clock, 0.1);
  // Clock stopped for two seconds of wall time: no steps.
  const double frozen = node.simulated_time;
  WaitFor([] { return false; }, 2.0);
  EXPECT_EQ(node.simulated_time, frozen);
  tick(now + 0.5);
  WaitFor([] { return false; }, 0.5);
  EXPECT_NEAR(node.simulated_time - frozen, 0.5, 0.1);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.rfind("--expect=", 0) == 0) g_expected_errors.push_back(arg.substr(9));
  }
  ros::init(argc, argv, "test_msm_sim_node");
  ros::NodeHandle keep_alive;
  return RUN_ALL_TESTS();
}
