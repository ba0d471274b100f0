// Runs the real msm_lab executable on meshes (issue "Any mesh in"): `build` and `compression`
// with --mesh, and every assimp test model either built or refused with one error line.

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "msm_sim/geometry/mesh_import.h"
#include "msm_sim/model/model_file.h"
#include "run_lab.h"

namespace {

using msm_sim::testing::CountLines;
using msm_sim::testing::LabRun;
using msm_sim::testing::RunLab;

const std::string kCube100mm = std::string(MSM_SIM_TEST_DATA_DIR) + "/meshes/cube_100mm.stl";

TEST(LabCliMesh, BuildJsonHasTheContractKeysAndWritesModelAndVtk) {
  const std::string model_file = ::testing::TempDir() + "cube.msm";
  const std::string vtk_file = ::testing::TempDir() + "cube.vtu";
  const LabRun run = RunLab("build --mesh " + kCube100mm +
                            " --scale 0.001 --model cubic --spacing 0.0125 --youngs 1e5 "
                            "--poisson 0.45 --density 1200 --json --out " +
                            model_file + " --vtk " + vtk_file);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = nlohmann::json::parse(run.out);
  for (const char* key : {"nodes", "springs", "mass", "mesh_volume", "bbox_min", "bbox_max"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  EXPECT_EQ(json["nodes"], 8 * 8 * 8);
  EXPECT_NEAR(json["mesh_volume"].get<double>(), 1e-3, 1e-12);
  EXPECT_NEAR(json["mass"].get<double>(), 1.2, 1e-6);
  EXPECT_EQ(json["bbox_max"], nlohmann::json({0.1, 0.1, 0.1}));
  const msm_sim::core::Model saved = msm_sim::core::LoadModel(model_file);
  EXPECT_EQ(saved.num_nodes(), json["nodes"].get<int>());
  EXPECT_EQ(saved.num_springs(), json["springs"].get<int>());
  std::ifstream vtk(vtk_file);
  std::stringstream text;
  text << vtk.rdbuf();
  EXPECT_NE(text.str().find("NumberOfPoints=\"512\""), std::string::npos);
}

TEST(LabCliMesh, CompressionOfAMeshMatchesTheMaterial) {
  // 4000 nodes: a = 6.3 mm, 15.9 cells across the 100 mm cube, so the lattice does not fit it;
  // anti-aliasing weighs the outer layer by the 94 % of it inside.
  for (const char* antialias : {"on", "off"}) {
    const LabRun run = RunLab("compression --mesh " + kCube100mm +
                              " --scale 0.001 --model cubic --target-nodes 4000 --youngs 1e5 "
                              "--poisson 0.3 --json --antialias " +
                              antialias);
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const auto json = nlohmann::json::parse(run.out);
    if (std::string(antialias) == "on") {
      EXPECT_NEAR(json["youngs_measured"].get<double>() / 1e5, 1.0, 0.03);
      EXPECT_NEAR(json["poisson_measured"].get<double>(), 0.3, 0.02);
    }
  }
  const LabRun random = RunLab("compression --mesh " + kCube100mm +
                               " --scale 0.001 --model random --spacing 0.006 --youngs 1e5 "
                               "--poisson 0.3 --json");
  ASSERT_EQ(random.exit_code, 0) << random.err;
  EXPECT_NEAR(nlohmann::json::parse(random.out)["youngs_measured"].get<double>() / 1e5, 1.0, 0.1);
}

// Every file assimp's test models ship in the STL, PLY, OBJ and OFF folders either is a closed
// triangle mesh and builds, or gives one error line and exit code 1; every file in invalid/
// gives one error line and exit code 1. Never a signal.
const char* kAssimpModels = "/usr/share/assimp/models/";

std::vector<std::string> FilesIn(const std::string& directory) {
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(directory)) {
    if (entry.is_regular_file()) files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(LabCliMesh, EveryClosedAssimpTestModelBuilds) {
  ASSERT_TRUE(std::filesystem::is_directory(kAssimpModels))
      << "install Debian's assimp-testmodels (scripts/install_dependencies.sh does)";
  int closed = 0, refused = 0;
  for (const char* folder : {"STL", "PLY", "OBJ", "OFF"}) {
    for (const std::string& file : FilesIn(std::string(kAssimpModels) + folder)) {
      // Classify with the library: which files hold a closed surface, and how big it is.
      msm_sim::core::MeshImportOptions permissive;
      permissive.min_extent = 0.0;
      permissive.max_extent = 1e30;
      double extent = 0.0;
      bool is_closed = false;
      try {
        const auto imported = msm_sim::core::ImportTriangleMesh(file, permissive);
        Eigen::Vector3d lo, hi;
        msm_sim::core::BoundingBox(imported.mesh, &lo, &hi);
        extent = (hi - lo).maxCoeff();
        is_closed = imported.topology.closed() && extent > 0.0;
      } catch (const msm_sim::core::MeshImportError&) {
      }
      std::ostringstream command;
      command.precision(17);
      command << "build --mesh " << file << " --scale " << (extent > 0.0 ? 1.0 / extent : 1.0)
              << " --model cubic --target-nodes 300 --youngs 1e5 --poisson 0.3 --json";
      const LabRun run = RunLab(command.str());
      ASSERT_FALSE(run.signalled) << file;
      if (is_closed && run.exit_code == 0) {
        ++closed;
        EXPECT_GT(nlohmann::json::parse(run.out)["nodes"].get<int>(), 100) << file;
        continue;
      }
      // A closed file that fails must be a flat one (no volume); anything else must not build.
      EXPECT_EQ(run.exit_code, 1) << file << ": " << run.err;
      EXPECT_EQ(CountLines(run.err), 1) << file << ": " << run.err;
      EXPECT_NE(run.err.find(file), std::string::npos) << run.err;
      if (is_closed) {
        EXPECT_NE(run.err.find("no volume"), std::string::npos) << run.err;
      }
      ++refused;
    }
  }
  std::printf("  assimp test models: %d closed meshes built, %d files refused\n", closed, refused);
  EXPECT_GE(closed, 12);
}

TEST(LabCliMesh, EveryInvalidAssimpTestModelGivesOneErrorLineAndExitCode1) {
  ASSERT_TRUE(std::filesystem::is_directory(std::string(kAssimpModels) + "invalid"));
  const std::vector<std::string> files = FilesIn(std::string(kAssimpModels) + "invalid");
  ASSERT_GE(files.size(), 10u);
  for (const std::string& file : files) {
    const LabRun run =
        RunLab("build --mesh " + file + " --model cubic --spacing 0.1 --youngs 1e5 --poisson 0.3");
    EXPECT_FALSE(run.signalled) << file;
    EXPECT_EQ(run.exit_code, 1) << file << ": " << run.err;
    EXPECT_EQ(CountLines(run.err), 1) << file << ": " << run.err;
    EXPECT_EQ(run.err.rfind("msm_lab: error: mesh '" + file + "'", 0), 0u) << run.err;
  }
}

}  // namespace
