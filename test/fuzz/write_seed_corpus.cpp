// Writes the fuzzers' seed corpora (`make fuzz`): the test cube in every mesh format the header
// checks know (test/geometry/mesh_files.h), each prefixed with the byte that makes
// mesh_import_fuzzer pick its extension, and two small model files (linear and power-law springs)
// from the package's own writer.
// Usage: write_seed_corpus MESH_DIR MODEL_DIR
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "geometry/mesh_files.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/model/model_file.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: write_seed_corpus MESH_DIR MODEL_DIR\n");
    return 1;
  }
  // The extensions in mesh_import_fuzzer.cpp's order.
  const std::vector<std::string> extensions = {"stl", "obj", "ply", "off", "gltf", "glb"};
  int written = 0;
  for (const msm_sim::testing::MeshFile& file : msm_sim::testing::CubeFiles()) {
    for (std::size_t e = 0; e < extensions.size(); ++e) {
      if (extensions[e] != file.extension) continue;
      std::ofstream out(
          std::string(argv[1]) + "/cube_" + std::to_string(written++) + "." + file.extension,
          std::ios::binary);
      out << static_cast<char>(e) << file.bytes;
    }
  }
  msm_sim::core::CubicLatticeOptions options;
  options.size = Eigen::Vector3d(0.2, 0.2, 0.2);
  options.lattice.spacing = 0.1;
  const auto material = msm_sim::core::Material::FromYoungsPoisson(1e5, 0.3, 1000.0);
  msm_sim::core::SaveModel(msm_sim::core::BuildCubicLattice(material, options),
                           std::string(argv[2]) + "/cube.msm");
  // The same cube with the power spring law, whose file holds its alpha and beta (format 3).
  options.lattice.spring_law = msm_sim::core::SpringLaw::kPower;
  options.lattice.power_law = msm_sim::core::PowerSpringLaw{-4.54, 0.116};
  msm_sim::core::SaveModel(msm_sim::core::BuildCubicLattice(material, options),
                           std::string(argv[2]) + "/cube_power.msm");
  std::printf("write_seed_corpus: %d mesh files, 2 model files\n", written);
  return 0;
}
