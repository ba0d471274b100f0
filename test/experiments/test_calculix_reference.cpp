// The CalculiX reference for the cantilever (issue "A CalculiX reference in the suite"): the
// issue's box, 0.2 x 0.05 x 0.05 m clamped at x = 0, 0.05 N in -z on the end face as consistent
// nodal loads, E = 120 kPa, C3D8I 40 x 10 x 10, deflects 2.2046 mm at nu = 0.25 and 2.1687 mm at
// nu = 0.4 (mean -u_z of the end face's nodes). Needs calculix-ccx
// (scripts/install_dependencies.sh).
#include <sys/stat.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "msm_sim/experiments/calculix_reference.h"

namespace msm_sim::core {
namespace {

namespace fs = std::filesystem;

CalculixCantilever IssueBox(double poisson) {
  CalculixCantilever box;
  box.length = 0.2;
  box.width = 0.05;
  box.height = 0.05;
  box.youngs = 120e3;
  box.poisson = poisson;
  box.force = 0.05;
  box.elements_x = 40;
  box.elements_y = 10;
  box.elements_z = 10;
  box.timeout_seconds = 120.0;
  return box;
}

// The what() of the exception `run` throws, or "" when it throws none or another type.
template <typename Exception, typename Run>
std::string MessageOf(Run run) {
  try {
    run();
  } catch (const Exception& error) {
    return error.what();
  }
  return "";
}

class CalculixIssueBox : public ::testing::TestWithParam<std::pair<double, double>> {};

TEST_P(CalculixIssueBox, EndFaceDeflectionMatchesTheIssue) {
  const auto [poisson, expected] = GetParam();
  const CalculixCantileverResult result = RunCalculixCantilever(IssueBox(poisson));
  std::printf("  nu = %.2f: end face %.5f mm (issue %.4f mm), ccx %.2f s\n", poisson,
              1e3 * result.end_face_deflection, 1e3 * expected, result.seconds);
  EXPECT_NEAR(result.end_face_deflection / expected, 1.0, 0.005);

  // The profile: one station per node layer, 0 at the clamp, growing to the end face.
  ASSERT_EQ(result.profile.size(), 41u);
  EXPECT_EQ(result.profile.front().x, 0.0);
  EXPECT_EQ(result.profile.front().deflection, 0.0);
  EXPECT_NEAR(result.profile.back().x, 0.2, 1e-12);
  EXPECT_EQ(result.profile.back().deflection, result.end_face_deflection);
  for (std::size_t i = 1; i < result.profile.size(); ++i) {
    EXPECT_GT(result.profile[i].x, result.profile[i - 1].x) << i;
    EXPECT_GT(result.profile[i].deflection, result.profile[i - 1].deflection) << i;
  }
}

INSTANTIATE_TEST_SUITE_P(Issue, CalculixIssueBox,
                         ::testing::Values(std::make_pair(0.25, 2.2046e-3),
                                           std::make_pair(0.4, 2.1687e-3)));

// The deck's loads add up to the force, corners carry a quarter and edges half of what an
// interior node of the end face carries, and the first element lists its nodes in CalculiX's
// order (lower face counter-clockwise seen from +z, then the upper face).
TEST(CalculixDeck, ConsistentLoadsAndNodeOrder) {
  CalculixCantilever box = IssueBox(0.25);
  box.elements_x = 3;
  box.elements_y = 2;
  box.elements_z = 2;
  const std::string deck = CalculixCantileverDeck(box);
  std::istringstream lines(deck.substr(deck.find("*CLOAD\n") + 7));
  std::string line;
  double total = 0.0;
  double corner = 0.0;
  double interior = 0.0;
  int count = 0;
  while (std::getline(lines, line) && line[0] != '*') {
    long node = 0;
    int dof = 0;
    double value = 0.0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%ld, %d, %lf", &node, &dof, &value), 3) << line;
    EXPECT_EQ(dof, 3);
    total += value;
    if (node == 4) corner = value;                // (3, 0, 0)
    if (node == 4 + 4 + 4 * 3) interior = value;  // (3, 1, 1)
    ++count;
  }
  EXPECT_EQ(count, 9);
  EXPECT_NEAR(total, -box.force, 1e-15);
  EXPECT_NEAR(corner, 0.25 * interior, 1e-15);
  // Nodes (i, j, k) are numbered 1 + i + 4 (j + 3 k).
  EXPECT_NE(deck.find("*ELEMENT, TYPE=C3D8I, ELSET=EALL\n1, 1, 2, 6, 5, 13, 14, 18, 17\n"),
            std::string::npos);
}

// CalculiX reads at most 20 characters of a field (-2.4999999999999994E-07, a load of a slender
// bar's deck at 17 digits, stopped it with "*ERROR reading *CLOAD").
TEST(CalculixDeck, EveryFieldFitsCalculixsTwentyCharacters) {
  CalculixCantilever box = IssueBox(1.0 / 3.0);
  box.length = 4.0;
  box.width = 0.1;
  box.height = 0.1 / 3.0;
  box.youngs = 1.0 / 3.0 * 1e5;
  box.force = 1e-4 / 3.0;
  box.elements_x = 30;
  box.elements_y = 7;
  box.elements_z = 3;
  std::istringstream lines(CalculixCantileverDeck(box));
  std::string line;
  int fields = 0;
  while (std::getline(lines, line)) {
    if (line.rfind("**", 0) == 0 || line.rfind("msm_sim", 0) == 0) continue;  // comment, title
    std::istringstream row(line);
    std::string field;
    while (std::getline(row, field, ',')) {
      field.erase(0, field.find_first_not_of(' '));
      EXPECT_LE(field.size(), 20u) << line;
      ++fields;
    }
  }
  EXPECT_GT(fields, 31 * 8 * 4 * 4);  // at least the nodes' fields
}

TEST(CalculixDeck, BadInputThrowsAClearMessage) {
  const auto message = [](CalculixCantilever box) {
    return MessageOf<std::invalid_argument>([&] { CalculixCantileverDeck(box); });
  };
  CalculixCantilever box = IssueBox(0.25);
  box.elements_y = 0;
  EXPECT_NE(message(box).find("elements along x, y and z must each be >= 1"), std::string::npos);
  box = IssueBox(0.25);
  box.youngs = 0.0;
  EXPECT_NE(message(box).find("Young's modulus must be finite and > 0"), std::string::npos);
  box.youngs = -120e3;
  EXPECT_NE(message(box).find("Young's modulus"), std::string::npos);
  box = IssueBox(0.5);
  EXPECT_NE(message(box).find("Poisson's ratio"), std::string::npos);
  box = IssueBox(0.25);
  box.width = std::nan("");
  EXPECT_NE(message(box).find("length, width and height"), std::string::npos);
  box = IssueBox(0.25);
  box.elements_x = 1000;
  box.elements_y = 1000;
  EXPECT_NE(message(box).find("more than the limit"), std::string::npos);
  // The run checks before it starts anything.
  box.executable = "msm_sim_no_such_program";
  EXPECT_NE(MessageOf<std::invalid_argument>([&] {
              RunCalculixCantilever(box);
            }).find("more than the limit"),
            std::string::npos);
}

// A run that fails leaves nothing behind; so does one that succeeds (coarse mesh, fast).
class CalculixRunFailures : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fs::path(::testing::TempDir()) / "msm_sim_calculix_test";
    fs::remove_all(directory_);
    fs::create_directories(directory_ / "tmp");
    const char* previous = std::getenv("TMPDIR");
    had_tmpdir_ = previous != nullptr;
    if (had_tmpdir_) previous_tmpdir_ = previous;
    setenv("TMPDIR", (directory_ / "tmp").c_str(), 1);
  }
  void TearDown() override {
    EXPECT_TRUE(fs::is_empty(directory_ / "tmp")) << "a run left its directory behind";
    if (had_tmpdir_) {
      setenv("TMPDIR", previous_tmpdir_.c_str(), 1);
    } else {
      unsetenv("TMPDIR");
    }
    fs::remove_all(directory_);
  }
  // An executable shell script standing in for ccx.
  std::string Script(const std::string& name, const std::string& body) {
    const fs::path path = directory_ / name;
    std::ofstream(path) << "#!/bin/sh\n" << body << "\n";
    chmod(path.c_str(), 0755);
    return path.string();
  }
  fs::path directory_;
  bool had_tmpdir_ = false;
  std::string previous_tmpdir_;
};

TEST_F(CalculixRunFailures, MissingCcxSaysWhatToInstall) {
  CalculixCantilever box = IssueBox(0.25);
  box.executable = "msm_sim_no_such_ccx";
  const std::string message = MessageOf<std::runtime_error>([&] { RunCalculixCantilever(box); });
  EXPECT_NE(message.find("'msm_sim_no_such_ccx' not found"), std::string::npos) << message;
  EXPECT_NE(message.find("install calculix-ccx (scripts/install_dependencies.sh)"),
            std::string::npos)
      << message;
}

TEST_F(CalculixRunFailures, FailingCcxReportsItsErrorLine) {
  CalculixCantilever box = IssueBox(0.25);
  // ccx's own layout: the cause, its card on the next line, then the consequence.
  box.executable = Script("failing_ccx",
                          "printf ' *ERROR reading *CLOAD. Card image:\\n        201,3,-2\\n\\n'\n"
                          "printf ' *ERROR in calinput: at least one fatal\\n\\n'\n"
                          "echo ' Total CalculiX Time: 0.01'; exit 201");
  const std::string message = MessageOf<std::runtime_error>([&] { RunCalculixCantilever(box); });
  EXPECT_EQ(message,
            "CalculiX failed (exit code 201): *ERROR reading *CLOAD. Card image: 201,3,-2");
  box.executable = Script("silent_ccx", "echo 'Job finished'");
  EXPECT_NE(MessageOf<std::runtime_error>([&] {
              RunCalculixCantilever(box);
            }).find("CalculiX wrote no displacement for node 1"),
            std::string::npos);
}

TEST_F(CalculixRunFailures, SlowCcxIsStoppedAtTheTimeout) {
  CalculixCantilever box = IssueBox(0.25);
  box.executable = Script("slow_ccx", "echo started; exec sleep 30");
  box.timeout_seconds = 0.3;
  const auto start = std::chrono::steady_clock::now();
  const std::string message = MessageOf<std::runtime_error>([&] { RunCalculixCantilever(box); });
  const std::chrono::duration<double> seconds = std::chrono::steady_clock::now() - start;
  EXPECT_EQ(message, "CalculiX did not finish within 0.3 s (last output: started)");
  EXPECT_LT(seconds.count(), 5.0);
}

TEST_F(CalculixRunFailures, CoarseRunCleansUp) {
  CalculixCantilever box = IssueBox(0.25);
  box.elements_x = 8;
  box.elements_y = 2;
  box.elements_z = 2;
  const CalculixCantileverResult result = RunCalculixCantilever(box);
  // Coarser, so stiffer than the 40 x 10 x 10 mesh, but C3D8I bends well even two elements thick.
  EXPECT_GT(result.end_face_deflection, 0.9 * 2.2046e-3);
  EXPECT_LT(result.end_face_deflection, 2.2046e-3 * 1.001);
  EXPECT_EQ(result.profile.size(), 9u);
}

}  // namespace
}  // namespace msm_sim::core
