// The mesh header checks (src/geometry/mesh_header_check.h) and the import limits: a header that
// declares more than its file holds is refused before assimp allocates, a valid file never is.
#include <cstdint>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "forked_run.h"
#include "geometry/mesh_header_check.h"
#include "mesh_files.h"
#include "msm_sim/geometry/mesh_import.h"

namespace msm_sim::core {
namespace {

using mesh_header::Limits;
using testing::MeshFile;

constexpr Limits kLimits{50'000'000, 50'000'000};

#define EXPECT_CONTAINS(text, part) \
  EXPECT_NE(std::string(text).find(part), std::string::npos) << "'" << (text) << "'"

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

std::string WriteFile(const std::string& name, const std::string& bytes) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

TEST(MeshHeaderCheck, EveryValidCubeFileImportsUnrefused) {
  int index = 0;
  for (const MeshFile& file : testing::CubeFiles()) {
    const std::string path =
        WriteFile("cube" + std::to_string(index++) + "." + file.extension, file.bytes);
    EXPECT_EQ(mesh_header::CheckMeshHeader(path, file.bytes.size(), kLimits), "") << path;
    const ImportedMesh imported = ImportTriangleMesh(path);
    EXPECT_EQ(imported.mesh.num_triangles(), 12) << path;
    EXPECT_EQ(imported.mesh.num_vertices(), 8) << path;
    EXPECT_TRUE(imported.topology.closed()) << path;
  }
}

TEST(MeshHeaderCheck, OffCountsMustFitTheFile) {
  const std::string off = testing::Off(testing::TestCube());
  EXPECT_EQ(mesh_header::CheckOff(off, off.size(), kLimits), "");
  // assimp-testmodels' OutOfMemory.off: 3.5e11 vertices in 309 bytes.
  const std::string huge = Replace(off, "8 12 0", "353535235358 12 0");
  EXPECT_CONTAINS(mesh_header::CheckOff(huge, huge.size(), kLimits),
                  "declares 353535235358 vertices and 12 faces");
  const std::string many_faces = Replace(off, "8 12 0", "8 4000 0");
  EXPECT_CONTAINS(mesh_header::CheckOff(many_faces, many_faces.size(), kLimits), "truncated");
  // Without the keyword assimp reads the counts alone; with "nOFF" a dimension first.
  const std::string bare = Replace(off, "OFF\n", "");
  EXPECT_EQ(mesh_header::CheckOff(bare, bare.size(), kLimits), "");
  const std::string bare_huge = Replace(bare, "8 12 0", "99999999999 12 0");
  EXPECT_NE(mesh_header::CheckOff(bare_huge, bare_huge.size(), kLimits), "");
  const std::string dimension = Replace(huge, "OFF\n", "nOFF 3\n");
  EXPECT_NE(mesh_header::CheckOff(dimension, dimension.size(), kLimits), "");
  EXPECT_CONTAINS(mesh_header::CheckOff(off, off.size(), {7, 100}), "max_vertices");
  EXPECT_CONTAINS(mesh_header::CheckOff(off, off.size(), {100, 11}), "max_triangles");
  // A header that never ends within what the check reads is refused, not searched further.
  const std::string comments = "OFF\n" + std::string(mesh_header::kHeadBytes, '#');
  EXPECT_CONTAINS(mesh_header::CheckOff(comments, comments.size() + 100, kLimits), "does not end");
}

TEST(MeshHeaderCheck, PlyElementCountsMustFitTheBytesAfterTheHeader) {
  const TriangleMesh cube = testing::TestCube();
  for (const std::string& ply : {testing::AsciiPly(cube), testing::BinaryPly(cube)}) {
    EXPECT_EQ(mesh_header::CheckPly(ply, ply.size(), kLimits), "");
    const std::string huge = Replace(ply, "element vertex 8", "element vertex 4294967295");
    EXPECT_CONTAINS(mesh_header::CheckPly(huge, huge.size(), kLimits),
                    "4294967295 vertex, 12 face");
    EXPECT_CONTAINS(mesh_header::CheckPly(ply, ply.size(), {7, 100}), "max_vertices");
  }
  // Binary sizes are exact but for lists, which may be empty (a byte for the count).
  const std::string binary = testing::BinaryPly(cube);
  const std::string more_vertices = Replace(binary, "element vertex 8", "element vertex 30");
  EXPECT_CONTAINS(mesh_header::CheckPly(more_vertices, more_vertices.size(), kLimits),
                  "need at least 372 bytes, but only 252");
  const std::string more_faces = Replace(binary, "element face 12", "element face 200");
  EXPECT_CONTAINS(mesh_header::CheckPly(more_faces, more_faces.size(), kLimits), "truncated");
  // Assimp's reader loops forever on a header without its end (found by test_mesh_fuzz.cpp).
  const std::string cut = binary.substr(0, binary.find("end_header"));
  EXPECT_CONTAINS(mesh_header::CheckPly(cut, cut.size(), kLimits), "no \"end_header\" line");
}

TEST(MeshHeaderCheck, BinaryStlCountMustMatchTheSizeIn64Bits) {
  std::string stl = testing::BinaryStl(testing::TestCube());
  EXPECT_EQ(mesh_header::CheckStl(stl, stl.size(), kLimits), "");
  EXPECT_CONTAINS(mesh_header::CheckStl(stl, stl.size(), {100, 11}), "max_triangles");
  // 12 + 2^31 triangles: 84 + 50 n equals the file size modulo 2^32, so assimp's 32-bit format
  // detection takes it for a binary STL (its reader then finds it too small).
  const std::uint32_t wrapped = 12 + (std::uint32_t{1} << 31);
  std::memcpy(&stl[80], &wrapped, 4);
  EXPECT_CONTAINS(mesh_header::CheckStl(stl, stl.size(), kLimits),
                  "declares 2147483660 binary STL triangles");
  // Neither binary (size) nor ascii ("solid"): refused with what was expected.
  const std::string truncated = testing::BinaryStl(testing::TestCube()).substr(0, 500);
  EXPECT_CONTAINS(mesh_header::CheckStl(truncated, truncated.size(), kLimits),
                  "so 684 bytes, but the file has 500");
  const std::string ascii = testing::AsciiStl(testing::TestCube());
  EXPECT_EQ(mesh_header::CheckStl(ascii, ascii.size(), kLimits), "");
}

TEST(MeshHeaderCheck, GltfBuffersAccessorsAndNesting) {
  const TriangleMesh cube = testing::TestCube();
  const std::string gltf = testing::Gltf(cube);
  EXPECT_EQ(mesh_header::CheckGltfJson(gltf, 0), "");
  EXPECT_CONTAINS(mesh_header::CheckGltfJson(
                      Replace(gltf, "\"byteLength\":168", "\"byteLength\":9000000000"), 0),
                  "a glTF buffer declares 9000000000 bytes");
  EXPECT_CONTAINS(
      mesh_header::CheckGltfJson(Replace(gltf, "\"count\":36", "\"count\":4000000000"), 0),
      "accessor declares 4000000000 elements");
  // glTF 1 keys buffers by id; its binary extension backs the "data:," buffer by the .glb's body.
  const std::string binary_gltf =
      R"({"buffers":{"binary_glTF":{"byteLength":100,"uri":"data:,"}}})";
  EXPECT_EQ(mesh_header::CheckGltfJson(binary_gltf, 100), "");
  EXPECT_CONTAINS(mesh_header::CheckGltfJson(binary_gltf, 99), "declares 100 bytes");
  // A million '[' would overflow the stack of assimp's recursive JSON parser.
  const std::string deep = "{\"extras\":" + std::string(1'000'000, '[') + "}";
  EXPECT_CONTAINS(mesh_header::CheckGltfJson(deep, 0), "nests deeper than");

  const std::string glb = testing::Glb(cube);
  EXPECT_EQ(mesh_header::CheckGlb(glb), "");
  EXPECT_NE(mesh_header::CheckGlb(glb.substr(0, glb.size() - 1)), "");  // binary chunk short
  std::string long_json = glb;
  const std::uint32_t json_bytes = 0x7fffffff;
  std::memcpy(&long_json[12], &json_bytes, 4);
  EXPECT_CONTAINS(mesh_header::CheckGlb(long_json), "a JSON chunk of 2147483647 bytes");
  // Same length, so that the chunk lengths still hold.
  const std::string embedded = Replace(glb, "\"byteLength\":168", "\"byteLength\":999");
  EXPECT_CONTAINS(mesh_header::CheckGlb(embedded),
                  "declares 999 bytes, but its data has at most 168");
}

TEST(MeshHeaderCheck, ImportLimitsGiveOneClearLine) {
  const std::string obj = WriteFile("limits_cube.obj", testing::Obj(testing::TestCube()));
  MeshImportOptions options;
  options.max_file_bytes = 100;
  EXPECT_THROW(
      {
        try {
          ImportTriangleMesh(obj, options);
        } catch (const MeshImportError& e) {
          EXPECT_CONTAINS(e.what(), "mesh '" + obj + "': the file has ");
          EXPECT_CONTAINS(e.what(), "max_file_bytes");
          throw;
        }
      },
      MeshImportError);
  // OBJ declares no counts: the scene assimp read is checked before it is copied.
  options = MeshImportOptions();
  options.max_triangles = 11;
  EXPECT_THROW(
      {
        try {
          ImportTriangleMesh(obj, options);
        } catch (const MeshImportError& e) {
          EXPECT_CONTAINS(e.what(), "12 faces, more than the 11");
          throw;
        }
      },
      MeshImportError);
}

// Each list's item count against the bytes after it: assimp allocates what a list declares, and
// a 500-byte file whose face declares 4294967295 indices made it allocate 32 GB (found by
// test_mesh_fuzz.cpp under AddressSanitizer, which has no address-space cap to stop it).
TEST(MeshHeaderCheck, PlyListCountsMustFitTheBytesAfterThem) {
  const core::TriangleMesh cube = testing::TestCube();
  const std::string ascii = testing::AsciiPly(cube);
  const std::string binary = testing::BinaryPly(cube);
  EXPECT_EQ(mesh_header::CheckPlyLists(ascii), "");
  EXPECT_EQ(mesh_header::CheckPlyLists(binary), "");
  const std::string huge = Replace(ascii, "\n3 0 ", "\n4294967295 0 ");
  EXPECT_NE(mesh_header::CheckPlyLists(huge).find("PLY face 0 declares a list of 4294967295 items"),
            std::string::npos);
  const std::string negative = Replace(ascii, "\n3 0 ", "\n-1 0 ");
  EXPECT_NE(mesh_header::CheckPlyLists(negative).find("a list of 18446744073709551615 items"),
            std::string::npos);
  // The last face of the binary cube: 4 indices of 4 bytes where 12 bytes are left.
  std::string more_indices = binary;
  more_indices[more_indices.size() - 13] = 4;
  EXPECT_NE(mesh_header::CheckPlyLists(more_indices).find("PLY face 11 declares a list of 4 items"),
            std::string::npos);
  try {
    ImportTriangleMesh(WriteFile("huge_list.ply", huge));
    ADD_FAILURE() << "huge_list.ply was imported";
  } catch (const MeshImportError& e) {
    EXPECT_NE(std::string(e.what()).find("more than the"), std::string::npos) << e.what();
  }
}

// Assimp falls back on the reader the first bytes name when the extension's refuses a file: a
// ".gltf" holding a PLY header without "end_header" hung its PLY reader (found by make fuzz), so
// the content's checks run whatever the extension.
TEST(MeshHeaderCheck, TheContentsChecksRunWhateverTheExtension) {
  const std::string truncated_ply = "ply\nformat ascii 1.0\ncom";
  for (const char* name : {"ply_inside.gltf", "ply_inside.obj", "ply_inside.dae"}) {
    const std::string path = WriteFile(name, truncated_ply);
    EXPECT_NE(mesh_header::CheckMeshHeader(path, truncated_ply.size(), kLimits).find("end_header"),
              std::string::npos)
        << name;
  }
}

// A face line "0" gives a face without vertices, on which assimp's triangulation asserts and
// aborts the process (found by test_mesh_fuzz.cpp); in a child, so that a regression fails the
// test rather than ending the test binary.
TEST(MeshHeaderCheck, AFaceWithoutVerticesIsRefusedNotAnAbort) {
  const std::string path = WriteFile(
      "empty_face.ply", Replace(testing::AsciiPly(testing::TestCube()), "\n3 0 ", "\n0\n3 0 "));
  const testing::ChildRun run = testing::RunInChild(
      [&] {
        try {
          ImportTriangleMesh(path);
          return 0;
        } catch (const MeshImportError& e) {
          return std::string(e.what()).find("has no vertices") != std::string::npos ? 1 : 2;
        }
      },
      std::uint64_t{1} << 30, 30);
  EXPECT_TRUE(run.exited && run.exit_code == 1) << run.Describe();
}

// Through the importer, in a child limited to 1 GB: files that make assimp allocate gigabytes,
// overflow its stack (deep.gltf: SIGSEGV without the check) or pass its 32-bit STL detection are
// refused by their headers, in a few megabytes. Under the limit assimp's allocation would fail and
// it would refuse the OFF too, so the child checks that the header check gave the message.
TEST(MeshHeaderCheck, HostileHeadersAreRefusedInLittleMemory) {
  std::string wrapped_stl = testing::BinaryStl(testing::TestCube());
  const std::uint32_t wrapped = 12 + (std::uint32_t{1} << 31);
  std::memcpy(&wrapped_stl[80], &wrapped, 4);
  const std::string deep =
      "{\"asset\":{\"version\":\"2.0\"},\"extras\":" + std::string(1'000'000, '[') +
      std::string(1'000'000, ']') + "}";
  const std::string off = Replace(testing::Off(testing::TestCube()), "8 12", "353535235358 12");
  struct Hostile {
    std::string name, bytes, message;
  };
  for (const Hostile& file :
       {Hostile{"wrapped.stl", wrapped_stl, "2147483660 binary STL triangles"},
        Hostile{"deep.gltf", deep, "nests deeper than 64 levels"},
        Hostile{"out_of_memory.off", off, "353535235358 vertices"}}) {
    const std::string path = WriteFile(file.name, file.bytes);
    const testing::ChildRun run = testing::RunInChild(
        [&] {
          try {
            ImportTriangleMesh(path);
            return 0;
          } catch (const MeshImportError& e) {
            if (std::string(e.what()).find(file.message) != std::string::npos) return 1;
            std::fprintf(stderr, "%s\n", e.what());
            return 2;
          }
        },
        std::uint64_t{1} << 30, 30);
    EXPECT_TRUE(run.exited && run.exit_code == 1) << file.name << ": " << run.Describe();
    EXPECT_LT(run.bounded_rss_mb(), 200) << file.name;
    std::printf("%-18s %s  %.3f s  %.1f MB\n", file.name.c_str(), run.Describe().c_str(),
                run.seconds, run.max_rss_mb);
  }
}

}  // namespace
}  // namespace msm_sim::core
