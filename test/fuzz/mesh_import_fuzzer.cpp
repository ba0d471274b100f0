// libFuzzer target: the mesh importer on arbitrary bytes (`make fuzz`). The first byte picks the
// format by file extension (or MSM_SIM_FUZZ_EXTENSION names one), the rest is the file. A
// MeshImportError (a one-line refusal) is the expected outcome for a damaged file; any other
// exception, a crash, a hang, a sanitizer report or an allocation beyond -rss_limit_mb is a bug
// (the same contract as test_mesh_fuzz.cpp).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "msm_sim/geometry/mesh_import.h"

namespace {

constexpr const char* kExtensions[] = {"stl", "obj", "ply", "off", "gltf", "glb"};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  // MSM_SIM_FUZZ_EXTENSION=ply (say) fuzzes one reader whatever the first byte.
  static const char* const only = std::getenv("MSM_SIM_FUZZ_EXTENSION");
  const char* extension =
      only ? only : kExtensions[data[0] % (sizeof(kExtensions) / sizeof(kExtensions[0]))];
  const std::string path = "/tmp/msm_sim_mesh_fuzz_" + std::to_string(getpid()) + "." + extension;
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) return 0;
  std::fwrite(data + 1, 1, size - 1, file);
  std::fclose(file);
  try {
    msm_sim::core::ImportTriangleMesh(path);
  } catch (const msm_sim::core::MeshImportError&) {
    // A refusal, with its one-line reason: what a damaged file should get.
  }
  std::remove(path.c_str());
  return 0;
}
