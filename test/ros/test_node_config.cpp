// The node's configuration reading (LoadSimulationConfig against the parameter server):
// valid values are read, each bad one is a ConfigError naming the parameter. Part of
// test_msm_sim_node (main is in test_msm_sim_node.cpp).
#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "node_test_support.h"
#include "object_builder.h"
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
  EXPECT_EQ(defaults.world.max_substep_refinement, 8);
  scene.setParam("world/max_substep_refinement", 2);
  scene.setParam("world/spring_precision", std::string("double"));
  EXPECT_EQ(defaults.world.penetration_recovery_time, 0.05);
  EXPECT_EQ(defaults.world.penetration_max_speed, 0.1);
  scene.setParam("world/penetration_recovery_time", 0.02);
  scene.setParam("world/penetration_max_speed", 0.0);
  const auto config = msm_sim::ros_interface::LoadSimulationConfig(scene);
  EXPECT_EQ(config.world.integrator, msm_sim::core::Integrator::kImplicit);
  EXPECT_EQ(config.world.time_step_safety, 0.4);
  EXPECT_EQ(config.world.max_substep_refinement, 2);
  EXPECT_EQ(config.world.spring_precision, msm_sim::core::SpringPrecision::kDouble);
  EXPECT_EQ(config.world.penetration_recovery_time, 0.02);
  EXPECT_EQ(config.world.penetration_max_speed, 0.0);
  scene.deleteParam("");
}

// world/publish_clock (off by default) and robot/tf_delay (0.1 s by default, >= 0).
TEST(WorldConfig, ClockAndRobotDelayAreRead) {
  ros::NodeHandle scene("/clock_scene");
  scene.deleteParam("");
  XmlRpc::XmlRpcValue objects;
  objects[0] = BoxObject();
  scene.setParam("objects", objects);
  scene.setParam("robot/friction", 0.5);
  const auto defaults = msm_sim::ros_interface::LoadSimulationConfig(scene);
  EXPECT_FALSE(defaults.world.publish_clock);
  EXPECT_EQ(defaults.robot.tf_delay, 0.1);
  scene.setParam("world/publish_clock", true);
  scene.setParam("robot/tf_delay", 0.0);
  const auto config = msm_sim::ros_interface::LoadSimulationConfig(scene);
  EXPECT_TRUE(config.world.publish_clock);
  EXPECT_EQ(config.robot.tf_delay, 0.0);
  scene.setParam("robot/tf_delay", -0.1);
  EXPECT_THROW(msm_sim::ros_interface::LoadSimulationConfig(scene),
               msm_sim::ros_interface::ConfigError);
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
  EXPECT_FALSE(LoadBoxObject().surface.free_face_bending);
  EXPECT_TRUE(LoadBoxObject("free_face_bending", true).surface.free_face_bending);
}

// objects[]/surface_dispersion (docs/physics.md §7): 1 (off) unless asked for, and what the
// object's model is built with.
TEST(ObjectConfig, SurfaceDispersionIsRead) {
  EXPECT_EQ(LoadBoxObject().surface.surface_dispersion, 1.0);
  EXPECT_EQ(LoadBoxObject("surface_dispersion", 0.5).surface.surface_dispersion, 0.5);
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
  // Soft silicones by the type 00 sphere relation (docs/materials.md table 3): Ecoflex 00-30's
  // hardness and Shore A 10 (= 00 55).
  EXPECT_NEAR(load("shore_00", 30.0).objects[0].youngs, 121.4e3, 0.1e3);
  EXPECT_NEAR(load("shore_a", 10.0).objects[0].youngs, 328.0e3, 0.2e3);
  try {
    load("shore_a", 5.0);
    ADD_FAILURE() << "shore_a 5 was accepted";
  } catch (const msm_sim::ros_interface::ConfigError& e) {
    const std::string message = e.what();
    for (const char* text : {"~objects[0]/shore_a", "object 'pad'", "[10, 90]", "give youngs"}) {
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
  ExpectConfigError("world/publish_clock", std::string("yes"), "~world/publish_clock");
  ExpectConfigError("world/time_step_safety", 1.5, "~world/time_step_safety");
  ExpectConfigError("world/time_step_safety", 0.0, "~world/time_step_safety");
  ExpectConfigError("world/max_substep_refinement", 3, "~world/max_substep_refinement");
  ExpectConfigError("world/max_substep_refinement", 0.5, "~world/max_substep_refinement");
  ExpectConfigError("world/integrator", std::string("rk4"), "~world/integrator");
  ExpectConfigError("world/spring_precision", std::string("half"), "~world/spring_precision");
  ExpectConfigError("world/penetration_recovery_time", 0.0, "~world/penetration_recovery_time");
  ExpectConfigError("world/penetration_max_speed", -0.1, "~world/penetration_max_speed");
  XmlRpc::XmlRpcValue bad_clamp;
  bad_clamp[0]["name"] = std::string("c");
  ExpectConfigError("clamps", bad_clamp, "~objects[0]/clamps[0]");
  ros::NodeHandle("/empty_scene").deleteParam("");
  EXPECT_THROW(msm_sim::ros_interface::LoadSimulationConfig(ros::NodeHandle("/empty_scene")),
               msm_sim::ros_interface::ConfigError);
}

// A cantilever object 0.2 x 0.05 x 0.05 m at 4 cells across, posed in the world (turned about z,
// lifted), with one half-space clamp given in the world frame.
msm_sim::ros_interface::ObjectConfig CantileverObject(const Eigen::Vector3d& clamp_point,
                                                      const Eigen::Vector3d& clamp_normal) {
  msm_sim::ros_interface::ObjectConfig config;
  config.name = "beam";
  config.shape.kind = msm_sim::core::BodyShape::Kind::kBox;
  config.shape.size = Eigen::Vector3d(0.2, 0.05, 0.05);
  config.lattice.spacing = 0.0125;
  config.youngs = 120e3;
  config.poisson = 0.25;
  config.density = 1000.0;
  config.pose.translate(Eigen::Vector3d(0.3, -0.1, 0.2));
  config.pose.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()));
  msm_sim::ros_interface::ClampConfig clamp;
  clamp.name = "wall";
  clamp.is_box = false;
  clamp.point = config.pose * clamp_point;
  clamp.normal = config.pose.linear() * clamp_normal;
  config.clamps.push_back(clamp);
  return config;
}

// A half-space clamp whose plane is a face of a cubic box clamps that face as FEM does (docs/
// physics.md §2.1 "Face anchors"): the object is the lab's anchored cantilever, whose end face
// test_cantilever_faces.cpp holds within 3 % of CalculiX (with free_face_bending, as there),
// and the clamp holds its anchors.
TEST(ObjectConfig, HalfSpaceOnABoxFaceAnchorsTheFace) {
  using msm_sim::core::AnchoredPlane;
  for (const bool free_face_bending : {false, true}) {
    auto config = CantileverObject(Eigen::Vector3d(-0.1, 0.0, 0.0), Eigen::Vector3d::UnitX());
    config.surface.free_face_bending = free_face_bending;
    const auto built = msm_sim::ros_interface::BuildObject(config, "~objects[0]");
    msm_sim::core::CubicLatticeOptions lattice_options;
    lattice_options.size = config.shape.size;
    lattice_options.lattice.spacing = config.lattice.spacing;
    lattice_options.surface.free_face_bending = free_face_bending;
    lattice_options.surface.anchored_planes = {
        AnchoredPlane{Eigen::Vector3d::Zero(), -Eigen::Vector3d::UnitX()}};
    const msm_sim::core::Model lab = msm_sim::core::BuildCubicLattice(
        msm_sim::core::Material::FromYoungsPoisson(120e3, 0.25, 1000.0), lattice_options);
    const msm_sim::core::Model& node = *built.model;
    ASSERT_EQ(node.num_nodes(), lab.num_nodes());
    ASSERT_EQ(node.num_springs(), lab.num_springs());
    std::vector<double> k_node = node.spring_stiffness(), k_lab = lab.spring_stiffness();
    std::sort(k_node.begin(), k_node.end());
    std::sort(k_lab.begin(), k_lab.end());
    for (std::size_t s = 0; s < k_lab.size(); ++s) {
      EXPECT_NEAR(k_node[s], k_lab[s], 1e-6 * k_lab[s]) << free_face_bending;
    }
    // The clamp holds exactly the anchors on the face x = -L/2 of the posed object.
    ASSERT_EQ(built.clamps.size(), 1u);
    const std::vector<msm_sim::core::NodeIndex>& held = built.clamps[0].second;
    EXPECT_EQ(held.size(),
              msm_sim::core::AnchorNodes(lab, lattice_options.surface.anchored_planes[0]).size());
    EXPECT_EQ(held.size(), 4u * 4u + 2u * 4u * 5u);
    for (const msm_sim::core::NodeIndex i : held) {
      const Eigen::Vector3d local =
          config.pose.inverse() * Eigen::Vector3d(node.rest_positions().col(i));
      EXPECT_NEAR(local.x(), -0.1, 1e-12);
    }
  }
}

// A half-space inside the body holds the nodes behind its plane, as before, and adds no anchor;
// a face of a box that is not a whole number of spacings across cannot be anchored: the clamp
// holds no node and the error says why and what to change.
TEST(ObjectConfig, OtherHalfSpacesHoldTheirNodes) {
  const auto inside = CantileverObject(Eigen::Vector3d(-0.09, 0.0, 0.0), Eigen::Vector3d::UnitX());
  const auto built = msm_sim::ros_interface::BuildObject(inside, "~objects[0]");
  EXPECT_EQ(built.model->num_nodes(), 16 * 4 * 4);
  EXPECT_EQ(built.clamps[0].second.size(), 16u);  // the layer at x = -L/2 + a/2
  auto uneven = CantileverObject(Eigen::Vector3d(-0.1, 0.0, 0.0), Eigen::Vector3d::UnitX());
  uneven.lattice.spacing = 0.012;
  try {
    msm_sim::ros_interface::BuildObject(uneven, "~objects[0]");
    ADD_FAILURE() << "a face clamp on 0.2 / 0.012 cells was accepted";
  } catch (const msm_sim::ros_interface::ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("~objects[0]/clamps[0]: clamp 'wall' holds no node"), std::string::npos)
        << what;
    EXPECT_NE(what.find("not a whole number of spacings"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

}  // namespace
