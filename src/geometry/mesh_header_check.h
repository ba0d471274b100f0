#pragma once
// Private to the mesh importer (mesh_import.cpp): cheap checks of a mesh file's header, run before
// assimp reads the file. Assimp allocates what a header declares before it reads the elements
// (assimp-testmodels' OutOfMemory.off, 309 bytes declaring 3.5e11 vertices, took 15.8 GB), so
// refusing a header that declares more elements than the file can hold, or than one import may
// take, is what bounds the memory and time of an import.
//
// Every check returns the problem as one line (the importer prefixes "mesh '<path>': "), or an
// empty string if the header is consistent with the file. A file a check cannot make sense of is
// left to assimp, which refuses it with its own message.

#include <cstdint>
#include <string>
#include <string_view>

namespace msm_sim::core::mesh_header {

/// How many elements one import may declare.
struct Limits {
  std::uint64_t max_vertices = 0;
  std::uint64_t max_triangles = 0;  ///< faces: a polygon counts once
};

/// The checks read at most this many bytes from the start of the file (the glTF JSON excepted).
inline constexpr std::size_t kHeadBytes = 64 * 1024;

/// OFF ("OFF", "COFF", "NOFF", "STOFF", "4OFF", "nOFF" with a dimension, or counts alone, as
/// assimp reads them): the vertex and face counts against the bytes after the header, each vertex
/// a line of at least one number per coordinate, each face a line of at least two numbers.
/// `head`: the file's first bytes (up to kHeadBytes), `size`: the file's size.
std::string CheckOff(std::string_view head, std::uint64_t size, const Limits& limits);

/// PLY, ascii and binary: every element's count times the least bytes one instance takes (from
/// its properties' types) against the bytes after "end_header". A header without "end_header" in
/// the first kHeadBytes is refused: assimp's reader loops forever on one.
std::string CheckPly(std::string_view head, std::uint64_t size, const Limits& limits);

/// PLY, ascii and binary, after CheckPly: every list's item count (a face's vertex indices)
/// against the bytes after it. Assimp allocates a list as its count declares: a 500-byte file
/// whose face declares 4294967295 indices made it allocate 32 GB (found under AddressSanitizer,
/// which has no address-space cap to turn that into bad_alloc). `file`: the whole file.
std::string CheckPlyLists(std::string_view file);

/// STL: a binary file must be 84 + 50 n bytes for the n triangles it declares, compared in 64
/// bits (assimp's format detection compares them in 32 bits, so a wrapped count passes it);
/// anything else must be ascii ("solid"). The message says which was expected and why it does not
/// fit.
std::string CheckStl(std::string_view head, std::uint64_t size, const Limits& limits);

/// glTF 1 and 2 JSON: nesting depth (assimp's JSON parser recurses), every embedded buffer's
/// byteLength against the bytes that can hold it (a data URI's length, or `embedded_bytes`, the
/// binary chunk of a .glb; assimp checks an external buffer against its file itself) and every
/// accessor's count against the buffers' total.
std::string CheckGltfJson(std::string_view json, std::uint64_t embedded_bytes);

/// Binary glTF (.glb), versions 1 and 2: the chunk lengths against the file size, then
/// CheckGltfJson on the JSON chunk. `file`: the whole file.
std::string CheckGlb(std::string_view file);

/// Runs the checks of the extension (stl, off, ply, gltf, glb), then those of the first bytes
/// ("ply", an OFF keyword, "glTF", an STL): assimp falls back on the reader the content names
/// when the extension's refuses the file. Reads what they need of `path` (`size` bytes).
/// Precondition: `path` is a regular file of `size` bytes.
std::string CheckMeshHeader(const std::string& path, std::uint64_t size, const Limits& limits);

// Shared by the checks.

/// a + b and a * b, saturating at the uint64 maximum.
std::uint64_t SaturatingAdd(std::uint64_t a, std::uint64_t b);
std::uint64_t SaturatingMul(std::uint64_t a, std::uint64_t b);
/// The decimal digits at `*pos` of `text` as a count (saturating), advancing `*pos` past them;
/// false (and `*pos` unchanged) if there is no digit there.
bool ReadCount(std::string_view text, std::size_t* pos, std::uint64_t* count);
/// The problem "the header declares <what>, which need at least <need> bytes, but ... <have>".
std::string Overclaims(const std::string& what, std::uint64_t need, std::uint64_t have);
/// "" if `count` <= `limit`, else the problem naming `noun` and the option that sets the limit.
std::string OverLimit(std::uint64_t count, const char* noun, std::uint64_t limit,
                      const char* option);

}  // namespace msm_sim::core::mesh_header
