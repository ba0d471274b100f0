// Config fuzz (issue "Hardening"): malformed scenes, each the robot demo's scene
// (config/default.yaml with config/demo.yaml) changed by one mutation, run through the real
// msm_replay, which loads and builds the scene as msm_sim_node does (LoadSimulationConfig, then
// Simulation). Each must end with exit code 1 and one error line naming the parameter, in < 5 s.

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include "../run_command.h"

namespace {

const std::string kData = MSM_SIM_TEST_DATA_DIR;
const std::string kPackage = MSM_SIM_PACKAGE_DIR;

// One change of the scene: the value at `path` (keys separated by '/', list indices as numbers,
// "+" appends to a list) becomes `value` (YAML text), or is removed when `value` is empty.
struct Edit {
  std::string path;
  std::string value;
};

struct Scene {
  std::vector<Edit> edits;  // one mutation (two edits when it swaps one key for another)
  std::string names;        // the parameter the error line must name
};

std::vector<std::string> Split(const std::string& path) {
  std::vector<std::string> keys;
  std::stringstream stream(path);
  for (std::string key; std::getline(stream, key, '/');) keys.push_back(key);
  return keys;
}

// Applies the edit below `node` (a handle: yaml-cpp nodes share their data).
void Apply(YAML::Node node, const std::vector<std::string>& keys, std::size_t depth,
           const std::string& value) {
  const std::string& key = keys[depth];
  const bool index = std::isdigit(static_cast<unsigned char>(key[0])) != 0;
  if (depth + 1 < keys.size()) {
    Apply(index ? node[std::stoi(key)] : node[key], keys, depth + 1, value);
  } else if (key == "+") {
    node.push_back(YAML::Load(value));
  } else if (value.empty()) {
    node.remove(key);
  } else if (index) {
    node[std::stoi(key)] = YAML::Load(value);
  } else {
    node[key] = YAML::Load(value);
  }
}

YAML::Node BaseScene() {
  YAML::Node scene = YAML::LoadFile(kPackage + "/config/default.yaml");
  const YAML::Node demo = YAML::LoadFile(kPackage + "/config/demo.yaml");
  for (const auto& entry : demo) scene[entry.first.as<std::string>()] = entry.second;
  return scene;
}

const std::string kBlock = "~objects[0] (object 'soft_block'): ";

// ~world: wrong types, NaN, Inf, negative, zero, unknown keys.
std::vector<Scene> WorldScenes() {
  return {
      {{{"world/time_step", "-0.001"}}, "~world/time_step"},
      {{{"world/time_step", ".nan"}}, "~world/time_step"},
      {{{"world/time_step", "'fast'"}}, "~world/time_step"},
      {{{"world/time_step", "0"}}, "~world/time_step"},
      {{{"world/publish_rate", ".inf"}}, "~world/publish_rate"},
      {{{"world/publish_rate", "[1, 2]"}}, "~world/publish_rate"},
      {{{"world/max_force", "-1000"}}, "~world/max_force"},
      {{{"world/time_step_safety", "1.5"}}, "~world/time_step_safety"},
      {{{"world/integrator", "rk4"}}, "~world/integrator"},
      {{{"world/integrator", "42"}}, "~world/integrator"},
      {{{"world/penetration_recovery_time", "0"}}, "~world/penetration_recovery_time"},
      {{{"world/penetration_max_speed", "-0.1"}}, "~world/penetration_max_speed"},
      {{{"world/spring_precision", "half"}}, "~world/spring_precision"},
      {{{"world/spring_precision", "32"}}, "~world/spring_precision"},
      {{{"world/gravity", "[0, 0]"}}, "~world/gravity"},
      {{{"world/gravity", "[0, 0, .nan]"}}, "~world/gravity"},
      {{{"world/gravity", "down"}}, "~world/gravity"},
      {{{"world/frame", "''"}}, "~world/frame"},
      {{{"world/real_time", "'sometimes'"}}, "~world/real_time"},
      {{{"world/ground", "5"}}, "~world/ground"},
      {{{"world/ground/friction", "-0.6"}}, "~world/ground/friction"},
      {{{"world/ground/enabled", "1"}}, "~world/ground/enabled"},
      {{{"world/ground/height", "-.inf"}}, "~world/ground/height"},
      {{{"world/gravty", "[0, 0, -9.81]"}}, "~world/gravty"},
      {{{"world", "[]"}}, "~world"},
  };
}

// ~world: finite values far beyond any robot scene (they wrecked the run before: NaN contact
// points, every step rejected), each refused naming the key.
std::vector<Scene> AbsurdWorldScenes() {
  return {
      {{{"world/ground/height", "1.0e+300"}}, "~world/ground/height"},
      {{{"world/ground/height", "-600"}}, "~world/ground/height"},
      {{{"world/gravity", "[0, 0, -1.0e+30]"}}, "~world/gravity"},
      {{{"world/gravity", "[2000, 0, 0]"}}, "~world/gravity"},
      {{{"world/ground/friction", "1.0e+300"}}, "~world/ground/friction"},
      {{{"world/time_step", "10"}}, "~world/time_step"},
      {{{"world/publish_rate", "1.0e+9"}}, "~world/publish_rate"},
      {{{"world/max_force", "1.0e+300"}}, "~world/max_force"},
      {{{"world/max_distance", "1.0e+30"}}, "~world/max_distance"},
      {{{"world/max_distance", "0"}}, "~world/max_distance"},
      {{{"world/max_pending_pushes", "0"}}, "~world/max_pending_pushes"},
      {{{"world/max_pending_pushes", "1.0e+12"}}, "~world/max_pending_pushes"},
      {{{"world/max_pending_force", "-1"}}, "~world/max_pending_force"},
      {{{"world/penetration_recovery_time", "1.0e+20"}}, "~world/penetration_recovery_time"},
      {{{"world/penetration_max_speed", "1.0e+6"}}, "~world/penetration_max_speed"},
      {{{"objects/0/pose/position", "[0, 0, 1.0e+30]"}}, "~objects[0]/pose/position"},
      {{{"robot/friction", "1.0e+300"}}, "~robot/friction"},
      {{{"robot/max_link_speed", "0"}}, "~robot/max_link_speed"},
  };
}

// Names that clash with the world frame or the ground, or are not ROS names (roscpp ended the
// node with its own text for them).
std::vector<Scene> NameScenes() {
  return {
      {{{"objects/0/name", "world"}}, "~objects[0]/name"},
      {{{"objects/0/name", "ground"}}, "~objects[0]/name"},
      {{{"objects/0/name", "'a/b c'"}}, "~objects[0]/name"},
      {{{"objects/0/name", "'2nd_block'"}}, "~objects[0]/name"},
      {{{"objects/0/clamps/0/name", "ground"}}, "~objects[0]/clamps[0]/name"},
      {{{"objects/0/clamps/0/name", "'table clamp'"}}, "~objects[0]/clamps[0]/name"},
      {{{"objects/0/clamps/+", "{name: table_clamp, half_space: {point: [0, 0, 0.005]}}"}},
       "~objects[0]/clamps[1]/name"},
      {{{"world/frame", "map"}, {"objects/0/name", "map"}}, "~objects[0]/name"},
      {{{"wrench_inputs", "[{topic: 'bad topic!!', object: soft_block}]"}},
       "~wrench_inputs[0]/topic"},
  };
}

// ~objects: empty lists, duplicates, bad materials, absurd node counts.
std::vector<Scene> ObjectMaterialScenes() {
  return {
      {{{"objects", "[]"}}, "~objects"},
      {{{"objects", "{}"}}, "~objects"},
      {{{"objects", ""}}, "~objects"},
      {{{"objects/0", "block"}}, "~objects[0]"},
      {{{"objects/0/name", "''"}}, "~objects[0]/name"},
      {{{"objects/+",
         "{name: soft_block, shape: {type: sphere, radius: 0.02}, spacing: 0.01, "
         "material: cork}"}},
       "~objects[1]/name"},
      {{{"objects/0/poisson", "0.5"}}, "~objects[0]/poisson"},
      {{{"objects/0/poisson", ".nan"}}, "~objects[0]/poisson"},
      {{{"objects/0/poisson", "-1.5"}}, "~objects[0]/poisson"},
      {{{"objects/0/youngs", "-1.0e+5"}}, "~objects[0]/youngs"},
      {{{"objects/0/youngs", "0"}}, "~objects[0]/youngs"},
      {{{"objects/0/density", ".inf"}}, "~objects[0]/density"},
      {{{"objects/0/youngs", "1.0e+12"}}, "~objects[0]/youngs"},
      {{{"objects/0/density", "1.0e+300"}}, "~objects[0]/density"},
      {{{"objects/0/density", "1.0e-300"}}, kBlock + "the material's stiffness-to-mass"},
      {{{"objects/0/density", "1.0e-6"}}, kBlock + "the material gives a stable step"},
      {{{"objects/0/density", "heavy"}}, "~objects[0]/density"},
      {{{"objects/0/material", "unobtainium"}}, "~objects[0]/material"},
      {{{"objects/0/material", "[1, 2]"}}, "~objects[0]/material"},
      {{{"objects/0/spacing", "-0.01"}}, "~objects[0]/spacing"},
      {{{"objects/0/spacing", ".nan"}}, "~objects[0]/spacing"},
      {{{"objects/0/spacing", "1.0e-6"}}, kBlock + "spacing 1e-06 m"},
      {{{"objects/0/spacing", "0.5"}}, kBlock + "lattice spacing"},
      {{{"objects/0/spacing", ""}, {"objects/0/target_nodes", "1.0e+12"}},
       "~objects[0]/target_nodes"},
      {{{"objects/0/spacing", ""}, {"objects/0/target_nodes", "2.5"}}, "~objects[0]/target_nodes"},
      {{{"objects/0/spacing", ""}, {"objects/0/target_nodes", "-5"}}, "~objects[0]/target_nodes"},
      {{{"objects/0/target_nodes", "1000"}}, "~objects[0]/spacing"},
  };
}

// ~objects: lattices, shapes, missing meshes, huge sizes, poses, clamps.
std::vector<Scene> ObjectShapeScenes() {
  return {
      {{{"objects/0/model", "tetrahedral"}}, "~objects[0]/model"},
      {{{"objects/0/spring", "quadratic"}}, "~objects[0]/spring"},
      {{{"objects/0/spring", "power"}}, "~objects[0]/spring"},
      {{{"objects/0/tensile_law", "{alpha: -4.54}"}}, "~objects[0]/tensile_law/beta"},
      {{{"objects/0/tensile_law", "{alpha: -4.54, beta: -0.1}"}}, "~objects[0]/tensile_law/beta"},
      {{{"objects/0/shape", ""}}, "~objects[0]/shape"},
      {{{"objects/0/shape/type", "torus"}}, "~objects[0]/shape/type"},
      {{{"objects/0/shape/size", "[0.12, -0.08, 0.05]"}}, "~objects[0]/shape/size"},
      {{{"objects/0/shape/size", "[1.0e+300, 1.0e+300, 1.0e+300]"}}, "~objects[0]/shape/size"},
      {{{"objects/0/shape/size", "[1000, 1000, 1000]"}}, kBlock + "spacing 0.005 m gives"},
      {{{"objects/0/shape", "{type: sphere, radius: 1.0e+200}"}}, "~objects[0]/shape/radius"},
      {{{"objects/0/shape", "{type: mesh, uri: /nonexistent/bean.stl}"}}, "~objects[0]/shape/uri"},
      {{{"objects/0/shape", "{type: mesh, uri: 'package://msm_sim/meshes/none.stl'}"}},
       "~objects[0]/shape/uri"},
      {{{"objects/0/shape", "{type: sphere}"}}, "~objects[0]/shape/radius"},
      {{{"objects/0/shape", "{type: cylinder, radius: 0.05, length: .nan}"}},
       "~objects[0]/shape/length"},
      {{{"objects/0/shape/colour", "red"}}, "~objects[0]/shape/colour"},
      {{{"objects/0/pose/position", "[0, 0]"}}, "~objects[0]/pose/position"},
      {{{"objects/0/pose/rpy", "[.inf, 0, 0]"}}, "~objects[0]/pose/rpy"},
      {{{"objects/0/pose/orientation", "[0, 0, 0, 1]"}}, "~objects[0]/pose/orientation"},
      {{{"objects/0/poison", "0.3"}}, "~objects[0]/poison"},
      {{{"objects/0/damping", "-1"}}, "~objects[0]/damping"},
      {{{"objects/0/friction", "high"}}, "~objects[0]/friction"},
      {{{"objects/0/restitution", "2"}}, "~objects[0]/restitution"},
      {{{"objects/0/seed", "-1"}}, "~objects[0]/seed"},
      {{{"objects/0/seed", "1.0e+30"}}, "~objects[0]/seed"},
      {{{"objects/0/antialias", "'never'"}}, "~objects[0]/antialias"},
      {{{"objects/0/free_face_bending", "'always'"}}, "~objects[0]/free_face_bending"},
      {{{"objects/0/free_face_bending", "true"}, {"objects/0/model", "random"}},
       "~objects[0]/free_face_bending"},
      {{{"objects/0/surface_dispersion", "0"}}, "~objects[0]/surface_dispersion"},
      {{{"objects/0/surface_dispersion", "1.5"}}, "~objects[0]/surface_dispersion"},
      {{{"objects/0/surface_dispersion", ".nan"}}, "~objects[0]/surface_dispersion"},
      {{{"objects/0/surface_dispersion", "'half'"}}, "~objects[0]/surface_dispersion"},
      {{{"objects/0/surface_dispersion", "0.5"}, {"objects/0/model", "baudet"}},
       "~objects[0]/surface_dispersion"},
      {{{"objects/0/mass_scaling", "-0.01"}}, "~objects[0]/mass_scaling"},
      {{{"objects/0/mass_scaling", "0.5"}}, "~objects[0]/mass_scaling"},
      {{{"objects/0/mass_scaling", ".nan"}}, "~objects[0]/mass_scaling"},
      {{{"objects/0/mass_scaling", "'some'"}}, "~objects[0]/mass_scaling"},
      {{{"objects/0/self_calibrate", "'sometimes'"}, {"objects/0/model", "random"}},
       "~objects[0]/self_calibrate"},
      {{{"objects/0/self_calibrate", "1"}, {"objects/0/model", "random"}},
       "~objects[0]/self_calibrate"},
      {{{"objects/0/self_calibrate", "true"}}, "~objects[0]/self_calibrate"},
      {{{"objects/0/visual_mesh", "/nonexistent/skin.obj"}}, "~objects[0]/visual_mesh"},
      {{{"objects/0/clamps", "{}"}}, "~objects[0]/clamps"},
      {{{"objects/0/clamps/0/half_space/normal", "[0, 0, 0]"}},
       "~objects[0]/clamps[0]/half_space/normal"},
      {{{"objects/0/clamps/0/half_space/point", "[0, 0, -10]"}}, "~objects[0]/clamps[0]"},
      {{{"objects/0/clamps/0/half_space", ""}}, "~objects[0]/clamps[0]"},
      {{{"objects/0/clamps/0/box", "{min: [1, 1, 1], max: [0, 0, 0]}"},
        {"objects/0/clamps/0/half_space", ""}},
       "~objects[0]/clamps[0]/box"},
  };
}

// ~wrench_inputs, ~robot, ~markers, ~materials.
std::vector<Scene> InputRobotMarkerScenes() {
  return {
      {{{"wrench_inputs", "{}"}}, "~wrench_inputs"},
      {{{"wrench_inputs", "[{topic: /w, object: nothing}]"}}, "~wrench_inputs[0]/object"},
      {{{"wrench_inputs", "[{object: soft_block}]"}}, "~wrench_inputs[0]/topic"},
      {{{"wrench_inputs", "[{topic: /w, object: soft_block, radius: -1}]"}},
       "~wrench_inputs[0]/radius"},
      {{{"wrench_inputs", "[{topic: /w, object: soft_block, frame: tool}]"}},
       "~wrench_inputs[0]/frame"},
      {{{"robot", "[]"}}, "~robot"},
      {{{"robot/tf_timeout", "0"}}, "~robot/tf_timeout"},
      {{{"robot/links", "fingertip"}}, "~robot/links"},
      {{{"robot/links", "[1, 2]"}}, "~robot/links[0]"},
      {{{"robot/link_friction", "{fingertip: -0.4}"}}, "~robot/link_friction/fingertip"},
      {{{"robot/link_friction", "[0.4]"}}, "~robot/link_friction"},
      {{{"robot/frition", "0.5"}}, "~robot/frition"},
      {{{"markers/strain_range", "0"}}, "~markers/strain_range"},
      {{{"markers/nodes", "'maybe'"}}, "~markers/nodes"},
      {{{"markers", "7"}}, "~markers"},
      {{{"markers/colour", "true"}}, "~markers/colour"},
      {{{"materials", "{silicone_ecoflex_00_30: {youngs: -5, poisson: 0.3, density: 1000}}"}},
       "~materials/silicone_ecoflex_00_30/youngs"},
      {{{"materials", "{silicone_ecoflex_00_30: {youngs: 1.0e+5, poisson: .nan, density: 1}}"}},
       "~materials/silicone_ecoflex_00_30/poisson"},
  };
}

// The malformed scenes: wrong types, NaN, Inf, negative, huge, empty lists, unknown keys,
// missing meshes, absurd node counts.
std::vector<Scene> MalformedScenes() {
  std::vector<Scene> scenes;
  for (const auto& part : {WorldScenes(), AbsurdWorldScenes(), NameScenes(), ObjectMaterialScenes(),
                           ObjectShapeScenes(), InputRobotMarkerScenes()}) {
    scenes.insert(scenes.end(), part.begin(), part.end());
  }
  return scenes;
}

std::string Describe(const Scene& scene) {
  std::string text;
  for (const Edit& e : scene.edits) text += e.path + " := '" + e.value + "' ";
  return text;
}

// Lines of `text` that are not empty.
std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::stringstream stream(text);
  for (std::string line; std::getline(stream, line);) {
    if (!line.empty()) lines.push_back(line);
  }
  return lines;
}

// Runs msm_replay on `scene` changed by `edits`, killed after 60 s (a hang fails instead of
// stalling the suite); *seconds gets its wall time.
msm_sim::testing::CommandRun RunScene(const std::vector<Edit>& edits, double* seconds) {
  const std::string path = ::testing::TempDir() + "config_fuzz_scene.yaml";
  const std::string out = ::testing::TempDir() + "config_fuzz_out.bag";
  YAML::Node tree = BaseScene();
  for (const Edit& e : edits) Apply(tree, Split(e.path), 0, e.value);
  std::ofstream(path) << YAML::Dump(tree) << "\n";
  const auto start = std::chrono::steady_clock::now();
  const msm_sim::testing::CommandRun run = msm_sim::testing::RunCommand(
      "timeout -s KILL 60 " + std::string(MSM_REPLAY_EXECUTABLE) + " --quiet --config " + path +
      " --materials " + kPackage + "/config/materials.yaml --in " + kData +
      "/demo_input.bag --out " + out);
  *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return run;
}

// The run ended with exit code 1 and one line naming the scene's parameter.
void ExpectOneErrorLine(const msm_sim::testing::CommandRun& run, const Scene& scene) {
  const std::vector<std::string> lines = Lines(run.err);
  EXPECT_FALSE(run.signalled) << Describe(scene);
  EXPECT_EQ(run.exit_code, 1) << Describe(scene) << "\n" << run.err;
  EXPECT_EQ(lines.size(), 1u) << Describe(scene) << "\n" << run.err;
  if (lines.empty()) return;
  EXPECT_EQ(lines[0].rfind("msm_replay: error: parameter ", 0), 0u) << lines[0];
  EXPECT_NE(lines[0].find(scene.names), std::string::npos)
      << Describe(scene) << "\nexpected to name " << scene.names << "\n"
      << lines[0];
}

TEST(ConfigFuzz, EachMalformedSceneIsOneErrorNamingTheParameter) {
  const std::vector<Scene> scenes = MalformedScenes();
  ASSERT_GE(scenes.size(), 50u);
  double worst_seconds = 0.0;
  for (const Scene& scene : scenes) {
    double seconds = 0.0;
    const msm_sim::testing::CommandRun run = RunScene(scene.edits, &seconds);
    worst_seconds = std::max(worst_seconds, seconds);
    ExpectOneErrorLine(run, scene);
    EXPECT_LT(seconds, 5.0) << Describe(scene);
    const std::vector<std::string> lines = Lines(run.err);
    std::printf("  %-60.60s %.2f s | %s\n", Describe(scene).c_str(), seconds,
                lines.empty() ? "" : lines[0].c_str());
  }
  std::printf("  %zu malformed scenes, worst %.2f s\n", scenes.size(), worst_seconds);
}

// A mesh path that is a FIFO hung start-up forever (the file was opened before it was known
// to be a regular file); now it is refused before anything opens it.
TEST(ConfigFuzz, AFifoMeshPathIsRefusedWithinASecond) {
  const std::string fifo =
      ::testing::TempDir() + "config_fuzz_fifo_" + std::to_string(::getpid()) + ".stl";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::vector<Scene> scenes = {
      {{{"objects/0/shape", "{type: mesh, uri: '" + fifo + "'}"}}, "~objects[0]/shape/uri"},
      {{{"objects/0/visual_mesh", "'file://" + fifo + "'"}}, "~objects[0]/visual_mesh"},
  };
  for (const Scene& scene : scenes) {
    double seconds = 0.0;
    const msm_sim::testing::CommandRun run = RunScene(scene.edits, &seconds);
    ExpectOneErrorLine(run, scene);
    EXPECT_NE(run.err.find("not a regular file"), std::string::npos) << run.err;
    EXPECT_LT(seconds, 1.0) << Describe(scene);
  }
  std::remove(fifo.c_str());
}

}  // namespace
