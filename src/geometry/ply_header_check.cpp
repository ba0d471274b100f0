// CheckPly and CheckPlyLists (mesh_header_check.h): a PLY header's element counts, and each
// list's item count, against the bytes after them.
#include <algorithm>
#include <cctype>
#include <string>
#include <vector>

#include "geometry/mesh_header_check.h"

namespace msm_sim::core::mesh_header {
namespace {

// One "property": a scalar of `bytes`, or a list of items of `bytes` after a count of
// `count_bytes` (binary sizes; 0 for a type assimp does not know).
struct PlyProperty {
  bool list = false;
  std::uint64_t count_bytes = 0;
  std::uint64_t bytes = 0;
};

// One "element <name> <count>", its properties and the least bytes one instance of it takes.
struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::uint64_t ascii_bytes = 0;   // a digit and a separator per scalar or list
  std::uint64_t binary_bytes = 0;  // the scalars' sizes; a list's count (it may be empty)
  std::vector<PlyProperty> properties;
};

// The format line's encoding.
enum class PlyEncoding { kAscii, kLittleEndian, kBigEndian };

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
std::size_t ReadPlyHeader(std::string_view head, PlyEncoding* encoding,
                          std::vector<PlyElement>* elements) {
  std::size_t pos = 0;
  while (pos < head.size()) {
    const std::size_t eol = head.find('\n', pos);
    if (eol == std::string_view::npos) return 0;
    const std::vector<std::string_view> tokens = Tokens(head.substr(pos, eol - pos));
    pos = eol + 1;
    if (tokens.empty()) continue;
    if (tokens[0] == "end_header") return pos;
    if (tokens[0] == "format" && tokens.size() > 1) {
      *encoding = tokens[1] == "ascii"               ? PlyEncoding::kAscii
                  : tokens[1] == "binary_big_endian" ? PlyEncoding::kBigEndian
                                                     : PlyEncoding::kLittleEndian;
    }
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
      PlyProperty property;
      property.list = list;
      property.count_bytes = list && tokens.size() > 2 ? TypeBytes(tokens[2]) : 0;
      property.bytes = TypeBytes(tokens[list ? std::min<std::size_t>(3, tokens.size() - 1) : 1]);
      element.properties.push_back(property);
    }
  }
  return 0;
}

// The item count a list declares, too many for the `left` bytes after it to hold: "" if none.
std::string ListOverclaims(const PlyElement& element, std::uint64_t instance, std::uint64_t items,
                           std::uint64_t least_item_bytes, std::uint64_t left) {
  if (items <= left / least_item_bytes) return "";
  return "PLY " + element.name + " " + std::to_string(instance) + " declares a list of " +
         std::to_string(items) + " items, more than the " + std::to_string(left) +
         " bytes after it can hold; the file is damaged";
}

// Ascii: each list's count against the bytes after it (an item takes a digit and a separator).
std::string CheckAsciiLists(std::string_view body, const std::vector<PlyElement>& elements) {
  std::size_t pos = 0;
  const auto next = [&body, &pos](std::string_view* token) {
    while (pos < body.size() && std::isspace(static_cast<unsigned char>(body[pos]))) ++pos;
    const std::size_t start = pos;
    while (pos < body.size() && !std::isspace(static_cast<unsigned char>(body[pos]))) ++pos;
    *token = body.substr(start, pos - start);
    return pos > start;
  };
  std::string_view token;
  for (const PlyElement& element : elements) {
    for (std::uint64_t i = 0; i < element.count; ++i) {
      for (const PlyProperty& property : element.properties) {
        if (!next(&token)) return "";  // short files are CheckPly's to refuse
        if (!property.list) continue;
        // A negative count reads as a huge unsigned one in assimp, as in the binary files.
        const bool negative = token[0] == '-';
        std::size_t digit = negative ? 1 : 0;
        std::uint64_t items = 0;
        if (!ReadCount(token, &digit, &items)) return "";  // not a count: assimp's to judge
        if (negative && items > 0) items = ~std::uint64_t{0};
        const std::string problem = ListOverclaims(element, i, items, 2, body.size() - pos + 1);
        if (!problem.empty()) return problem;
        for (std::uint64_t k = 0; k < items; ++k) next(&token);
      }
    }
  }
  return "";
}

std::uint64_t ReadUnsigned(std::string_view bytes, bool big_endian) {
  std::uint64_t value = 0;
  for (std::size_t k = 0; k < bytes.size(); ++k) {
    const std::size_t at = big_endian ? k : bytes.size() - 1 - k;
    value = (value << 8) | static_cast<unsigned char>(bytes[at]);
  }
  return value;
}

// Binary: each list's count (read as unsigned: a negative one is huge) against the bytes left.
std::string CheckBinaryLists(std::string_view body, bool big_endian,
                             const std::vector<PlyElement>& elements) {
  std::uint64_t pos = 0;
  for (const PlyElement& element : elements) {
    for (std::uint64_t i = 0; i < element.count; ++i) {
      for (const PlyProperty& property : element.properties) {
        if (property.bytes == 0 || (property.list && property.count_bytes == 0)) return "";
        const std::uint64_t scalar = property.list ? property.count_bytes : property.bytes;
        if (scalar > body.size() - pos) return "";  // short files are CheckPly's to refuse
        if (!property.list) {
          pos += scalar;
          continue;
        }
        const std::uint64_t items = ReadUnsigned(body.substr(pos, scalar), big_endian);
        pos += scalar;
        const std::string problem =
            ListOverclaims(element, i, items, property.bytes, body.size() - pos);
        if (!problem.empty()) return problem;
        pos += items * property.bytes;
      }
    }
  }
  return "";
}

}  // namespace

std::string CheckPly(std::string_view head, std::uint64_t size, const Limits& limits) {
  PlyEncoding encoding = PlyEncoding::kAscii;
  std::vector<PlyElement> elements;
  const std::size_t body = ReadPlyHeader(head, &encoding, &elements);
  const bool ascii = encoding == PlyEncoding::kAscii;
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

std::string CheckPlyLists(std::string_view file) {
  PlyEncoding encoding = PlyEncoding::kAscii;
  std::vector<PlyElement> elements;
  const std::size_t body = ReadPlyHeader(file.substr(0, kHeadBytes), &encoding, &elements);
  if (body == 0) return "";  // CheckPly refuses it
  if (encoding == PlyEncoding::kAscii) return CheckAsciiLists(file.substr(body), elements);
  return CheckBinaryLists(file.substr(body), encoding == PlyEncoding::kBigEndian, elements);
}

}  // namespace msm_sim::core::mesh_header
