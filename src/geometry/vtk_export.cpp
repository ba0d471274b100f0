#include "msm_sim/geometry/vtk_export.h"

#include <cerrno>
#include <fstream>
#include <locale>
#include <stdexcept>
#include <string>
#include <system_error>

namespace msm_sim::core {
namespace {

constexpr int kVtkLine = 3;

// errno is only meaningful if the failing call set it; say so rather than print "Success".
std::string IoError(const std::string& path, const std::string& what) {
  const int error = errno;
  return "VTK file '" + path + "': " + what + ": " +
         (error != 0 ? std::generic_category().message(error) : std::string("I/O error"));
}

void CheckState(const Model& model, const State& state) {
  const int n = model.num_nodes();
  if (state.positions.cols() != n || state.velocities.cols() != n) {
    throw std::invalid_argument("WriteVtu: the state has " +
                                std::to_string(state.positions.cols()) + " positions and " +
                                std::to_string(state.velocities.cols()) +
                                " velocities but the model has " + std::to_string(n) + " nodes");
  }
  for (int i = 0; i < n; ++i) {
    if (!state.positions.col(i).allFinite()) {
      throw std::invalid_argument("WriteVtu: node " + std::to_string(i) +
                                  " has a non-finite position");
    }
  }
  for (int i = 0; i < n; ++i) {
    if (!state.velocities.col(i).allFinite()) {
      throw std::invalid_argument("WriteVtu: node " + std::to_string(i) +
                                  " has a non-finite velocity");
    }
  }
}

void BeginArray(std::ostream& out, const char* type, const char* name, int components) {
  out << "        <DataArray type=\"" << type << "\"";
  if (name != nullptr) out << " Name=\"" << name << "\"";
  if (components > 1) out << " NumberOfComponents=\"" << components << "\"";
  out << " format=\"ascii\">\n";
}

void EndArray(std::ostream& out) { out << "        </DataArray>\n"; }

// One column per line keeps the file readable and the lines short.
void WriteColumns(std::ostream& out, const Eigen::Matrix3Xd& values) {
  for (Eigen::Index i = 0; i < values.cols(); ++i) {
    out << "          " << values(0, i) << ' ' << values(1, i) << ' ' << values(2, i) << '\n';
  }
}

// Per node: mass, displacement from rest and velocity.
void WritePointData(std::ostream& out, const Model& model, const State& state) {
  const int n = model.num_nodes();
  out << "      <PointData Scalars=\"mass\" Vectors=\"displacement\">\n";
  BeginArray(out, "Float64", "mass", 1);
  for (int i = 0; i < n; ++i) out << "          " << model.masses()[i] << '\n';
  EndArray(out);
  BeginArray(out, "Float64", "displacement", 3);
  WriteColumns(out, state.Displacements(model));
  EndArray(out);
  BeginArray(out, "Float64", "velocity", 3);
  WriteColumns(out, state.velocities);
  EndArray(out);
  out << "      </PointData>\n";
}

// Per spring: stiffness, rest length and strain (current length / rest length - 1).
void WriteCellData(std::ostream& out, const Model& model, const State& state) {
  const int s_count = model.num_springs();
  out << "      <CellData Scalars=\"strain\">\n";
  BeginArray(out, "Float64", "stiffness", 1);
  for (int s = 0; s < s_count; ++s) out << "          " << model.spring_stiffness()[s] << '\n';
  EndArray(out);
  BeginArray(out, "Float64", "rest_length", 1);
  for (int s = 0; s < s_count; ++s) out << "          " << model.spring_rest_length()[s] << '\n';
  EndArray(out);
  BeginArray(out, "Float64", "strain", 1);
  for (int s = 0; s < s_count; ++s) {
    const double length = (state.positions.col(model.spring_node_b()[s]) -
                           state.positions.col(model.spring_node_a()[s]))
                              .norm();
    out << "          " << length / model.spring_rest_length()[s] - 1.0 << '\n';
  }
  EndArray(out);
  out << "      </CellData>\n";
}

// One VTK_LINE cell per spring, from node a to node b. Int64 throughout: offsets reach 2 S,
// which overflows Int32 for S > 2^30 springs.
void WriteCells(std::ostream& out, const Model& model) {
  const int s_count = model.num_springs();
  out << "      <Cells>\n";
  BeginArray(out, "Int64", "connectivity", 1);
  for (int s = 0; s < s_count; ++s) {
    out << "          " << model.spring_node_a()[s] << ' ' << model.spring_node_b()[s] << '\n';
  }
  EndArray(out);
  BeginArray(out, "Int64", "offsets", 1);
  for (int s = 0; s < s_count; ++s)
    out << "          " << 2 * (static_cast<long long>(s) + 1) << '\n';
  EndArray(out);
  BeginArray(out, "UInt8", "types", 1);
  for (int s = 0; s < s_count; ++s) out << "          " << kVtkLine << '\n';
  EndArray(out);
  out << "      </Cells>\n";
}

}  // namespace

void WriteVtu(const Model& model, const State& state, const std::string& path) {
  CheckState(model, state);

  errno = 0;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error(IoError(path, "cannot open for writing"));
  // VTK parses "C" numbers; a global locale with a decimal comma must not leak into the file.
  out.imbue(std::locale::classic());
  out.precision(17);

  out << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "  <UnstructuredGrid>\n"
      << "    <Piece NumberOfPoints=\"" << model.num_nodes() << "\" NumberOfCells=\""
      << model.num_springs() << "\">\n";
  WritePointData(out, model, state);
  WriteCellData(out, model, state);
  out << "      <Points>\n";
  BeginArray(out, "Float64", nullptr, 3);
  WriteColumns(out, state.positions);
  EndArray(out);
  out << "      </Points>\n";
  WriteCells(out, model);
  out << "    </Piece>\n"
      << "  </UnstructuredGrid>\n"
      << "</VTKFile>\n";

  out.close();
  if (!out) throw std::runtime_error(IoError(path, "cannot write"));
}

}  // namespace msm_sim::core
