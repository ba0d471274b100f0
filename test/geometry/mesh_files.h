#pragma once
// Shared by the mesh import tests that damage files: a small closed mesh (a 0.1 m cube, 8
// vertices, 12 triangles) written in every format the importer's header checks know, as bytes.

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "msm_sim/geometry/mesh_primitives.h"
#include "msm_sim/geometry/triangle_mesh.h"

namespace msm_sim::testing {

/// A mesh file's extension (which picks assimp's reader) and its bytes.
struct MeshFile {
  std::string extension;
  std::string bytes;
};

inline core::TriangleMesh TestCube() { return core::MakeBoxMesh(Eigen::Vector3d(0.1, 0.1, 0.1)); }

template <typename T>
void AppendLittleEndian(T value, std::string* out) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));  // the test hosts are little-endian (x86-64, arm64)
  out->append(reinterpret_cast<const char*>(bytes), sizeof(T));
}

inline std::string Numbers(const Eigen::Vector3d& v) {
  return std::to_string(v.x()) + " " + std::to_string(v.y()) + " " + std::to_string(v.z());
}

inline std::string AsciiStl(const core::TriangleMesh& mesh) {
  std::string out = "solid cube\n";
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    out += "facet normal 0 0 0\nouter loop\n";
    for (int e = 0; e < 3; ++e) {
      out += "vertex " + Numbers(mesh.vertices.col(mesh.triangles(e, t))) + "\n";
    }
    out += "endloop\nendfacet\n";
  }
  return out + "endsolid cube\n";
}

inline std::string BinaryStl(const core::TriangleMesh& mesh) {
  std::string out(80, ' ');
  AppendLittleEndian(static_cast<std::uint32_t>(mesh.num_triangles()), &out);
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    for (int i = 0; i < 3; ++i) AppendLittleEndian(0.0f, &out);  // normal
    for (int e = 0; e < 3; ++e) {
      for (int d = 0; d < 3; ++d) {
        AppendLittleEndian(static_cast<float>(mesh.vertices(d, mesh.triangles(e, t))), &out);
      }
    }
    AppendLittleEndian(std::uint16_t{0}, &out);
  }
  return out;
}

inline std::string Obj(const core::TriangleMesh& mesh) {
  std::string out;
  for (int v = 0; v < mesh.num_vertices(); ++v) out += "v " + Numbers(mesh.vertices.col(v)) + "\n";
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    out += "f " + std::to_string(mesh.triangles(0, t) + 1) + " " +
           std::to_string(mesh.triangles(1, t) + 1) + " " +
           std::to_string(mesh.triangles(2, t) + 1) + "\n";
  }
  return out;
}

inline std::string Off(const core::TriangleMesh& mesh) {
  std::string out = "OFF\n# a cube\n" + std::to_string(mesh.num_vertices()) + " " +
                    std::to_string(mesh.num_triangles()) + " 0\n";
  for (int v = 0; v < mesh.num_vertices(); ++v) out += Numbers(mesh.vertices.col(v)) + "\n";
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    out += "3 " + std::to_string(mesh.triangles(0, t)) + " " +
           std::to_string(mesh.triangles(1, t)) + " " + std::to_string(mesh.triangles(2, t)) + "\n";
  }
  return out;
}

inline std::string PlyHeader(const core::TriangleMesh& mesh, const std::string& format) {
  return "ply\nformat " + format + " 1.0\ncomment a cube\nelement vertex " +
         std::to_string(mesh.num_vertices()) +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
         std::to_string(mesh.num_triangles()) +
         "\nproperty list uchar int vertex_indices\nend_header\n";
}

inline std::string AsciiPly(const core::TriangleMesh& mesh) {
  std::string out = PlyHeader(mesh, "ascii");
  for (int v = 0; v < mesh.num_vertices(); ++v) out += Numbers(mesh.vertices.col(v)) + "\n";
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    out += "3 " + std::to_string(mesh.triangles(0, t)) + " " +
           std::to_string(mesh.triangles(1, t)) + " " + std::to_string(mesh.triangles(2, t)) + "\n";
  }
  return out;
}

inline std::string BinaryPly(const core::TriangleMesh& mesh) {
  std::string out = PlyHeader(mesh, "binary_little_endian");
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    for (int d = 0; d < 3; ++d) AppendLittleEndian(static_cast<float>(mesh.vertices(d, v)), &out);
  }
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    AppendLittleEndian(std::uint8_t{3}, &out);
    for (int e = 0; e < 3; ++e) AppendLittleEndian(std::int32_t{mesh.triangles(e, t)}, &out);
  }
  return out;
}

inline std::string Base64(const std::string& bytes) {
  static const char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t chunk = 0;
    for (std::size_t j = 0; j < 3; ++j) {
      chunk = (chunk << 8) | (i + j < bytes.size() ? static_cast<unsigned char>(bytes[i + j]) : 0);
    }
    for (std::size_t j = 0; j < 4; ++j) {
      out += (i + j <= bytes.size()) ? kDigits[(chunk >> (18 - 6 * j)) & 63] : '=';
    }
  }
  return out;
}

/// The glTF buffer: uint16 indices (72 bytes), then float positions (96 bytes).
inline std::string GltfBuffer(const core::TriangleMesh& mesh) {
  std::string out;
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    for (int e = 0; e < 3; ++e)
      AppendLittleEndian(static_cast<std::uint16_t>(mesh.triangles(e, t)), &out);
  }
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    for (int d = 0; d < 3; ++d) AppendLittleEndian(static_cast<float>(mesh.vertices(d, v)), &out);
  }
  return out;
}

/// glTF 2 JSON for GltfBuffer; `uri` is the buffer's "uri" member ("" for a .glb's own chunk).
inline std::string GltfJson(const core::TriangleMesh& mesh, const std::string& uri) {
  const std::string buffer = GltfBuffer(mesh);
  const std::string index_bytes = std::to_string(6 * mesh.num_triangles());
  const std::string uri_member = uri.empty() ? "" : ",\"uri\":\"" + uri + "\"";
  return "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
         "\"nodes\":[{\"mesh\":0}],\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":1},"
         "\"indices\":0}]}],\"buffers\":[{\"byteLength\":" +
         std::to_string(buffer.size()) + uri_member +
         "}],\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":" + index_bytes +
         "},{\"buffer\":0,\"byteOffset\":" + index_bytes +
         ",\"byteLength\":" + std::to_string(12 * mesh.num_vertices()) +
         "}],\"accessors\":[{\"bufferView\":0,\"componentType\":5123,\"count\":" +
         std::to_string(3 * mesh.num_triangles()) +
         ",\"type\":\"SCALAR\"},{\"bufferView\":1,\"componentType\":5126,\"count\":" +
         std::to_string(mesh.num_vertices()) +
         ",\"type\":\"VEC3\",\"min\":[-0.05,-0.05,-0.05],\"max\":[0.05,0.05,0.05]}]}";
}

inline std::string Gltf(const core::TriangleMesh& mesh) {
  return GltfJson(mesh, "data:application/octet-stream;base64," + Base64(GltfBuffer(mesh)));
}

inline std::string Glb(const core::TriangleMesh& mesh) {
  std::string json = GltfJson(mesh, "");
  json.resize((json.size() + 3) / 4 * 4, ' ');
  const std::string buffer = GltfBuffer(mesh);  // 168 bytes, a multiple of 4
  std::string out = "glTF";
  AppendLittleEndian(std::uint32_t{2}, &out);
  AppendLittleEndian(static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + buffer.size()), &out);
  AppendLittleEndian(static_cast<std::uint32_t>(json.size()), &out);
  out += "JSON";
  out += json;
  AppendLittleEndian(static_cast<std::uint32_t>(buffer.size()), &out);
  out += std::string("BIN\0", 4);
  return out + buffer;
}

/// The cube in every format: ascii and binary STL, OBJ, OFF, ascii and binary PLY, glTF, glb.
inline std::vector<MeshFile> CubeFiles() {
  const core::TriangleMesh cube = TestCube();
  return {{"stl", AsciiStl(cube)}, {"stl", BinaryStl(cube)}, {"obj", Obj(cube)},
          {"off", Off(cube)},      {"ply", AsciiPly(cube)},  {"ply", BinaryPly(cube)},
          {"gltf", Gltf(cube)},    {"glb", Glb(cube)}};
}

}  // namespace msm_sim::testing
