// RegularFileProblem: every kind of path a user can hand a reader, answered without opening it
// (a FIFO opened for reading waits for a writer forever).
#include <cstdio>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include "msm_sim/io/regular_file.h"

namespace msm_sim::core {
namespace {

std::string TempPath(const std::string& name) {
  return ::testing::TempDir() + "msm_sim_regular_file_" + std::to_string(::getpid()) + "_" + name;
}

TEST(RegularFile, AReadableFileHasNoProblem) {
  const std::string path = TempPath("plain.txt");
  std::ofstream(path) << "x\n";
  EXPECT_EQ(RegularFileProblem(path), "");
  std::remove(path.c_str());
}

TEST(RegularFile, MissingPathsAndDirectoriesAreNamed) {
  EXPECT_EQ(RegularFileProblem(TempPath("missing.stl")), "no such file");
  EXPECT_EQ(RegularFileProblem(TempPath("missing_dir") + "/mesh.stl"), "no such file");
  EXPECT_EQ(RegularFileProblem(::testing::TempDir()), "is a directory");
  EXPECT_EQ(RegularFileProblem(""), "no such file");
}

TEST(RegularFile, AFifoIsRefusedAtOnceWithoutAWriter) {
  const std::string path = TempPath("fifo.stl");
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
  // Opening it would block this test until ctest's timeout.
  EXPECT_EQ(RegularFileProblem(path), "is a FIFO, device or socket, not a regular file");
  std::remove(path.c_str());
}

TEST(RegularFile, DevicesAreRefused) {
  EXPECT_EQ(RegularFileProblem("/dev/null"), "is a FIFO, device or socket, not a regular file");
}

TEST(RegularFile, AnUnreadableFileSaysWhy) {
  if (::geteuid() == 0) GTEST_SKIP() << "root reads every file";
  const std::string path = TempPath("locked.txt");
  std::ofstream(path) << "x\n";
  ::chmod(path.c_str(), 0);
  EXPECT_EQ(RegularFileProblem(path).rfind("cannot be read: ", 0), 0u);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace msm_sim::core
