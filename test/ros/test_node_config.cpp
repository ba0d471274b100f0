// The node's configuration reading (LoadSimulationConfig against the parameter server):
// valid values are read, each bad one is a ConfigError naming the parameter. Part of
// test_msm_sim_node (main is in test_msm_sim_node.cpp).
#include <string>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include "node_test_support.h"
#include "simulation_config.h"

namespace {

using msm_sim_test::Finite;
using msm_sim_test::g_expected_errors;
using msm_sim_test::NodeOutputs;
using msm_sim_test::WaitFor;

// A valid box object: 10 cm cube at 2.5 cm, E = 100 kPa, nu = 0.3, rho = 1000.
XmlRpc::XmlRpcValue BoxObject() {
  XmlRpc::XmlRpcValue object;
  object["name"] = std::string("block");
  object["shape"]["type"] = std::string("box");
  XmlRpc::XmlRpcValue size;
  for (int i = 0; i < 3; ++i) size[i] = 0.1;
  object["shape"]["size"] = size;
  object["spacing"] = 0.025;
  object["youngs"] = 1e5;
  object["poisson"] = 0.3;
  object["density"] = 1000.0;
  return object;
}

// A bad configuration is one ConfigError naming the parameter (the node prints it as its one
// ROS_FATAL line and exits 1).
void ExpectConfigError(const std::string& yaml_key, XmlRpc::XmlRpcValue value,
                       const std::string& mentions, XmlRpc::XmlRpcValue object = BoxObject()) {
  ros::NodeHandle scene("/bad_scene");
  scene.deleteParam("");
  // A valid scene (`object`), then one change.
  if (yaml_key.rfind("world/", 0) != 0) object[yaml_key] = value;
  XmlRpc::XmlRpcValue objects;
  objects[0] = object;
  scene.setParam("objects", objects);
  if (yaml_key.rfind("world/", 0) == 0) scene.setParam(yaml_key, value);
  try {
    msm_sim::ros_interface::LoadSimulationConfig(scene);
    ADD_FAILURE() << yaml_key << " was accepted";
  } catch (const msm_sim::ros_interface::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(mentions), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
  }
}

TEST(WorldConfig, IntegratorAndSafetyAreRead) {
  ros::NodeHandle scene("/integrator_scene");
  scene.deleteParam("");
  XmlRpc::XmlRpcValue objects;
  objects[0] = BoxObject();
  scene.setParam("objects", objects);
  const auto defaults = msm_sim::ros_interface::LoadSimulationConfig(scene);
  EXPECT_EQ(defaults.world.integrator, msm_sim::core::Integrator::kExplicit);
  EXPECT_EQ(defaults.world.spring_precision, msm_sim::core::SpringPrecision::kSingle);
  scene.setParam("world/integrator", std::string("implicit"));
  scene.setParam("world/time_step_safety", 0.4);
  scene.setParam("world/spring_precision", std::string("double"));
  const auto config = msm_sim::ros_interface::LoadSimulationConfig(scene);
  EXPECT_EQ(config.world.integrator, msm_sim::core::Integrator::kImplicit);
  EXPECT_EQ(config.world.time_step_safety, 0.4);
  EXPECT_EQ(config.world.spring_precision, msm_sim::core::SpringPrecision::kDouble);
  scene.deleteParam("");
}

// The first object as read from a scene holding BoxObject() with `key` set to `value` (an empty
// key: BoxObject() as it is).
msm_sim::ros_interface::ObjectConfig LoadBoxObject(const std::string& key = "",
                                                   XmlRpc::XmlRpcValue value = {}) {
  ros::NodeHandle scene("/object_scene");
  scene.deleteParam("");
  XmlRpc::XmlRpcValue objects;
  objects[0] = BoxObject();
  if (!key.empty()) objects[0][key] = value;
  scene.setParam("objects", objects);
  const auto config = msm_sim::ros_interface::LoadSimulationConfig(scene).objects[0];
  scene.deleteParam("");
  return config;
}

// objects[]/free_face_bending (docs/physics.md §2.1): off unless asked for.
TEST(ObjectConfig, FreeFaceBendingIsRead) {
  EXPECT_FALSE(LoadBoxObject().free_face_bending);
  EXPECT_TRUE(LoadBoxObject("free_face_bending", true).free_face_bending);
}

// objects[]/orientation_threshold (docs/physics.md §4): off unless asked for; outside (0, 1)
// the configuration is refused, naming the parameter.
TEST(ObjectConfig, OrientationThresholdIsRead) {
  EXPECT_EQ(LoadBoxObject().orientation_threshold, 0.0);
  EXPECT_EQ(LoadBoxObject("orientation_threshold", 0.2).orientation_threshold, 0.2);
  for (const double bad : {-0.1, 1.0, 1.5}) {
    ExpectConfigError("orientation_threshold", bad, "objects[0]/orientation_threshold");
  }
}

// A random lattice has no cells for the barrier: refused rather than silently ignored.
TEST(ObjectConfig, OrientationThresholdNeedsCells) {
  XmlRpc::XmlRpcValue random = BoxObject();
  random["model"] = std::string("random");
  ExpectConfigError("orientation_threshold", 0.2, "objects[0]/orientation_threshold", random);
}

// shore_a or shore_00 instead of youngs: E from the core's conversion; outside its range or
// beside youngs, one ConfigError naming the parameter, the object and what to give instead.
TEST(ObjectConfig, ShoreHardnessGivesTheModulus) {
  ros::NodeHandle scene("/shore_scene");
  auto load = [&](const std::string& key, double reading) {
    scene.deleteParam("");
    XmlRpc::XmlRpcValue object;
    object["name"] = std::string("pad");
    object["shape"]["type"] = std::string("sphere");
    object["shape"]["radius"] = 0.05;
    object["spacing"] = 0.025;
    object[key] = reading;
    object["poisson"] = 0.45;
    object["density"] = 1100.0;
    XmlRpc::XmlRpcValue objects;
    objects[0] = object;
    scene.setParam("objects", objects);
    return msm_sim::ros_interface::LoadSimulationConfig(scene);
  };
  EXPECT_NEAR(load("shore_00", 90.0).objects[0].youngs, 2.456e6, 2e3);  // = Shore A 50
  EXPECT_NEAR(load("shore_a", 30.0).objects[0].youngs, 1.142e6, 1e3);
  try {
    load("shore_a", 10.0);
    ADD_FAILURE() << "shore_a 10 was accepted";
  } catch (const msm_sim::ros_interface::ConfigError& e) {
    const std::string message = e.what();
    for (const char* text : {"~objects[0]/shore_a", "object 'pad'", "[20, 90]", "give youngs"}) {
      EXPECT_NE(message.find(text), std::string::npos) << message;
    }
  }
  scene.deleteParam("");
}

TEST(BadConfig, NamesTheParameter) {
  ExpectConfigError("shore_a", 50.0, "not several");  // beside the scene's youngs
  ExpectConfigError("shore_00", 20.0, "~objects[0]/shore_00");
  ExpectConfigError("poisson", 0.7, "~objects[0]/poisson");
  ExpectConfigError("model", std::string("foam"), "~objects[0]/model");
  ExpectConfigError("youngs", std::string("soft"), "~objects[0]/youngs");
  ExpectConfigError("material", std::string("unobtainium"), "~objects[0]/material");
  ExpectConfigError("world/time_step", -1.0, "~world/time_step");
  ExpectConfigError("world/publish_rate", 0.0, "~world/publish_rate");
  ExpectConfigError("world/time_step_safety", 1.5, "~world/time_step_safety");
  ExpectConfigError("world/time_step_safety", 0.0, "~world/time_step_safety");
  ExpectConfigError("world/integrator", std::string("rk4"), "~world/integrator");
  ExpectConfigError("world/spring_precision", std::string("half"), "~world/spring_precision");
  XmlRpc::XmlRpcValue bad_clamp;
  bad_clamp[0]["name"] = std::string("c");
  ExpectConfigError("clamps", bad_clamp, "~objects[0]/clamps[0]");
  ros::NodeHandle("/empty_scene").deleteParam("");
  EXPECT_THROW(msm_sim::ros_interface::LoadSimulationConfig(ros::NodeHandle("/empty_scene")),
               msm_sim::ros_interface::ConfigError);
}

}  // namespace
