// CheckGltfJson and CheckGlb (mesh_header_check.h): the glTF fields that size assimp's
// allocations, checked against the bytes that can back them, and the JSON's nesting depth.
#include <algorithm>
#include <string>

#include "geometry/mesh_header_check.h"

namespace msm_sim::core::mesh_header {
namespace {

// Deeper JSON is refused: assimp's JSON parser (rapidjson) recurses once per level, so a file of
// a million '[' would overflow its stack. glTF itself nests a handful of levels.
constexpr int kMaxDepth = 64;

// A forward-only scanner of just enough JSON to find the fields that size allocations. Every
// function returns false on anything it cannot scan (the file is then assimp's to judge).
class JsonScanner {
 public:
  explicit JsonScanner(std::string_view text) : text_(text) {}

  bool too_deep() const { return too_deep_; }

  // The next non-blank character, '\0' at the end.
  char Peek() {
    while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\t' ||
                                   text_[pos_] == '\n' || text_[pos_] == '\r')) {
      ++pos_;
    }
    return pos_ < text_.size() ? text_[pos_] : '\0';
  }

  // A string; escapes are kept as written (the fields read here need none).
  bool String(std::string* out) {
    if (Peek() != '"') return false;
    const std::size_t start = ++pos_;
    while (pos_ < text_.size() && text_[pos_] != '"') pos_ += text_[pos_] == '\\' ? 2 : 1;
    if (pos_ >= text_.size()) return false;
    if (out != nullptr) *out = std::string(text_.substr(start, pos_ - start));
    ++pos_;
    return true;
  }

  // A number; *count is its value if it is a non-negative integer, else 0.
  bool Number(std::uint64_t* count) {
    Peek();
    *count = 0;
    const bool integer = ReadCount(text_, &pos_, count);
    const std::size_t start = pos_;
    while (pos_ < text_.size() &&
           std::string_view("+-.eE0123456789").find(text_[pos_]) != std::string_view::npos) {
      ++pos_;
    }
    if (pos_ > start) *count = 0;  // a sign, fraction or exponent: not a count
    return integer || pos_ > start;
  }

  // Calls item(key) for each member of the object here, or item("") for each element of the
  // array here; item must consume the value. `depth` is the nesting level of this container.
  template <typename Item>
  bool Items(int depth, Item&& item) {
    if (depth > kMaxDepth) {
      too_deep_ = true;
      return false;
    }
    const char open = Peek();
    if (open != '{' && open != '[') return false;
    const char close = open == '{' ? '}' : ']';
    ++pos_;
    if (Peek() == close) {
      ++pos_;
      return true;
    }
    for (;;) {
      std::string key;
      if (open == '{' && (!String(&key) || Peek() != ':')) return false;
      if (open == '{') ++pos_;
      if (!item(key)) return false;
      const char next = Peek();
      ++pos_;
      if (next == close) return true;
      if (next != ',') return false;
    }
  }

  // Any value, checking its depth.
  bool Skip(int depth) {
    const char c = Peek();
    if (c == '{' || c == '[') {
      return Items(depth, [&](const std::string&) { return Skip(depth + 1); });
    }
    if (c == '"') return String(nullptr);
    std::uint64_t ignored;
    if (Number(&ignored)) return true;
    for (std::string_view word : {"true", "false", "null"}) {
      if (text_.substr(pos_, word.size()) == word) {
        pos_ += word.size();
        return true;
      }
    }
    return false;
  }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  bool too_deep_ = false;
};

// What the glTF declares: its buffers' lengths (and where their bytes are) and its accessors'
// element counts.
struct GltfSizes {
  std::string problem;
  std::uint64_t buffer_bytes = 0;
  std::uint64_t largest_count = 0;
};

// One buffer object: byteLength against the bytes behind it, added to sizes->buffer_bytes.
bool ReadBuffer(JsonScanner& json, int depth, std::uint64_t embedded_bytes, GltfSizes* sizes) {
  std::uint64_t length = 0;
  std::string uri;
  bool has_uri = false;
  const bool ok = json.Items(depth, [&](const std::string& key) {
    if (key == "byteLength") return json.Number(&length);
    if (key == "uri") return has_uri = json.String(&uri);
    return json.Skip(depth + 1);
  });
  if (!ok) return false;
  // A data URI holds 3 bytes per 4 characters; an external file assimp checks itself. In a .glb
  // the binary chunk (glTF 2: the buffer without a URI; glTF 1: the one whose URI is "data:,")
  // may back it.
  const bool data = uri.rfind("data:", 0) == 0;
  const std::uint64_t available =
      data ? std::max<std::uint64_t>(uri.size(), embedded_bytes) : embedded_bytes;
  if ((data || !has_uri) && length > available && sizes->problem.empty()) {
    sizes->problem = "a glTF buffer declares " + std::to_string(length) +
                     " bytes, but its data has at most " + std::to_string(available) +
                     "; the file is truncated or damaged";
  }
  sizes->buffer_bytes = SaturatingAdd(sizes->buffer_bytes, length);
  return true;
}

bool ReadAccessor(JsonScanner& json, int depth, GltfSizes* sizes) {
  return json.Items(depth, [&](const std::string& key) {
    if (key != "count") return json.Skip(depth + 1);
    std::uint64_t count = 0;
    if (!json.Number(&count)) return false;
    sizes->largest_count = std::max(sizes->largest_count, count);
    return true;
  });
}

}  // namespace

std::string CheckGltfJson(std::string_view text, std::uint64_t embedded_bytes) {
  JsonScanner json(text);
  GltfSizes sizes;
  // glTF 2 keeps buffers and accessors in arrays, glTF 1 in objects keyed by id: Items takes both.
  const bool ok = json.Items(0, [&](const std::string& key) {
    if (key == "buffers") {
      return json.Items(
          1, [&](const std::string&) { return ReadBuffer(json, 2, embedded_bytes, &sizes); });
    }
    if (key == "accessors") {
      return json.Items(1, [&](const std::string&) { return ReadAccessor(json, 2, &sizes); });
    }
    return json.Skip(1);
  });
  if (json.too_deep()) {
    return "the glTF JSON nests deeper than " + std::to_string(kMaxDepth) +
           " levels; no glTF needs that, the file is damaged";
  }
  if (!ok) return "";  // not JSON we can scan: assimp's parser will say what is wrong
  if (!sizes.problem.empty()) return sizes.problem;
  // Every element takes at least a byte of some buffer.
  if (sizes.largest_count > sizes.buffer_bytes) {
    return "a glTF accessor declares " + std::to_string(sizes.largest_count) +
           " elements, but the buffers hold " + std::to_string(sizes.buffer_bytes) +
           " bytes; the file is damaged";
  }
  return "";
}

std::string CheckGlb(std::string_view file) {
  const auto u32 = [&](std::size_t offset) {
    std::uint32_t value = 0;
    for (int i = 0; i < 4; ++i) {
      value |= static_cast<std::uint32_t>(static_cast<unsigned char>(file[offset + i])) << (8 * i);
    }
    return value;
  };
  // Both versions: magic, version, total length, then the JSON's length at 12 and the JSON at 20.
  constexpr std::uint64_t kJsonStart = 20;
  if (file.size() < kJsonStart) return "";  // assimp refuses it
  const std::uint32_t version = u32(4);
  if (version != 1 && version != 2) return "";
  const std::uint64_t json_bytes = u32(12);
  const std::uint64_t after_header = file.size() - kJsonStart;
  if (json_bytes > after_header) {
    return Overclaims("a JSON chunk of " + std::to_string(json_bytes) + " bytes", json_bytes,
                      after_header);
  }
  const std::string_view json = file.substr(kJsonStart, json_bytes);
  // Version 1: the rest of the file is the binary buffer; version 2: a chunk with its length.
  std::uint64_t embedded = after_header - json_bytes;
  const std::uint64_t next = kJsonStart + json_bytes;
  if (version == 2) {
    embedded = 0;
    if (next + 8 <= file.size()) {
      embedded = u32(next);
      const std::uint64_t after_chunk_header = file.size() - next - 8;
      if (embedded > after_chunk_header) {
        return Overclaims("a binary chunk of " + std::to_string(embedded) + " bytes", embedded,
                          after_chunk_header);
      }
    }
  }
  return CheckGltfJson(json, embedded);
}

}  // namespace msm_sim::core::mesh_header
