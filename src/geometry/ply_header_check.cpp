// CheckPly (mesh_header_check.h): a PLY header's element counts against the bytes after it.
#include <algorithm>
#include <cctype>
#include <string>
#include <vector>

#include "geometry/mesh_header_check.h"

namespace msm_sim::core::mesh_header {
namespace {

// One "element <name> <count>" and the least bytes one instance of it takes.
struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::uint64_t ascii_bytes = 0;   // a digit and a separator per scalar or list
  std::uint64_t binary_bytes = 0;  // the scalars' sizes; a list's count (it may be empty)
};

// The size of a PLY scalar type, 0 if assimp does not know it.
std::uint64_t TypeBytes(std::string_view type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32" || type == "float" ||
      type == "float32") {
    return 4;
  }
  if (type == "double" || type == "float64") return 8;
  return 0;
}

std::vector<std::string_view> Tokens(std::string_view line) {
  std::vector<std::string_view> tokens;
  std::size_t pos = 0;
  while (pos < line.size()) {
    while (pos < line.size() && std::isspace(static_cast<unsigned char>(line[pos]))) ++pos;
    const std::size_t start = pos;
    while (pos < line.size() && !std::isspace(static_cast<unsigned char>(line[pos]))) ++pos;
    if (pos > start) tokens.push_back(line.substr(start, pos - start));
  }
  return tokens;
}

// Reads the header's lines into `elements`; returns the offset after "end_header", or 0 if the
// header does not end within `head`.
std::size_t ReadPlyHeader(std::string_view head, bool* ascii, std::vector<PlyElement>* elements) {
  std::size_t pos = 0;
  while (pos < head.size()) {
    const std::size_t eol = head.find('\n', pos);
    if (eol == std::string_view::npos) return 0;
    const std::vector<std::string_view> tokens = Tokens(head.substr(pos, eol - pos));
    pos = eol + 1;
    if (tokens.empty()) continue;
    if (tokens[0] == "end_header") return pos;
    if (tokens[0] == "format" && tokens.size() > 1) *ascii = tokens[1] == "ascii";
    if (tokens[0] == "element" && tokens.size() > 2) {
      PlyElement element;
      element.name = std::string(tokens[1]);
      std::size_t digit = 0;
      if (!ReadCount(tokens[2], &digit, &element.count)) element.count = 0;
      elements->push_back(element);
    }
    if (tokens[0] == "property" && tokens.size() > 1 && !elements->empty()) {
      PlyElement& element = elements->back();
      const bool list = tokens[1] == "list";
      element.ascii_bytes += 2;
      if (!list) element.binary_bytes += TypeBytes(tokens[1]);
      if (list && tokens.size() > 2) element.binary_bytes += TypeBytes(tokens[2]);
    }
  }
  return 0;
}

}  // namespace

std::string CheckPly(std::string_view head, std::uint64_t size, const Limits& limits) {
  bool ascii = true;
  std::vector<PlyElement> elements;
  const std::size_t body = ReadPlyHeader(head, &ascii, &elements);
  // Assimp's PLY reader loops forever on a header without its end.
  if (body == 0) {
    return "the PLY header has no \"end_header\" line within the first " +
           std::to_string(std::min<std::uint64_t>(size, kHeadBytes)) +
           " bytes; the file is truncated or damaged";
  }
  std::uint64_t need = 0;
  std::string what;
  for (const PlyElement& element : elements) {
    // An instance of an element without properties still takes a byte: no file has a million
    // of them, and assimp would loop over them.
    const std::uint64_t instance =
        std::max<std::uint64_t>(ascii ? element.ascii_bytes : element.binary_bytes, 1);
    need = SaturatingAdd(need, SaturatingMul(element.count, instance));
    what += (what.empty() ? "" : ", ") + std::to_string(element.count) + " " + element.name;
  }
  if (ascii && need > 0) --need;  // the last number needs no separator
  const std::uint64_t have = size - body;
  if (need > have) return Overclaims("elements " + what, need, have);
  for (const PlyElement& element : elements) {
    std::string problem;
    if (element.name == "vertex") {
      problem = OverLimit(element.count, "vertices", limits.max_vertices, "max_vertices");
    }
    if (element.name == "face") {
      problem = OverLimit(element.count, "faces", limits.max_triangles, "max_triangles");
    }
    if (!problem.empty()) return problem;
  }
  return "";
}

}  // namespace msm_sim::core::mesh_header
