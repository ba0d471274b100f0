#include "geometry/mesh_header_check.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <limits>
#include <string>

namespace msm_sim::core::mesh_header {
namespace {

constexpr std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max();

// Assimp's ParsingUtils: blanks are spaces and tabs, line ends '\r', '\n', '\f' and NUL.
bool IsBlank(char c) { return c == ' ' || c == '\t'; }
bool IsLineEnd(char c) { return c == '\n' || c == '\r' || c == '\f' || c == '\0'; }

// Assimp's OFF reader's NextToken: skips blanks, line ends and '#' comment lines.
void NextOffToken(std::string_view text, std::size_t* pos) {
  const auto skip_blank = [&] {
    while (*pos < text.size() && (IsBlank(text[*pos]) || IsLineEnd(text[*pos]))) ++*pos;
  };
  skip_blank();
  while (*pos < text.size() && text[*pos] == '#') {
    while (*pos < text.size() && !IsLineEnd(text[*pos])) ++*pos;
    skip_blank();
  }
}

// The OFF header's flags, in the order assimp reads them: [ST][C][N][4][n]OFF.
struct OffKeyword {
  bool texcoords = false, colors = false, normals = false, homogeneous = false;
  bool dimension = false, keyword = false;
};

OffKeyword ReadOffKeyword(std::string_view text, std::size_t* pos) {
  OffKeyword k;
  const auto take = [&](std::string_view word) {
    if (text.substr(*pos, word.size()) != word) return false;
    *pos += word.size();
    return true;
  };
  k.texcoords = take("ST");
  k.colors = take("C");
  k.normals = take("N");
  k.homogeneous = take("4");
  k.dimension = take("n");
  k.keyword = take("OFF");
  if (!k.keyword) k.homogeneous = false;  // assimp: no keyword, so those were counts
  return k;
}

std::string Str(std::uint64_t value) { return std::to_string(value); }

std::string Lowercase(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

// The extension after the file name's last dot, lowercase; "" if none.
std::string Extension(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  return Lowercase(path.substr(dot + 1));
}

// Up to `limit` bytes from the start of the file.
std::string ReadHead(const std::string& path, std::uint64_t limit) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes(static_cast<std::size_t>(limit), '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  bytes.resize(static_cast<std::size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  return bytes;
}

bool LooksLikeOff(std::string_view head) {
  std::size_t pos = 0;
  NextOffToken(head, &pos);
  return ReadOffKeyword(head, &pos).keyword;
}

// Assimp's STL reader claims a file of another extension whose first 200 bytes hold "stl" or
// "solid"; only the binary count needs checking then.
bool LooksLikeStl(std::string_view head) {
  const std::string start = Lowercase(std::string(head.substr(0, 200)));
  return start.find("solid") != std::string::npos || start.find("stl") != std::string::npos;
}

std::uint32_t GetU32(std::string_view bytes, std::size_t offset) {
  std::uint32_t value = 0;
  for (int i = 0; i < 4; ++i) {
    value |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[offset + i])) << (8 * i);
  }
  return value;
}

// The binary STL problem, or "" if the file is a consistent binary STL; *binary tells whether
// assimp takes it for one (its size matches the count in 32-bit arithmetic).
std::string BinaryStlProblem(std::string_view head, std::uint64_t size, const Limits& limits,
                             bool* binary) {
  *binary = false;
  if (size < 84 || head.size() < 84) return "";
  const std::uint64_t triangles = GetU32(head, 80);
  const std::uint64_t expected = 84 + 50 * triangles;
  *binary = static_cast<std::uint32_t>(expected) == static_cast<std::uint32_t>(size);
  if (!*binary) return "";
  if (expected != size) {
    return Overclaims(Str(triangles) + " binary STL triangles", expected - 84, size - 84);
  }
  return OverLimit(triangles, "triangles", limits.max_triangles, "max_triangles");
}

}  // namespace

std::uint64_t SaturatingAdd(std::uint64_t a, std::uint64_t b) {
  return a > kMax - b ? kMax : a + b;
}

std::uint64_t SaturatingMul(std::uint64_t a, std::uint64_t b) {
  return (a != 0 && b > kMax / a) ? kMax : a * b;
}

bool ReadCount(std::string_view text, std::size_t* pos, std::uint64_t* count) {
  std::size_t p = *pos;
  std::uint64_t value = 0;
  while (p < text.size() && text[p] >= '0' && text[p] <= '9') {
    value = SaturatingAdd(SaturatingMul(value, 10), static_cast<std::uint64_t>(text[p] - '0'));
    ++p;
  }
  if (p == *pos) return false;
  *pos = p;
  *count = value;
  return true;
}

std::string Overclaims(const std::string& what, std::uint64_t need, std::uint64_t have) {
  return "the header declares " + what + ", which need at least " + Str(need) +
         " bytes, but only " + Str(have) +
         " follow the header; the file is truncated or its header is wrong";
}

std::string OverLimit(std::uint64_t count, const char* noun, std::uint64_t limit,
                      const char* option) {
  if (count <= limit) return "";
  return "the file declares " + Str(count) + " " + noun + ", more than the " + Str(limit) +
         " one import may hold (MeshImportOptions::" + option + "); simplify the mesh";
}

std::string CheckOff(std::string_view head, std::uint64_t size, const Limits& limits) {
  std::size_t pos = 0;
  NextOffToken(head, &pos);
  const OffKeyword k = ReadOffKeyword(head, &pos);
  NextOffToken(head, &pos);
  std::uint64_t dimensions = 3;
  if (k.dimension) {
    if (!ReadCount(head, &pos, &dimensions)) dimensions = 0;
    NextOffToken(head, &pos);
  }
  std::uint64_t vertices = 0, faces = 0, edges = 0;
  const bool counted = ReadCount(head, &pos, &vertices);
  NextOffToken(head, &pos);
  ReadCount(head, &pos, &faces);
  NextOffToken(head, &pos);
  ReadCount(head, &pos, &edges);
  NextOffToken(head, &pos);
  if (pos >= head.size() && head.size() < size) {
    return "the OFF header does not end within its first " + Str(kHeadBytes) + " bytes";
  }
  // Assimp refuses these itself.
  if (!counted || dimensions > 3 || vertices == 0 || faces == 0) return "";

  // A vertex is a line of numbers, each at least a digit and a separator; a face a line of a
  // count and at least one index. The last line may lack its line end.
  const std::uint64_t numbers = std::max<std::uint64_t>(dimensions, 1) + (k.homogeneous ? 1 : 0) +
                                (k.normals ? 3 : 0) + (k.colors ? 1 : 0) + (k.texcoords ? 2 : 0);
  const std::uint64_t need =
      SaturatingAdd(SaturatingMul(vertices, 2 * numbers), SaturatingMul(faces, 4)) - 1;
  const std::uint64_t have = size - pos;
  if (need > have)
    return Overclaims(Str(vertices) + " vertices and " + Str(faces) + " faces", need, have);
  std::string problem = OverLimit(vertices, "vertices", limits.max_vertices, "max_vertices");
  if (problem.empty()) problem = OverLimit(faces, "faces", limits.max_triangles, "max_triangles");
  return problem;
}

std::string CheckStl(std::string_view head, std::uint64_t size, const Limits& limits) {
  bool binary = false;
  const std::string problem = BinaryStlProblem(head, size, limits, &binary);
  if (binary) return problem;
  std::size_t pos = 0;
  while (pos < head.size() && IsBlank(head[pos])) ++pos;
  if (head.substr(pos, 5) == "solid") return "";  // ascii: no counts
  std::string declared;
  if (size >= 84 && head.size() >= 84) {
    const std::uint64_t triangles = GetU32(head, 80);
    declared = ": its header declares " + Str(triangles) + " triangles, so " +
               Str(84 + 50 * triangles) + " bytes";
  }
  return "neither an ascii STL (starting with \"solid\") nor a binary STL (84 + 50 n bytes for n "
         "triangles" +
         declared + ", but the file has " + Str(size) + "); it is truncated or not an STL file";
}

// CheckPly on the head, then CheckPlyLists on the whole file (read only if the counts fit it).
std::string CheckWholePly(const std::string& path, const std::string& head, std::uint64_t size,
                          const Limits& limits) {
  const std::string problem = CheckPly(head, size, limits);
  if (!problem.empty()) return problem;
  return CheckPlyLists(size <= head.size() ? head : ReadHead(path, size));
}

// The checks of the reader assimp picks by the first bytes (another extension, or the fallback
// when the extension's reader refuses the file).
std::string CheckByContent(const std::string& path, const std::string& head, std::uint64_t size,
                           const Limits& limits) {
  if (Lowercase(head.substr(0, 3)) == "ply") return CheckWholePly(path, head, size, limits);
  if (LooksLikeOff(head)) return CheckOff(head, size, limits);
  if (head.substr(0, 4) == "glTF") return CheckGlb(ReadHead(path, size));
  if (LooksLikeStl(head)) {
    bool binary = false;
    return BinaryStlProblem(head, size, limits, &binary);
  }
  return "";
}

// The checks of the reader the extension names ("" for none).
std::string CheckByExtension(const std::string& path, const std::string& extension,
                             const std::string& head, std::uint64_t size, const Limits& limits) {
  if (extension == "gltf") return CheckGltfJson(ReadHead(path, size), 0);
  if (extension == "glb") return CheckGlb(ReadHead(path, size));
  if (extension == "stl") return CheckStl(head, size, limits);
  if (extension == "off") return CheckOff(head, size, limits);
  if (extension == "ply") return CheckWholePly(path, head, size, limits);
  return "";  // obj has no counts (the file size bounds it); others go by content
}

std::string CheckMeshHeader(const std::string& path, std::uint64_t size, const Limits& limits) {
  const std::string head = ReadHead(path, kHeadBytes);
  const std::string problem = CheckByExtension(path, Extension(path), head, size, limits);
  if (!problem.empty()) return problem;
  // When the extension's reader refuses a file, assimp tries the others by its first bytes: a
  // ".gltf" holding a PLY header without its end hung its PLY reader (found by make fuzz).
  return CheckByContent(path, head, size, limits);
}

}  // namespace msm_sim::core::mesh_header
