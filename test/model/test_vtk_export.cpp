// The VTK export (WriteVtu): a well-formed file whose values read back bit-identical, and one
// clean exception for every bad state or unwritable path.
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <map>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "model_file_test.h"
#include "msm_sim/geometry/vtk_export.h"
#include "msm_sim/model/state.h"

namespace msm_sim::core {
namespace {

struct VtuSummary {
  int pieces = 0;
  long points = -1;
  long cells = -1;
  std::map<std::string, std::vector<double>> arrays;  // by Name; "Points" for the points
};

// A minimal reader: enough to check the structure and the values we wrote.
VtuSummary ParseVtu(const std::string& path) {
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  VtuSummary summary;
  const std::regex piece(R"re(<Piece NumberOfPoints="(\d+)" NumberOfCells="(\d+)">)re");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), piece);
       it != std::sregex_iterator(); ++it) {
    ++summary.pieces;
    summary.points = std::stol((*it)[1]);
    summary.cells = std::stol((*it)[2]);
  }
  const std::regex array(R"re(<DataArray ([^>]*)>([^<]*)</DataArray>)re");
  const std::regex name(R"re(Name="([^"]+)")re");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), array);
       it != std::sregex_iterator(); ++it) {
    const std::string attributes = (*it)[1];
    std::smatch match;
    const std::string key =
        std::regex_search(attributes, match, name) ? std::string(match[1]) : "Points";
    std::istringstream values((*it)[2]);
    std::vector<double>& out = summary.arrays[key];
    for (std::string token; values >> token;) out.push_back(std::strtod(token.c_str(), nullptr));
  }
  EXPECT_EQ(
      text.rfind("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\"", 0),
      0u);
  EXPECT_EQ(text.substr(text.size() - 11), "</VTKFile>\n");
  return summary;
}

TEST_F(ModelFileTest, VtuIsWellFormed) {
  const Model model = CubicModel();
  const int n = model.num_nodes();
  const int s = model.num_springs();
  State state = State::AtRest(model);
  state.positions *= 1.01;  // about the origin: every spring stretched by 1 %
  state.velocities.setConstant(0.5);
  WriteVtu(model, state, Path("model.vtu"));

  const VtuSummary vtu = ParseVtu(Path("model.vtu"));
  EXPECT_EQ(vtu.pieces, 1);
  EXPECT_EQ(vtu.points, n);
  EXPECT_EQ(vtu.cells, s);
  const std::map<std::string, std::size_t> expected_sizes = {
      {"mass", n},       {"displacement", 3 * n}, {"velocity", 3 * n},
      {"stiffness", s},  {"rest_length", s},      {"strain", s},
      {"Points", 3 * n}, {"connectivity", 2 * s}, {"offsets", s},
      {"types", s}};
  ASSERT_EQ(vtu.arrays.size(), expected_sizes.size());
  for (const auto& [key, size] : expected_sizes) {
    ASSERT_EQ(vtu.arrays.count(key), 1u) << key;
    EXPECT_EQ(vtu.arrays.at(key).size(), size) << key;
  }
  // 17 significant digits read back bit-identical.
  for (int i = 0; i < n; ++i) {
    EXPECT_TRUE(SameBits(vtu.arrays.at("mass")[i], model.masses()[i]));
    for (int d = 0; d < 3; ++d) {
      EXPECT_TRUE(SameBits(vtu.arrays.at("Points")[3 * i + d], state.positions(d, i)));
    }
  }
  for (int k = 0; k < s; ++k) {
    EXPECT_NEAR(vtu.arrays.at("strain")[k], 0.01, 1e-12);
    EXPECT_EQ(vtu.arrays.at("connectivity")[2 * k], model.spring_node_a()[k]);
    EXPECT_EQ(vtu.arrays.at("connectivity")[2 * k + 1], model.spring_node_b()[k]);
    EXPECT_EQ(vtu.arrays.at("offsets")[k], 2.0 * (k + 1));
    EXPECT_EQ(vtu.arrays.at("types")[k], 3.0);
  }
  EXPECT_EQ(vtu.arrays.at("velocity")[0], 0.5);
}

TEST_F(ModelFileTest, VtuRejectsBadStates) {
  const Model model = BaudetModel(0.1);
  State state = State::AtRest(model);
  state.positions(1, 3) = std::nan("");
  try {
    WriteVtu(model, state, Path("nan.vtu"));
    ADD_FAILURE() << "wrote a NaN position";
  } catch (const std::invalid_argument& e) {
    EXPECT_CONTAINS(std::string(e.what()), "node 3 has a non-finite position");
  }
  State velocity = State::AtRest(model);
  velocity.velocities(0, 5) = INFINITY;
  EXPECT_THROW(WriteVtu(model, velocity, Path("inf.vtu")), std::invalid_argument);
  State short_state = State::AtRest(model);
  short_state.positions.conservativeResize(3, model.num_nodes() - 1);
  EXPECT_THROW(WriteVtu(model, short_state, Path("short.vtu")), std::invalid_argument);
  try {
    WriteVtu(model, State::AtRest(model), Path("no_such_dir/model.vtu"));
    ADD_FAILURE() << "wrote into a missing directory";
  } catch (const std::runtime_error& e) {
    EXPECT_CONTAINS(std::string(e.what()), Path("no_such_dir/model.vtu"));
  }
}

}  // namespace
}  // namespace msm_sim::core
