// Every file of assimp-testmodels' models/invalid/ (empty files, out-of-range indices, a 309-byte
// OFF declaring 3.5e11 vertices, ...) is refused with a MeshImportError or, if it is in fact a
// usable mesh, loaded; each import runs in a forked child whose peak memory is measured.
#include <sys/stat.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "forked_run.h"
#include "msm_sim/geometry/mesh_import.h"

namespace msm_sim::core {
namespace {

// Installed by scripts/install_dependencies.sh (Debian package assimp-testmodels).
const char kInvalidDir[] = "/usr/share/assimp/models/invalid";

// Exit codes of the child: the file loaded, or was refused with a MeshImportError.
constexpr int kLoaded = 0;
constexpr int kRefused = 1;
// The children's address space is capped well above what the test allows (200 MB resident) but
// below what would hurt a shared machine if the header checks regressed (OutOfMemory.off then
// takes 16 GB; under the cap assimp's allocation fails instead, and the test below, which checks
// the message, fails).
constexpr std::uint64_t kSafetyNetBytes = std::uint64_t{4} << 30;

TEST(InvalidMeshes, AssimpsInvalidModelsAreRefusedInBoundedMemory) {
  if (!std::filesystem::is_directory(kInvalidDir)) {
    FAIL() << kInvalidDir << " is missing: install assimp-testmodels "
           << "(scripts/install_dependencies.sh)";
  }
  std::vector<std::string> paths;
  for (const auto& entry : std::filesystem::directory_iterator(kInvalidDir)) {
    paths.push_back(entry.path().string());
  }
  std::sort(paths.begin(), paths.end());
  ASSERT_FALSE(paths.empty());
  for (const std::string& path : paths) {
    const testing::ChildRun run = testing::RunInChild(
        [&] {
          try {
            ImportTriangleMesh(path);
            return kLoaded;
          } catch (const MeshImportError&) {
            return kRefused;
          }
        },
        kSafetyNetBytes, /*alarm_seconds=*/30);  // 30 s: a guard against hangs only
    const std::string name = std::filesystem::path(path).filename().string();
    std::printf("%-20s %-8s %7.3f s %7.1f MB\n", name.c_str(),
                !run.exited                 ? run.Describe().c_str()
                : run.exit_code == kLoaded  ? "loaded"
                : run.exit_code == kRefused ? "refused"
                                            : run.Describe().c_str(),
                run.seconds, run.max_rss_mb);
    EXPECT_TRUE(run.exited && (run.exit_code == kLoaded || run.exit_code == kRefused))
        << name << ": " << run.Describe();
    EXPECT_LT(run.bounded_rss_mb(), 200.0) << name;
  }
}

// The file that took 15.8 GB and 60 s before the header checks: refused by its header, with the
// message that says why (in a child limited to 1 GB, so that a regression cannot take the machine).
TEST(InvalidMeshes, OutOfMemoryOffIsRefusedByItsHeader) {
  const std::string path = std::string(kInvalidDir) + "/OutOfMemory.off";
  struct stat info {};
  ASSERT_EQ(stat(path.c_str(), &info), 0)
      << path << " is missing: install assimp-testmodels (scripts/install_dependencies.sh)";
  const std::string expected =
      "mesh '" + path +
      "': the header declares 353535235358 vertices and 6 faces, which need at least "
      "2121211412171 bytes, but only 288 follow the header; the file is truncated or its header "
      "is wrong";
  const testing::ChildRun run = testing::RunInChild(
      [&] {
        try {
          ImportTriangleMesh(path);
          return kLoaded;
        } catch (const MeshImportError& e) {
          if (e.what() == expected) return kRefused;
          std::fprintf(stderr, "unexpected message: %s\n", e.what());
          return testing::kUnexpectedException;
        }
      },
      std::uint64_t{1} << 30, 30);
  EXPECT_TRUE(run.exited && run.exit_code == kRefused) << run.Describe();
}

}  // namespace
}  // namespace msm_sim::core
