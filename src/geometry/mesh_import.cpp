#include "msm_sim/geometry/mesh_import.h"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <sys/stat.h>
#include <assimp/Importer.hpp>

#include "geometry/mesh_header_check.h"
#include "msm_sim/io/regular_file.h"

namespace msm_sim::core {
namespace {

std::string Describe(double value) {
  std::ostringstream out;
  out.precision(3);
  out << value;
  return out.str();
}

[[noreturn]] void Fail(const std::string& path, const std::string& problem) {
  throw MeshImportError("mesh '" + path + "': " + problem);
}

// Rejects bad options, a path that is not a non-empty regular file, a file over the size limit
// and a header that declares more than the file holds or the limits allow, before assimp sees it.
void CheckInput(const std::string& path, const MeshImportOptions& options) {
  if (!(options.scale > 0.0) || !std::isfinite(options.scale)) {
    Fail(path, "scale must be finite and > 0, got " + Describe(options.scale));
  }
  const std::string file_problem = RegularFileProblem(path);
  if (!file_problem.empty()) Fail(path, file_problem);
  struct stat info {};
  if (stat(path.c_str(), &info) != 0) Fail(path, "no such file");
  if (info.st_size == 0) Fail(path, "the file is empty");
  const auto size = static_cast<std::uint64_t>(info.st_size);
  if (size > options.max_file_bytes) {
    Fail(path, "the file has " + std::to_string(size) + " bytes, more than the " +
                   std::to_string(options.max_file_bytes) +
                   " one import may read (MeshImportOptions::max_file_bytes); simplify the mesh");
  }
  const std::string problem =
      mesh_header::CheckMeshHeader(path, size, {options.max_vertices, options.max_triangles});
  if (!problem.empty()) Fail(path, problem);
}

// Refuses a scene holding more vertices or faces than the options allow, or a face without
// vertices (assimp's triangulation asserts, aborting the process, on one), before post-processing
// or copying them.
void CheckScene(const std::string& path, const aiScene& scene, const MeshImportOptions& options) {
  std::uint64_t vertices = 0, faces = 0;
  for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
    const aiMesh* mesh = scene.mMeshes[m];
    if (mesh == nullptr) continue;
    vertices += mesh->mNumVertices;
    faces += mesh->mNumFaces;
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      if (mesh->mFaces[f].mNumIndices == 0 || mesh->mFaces[f].mIndices == nullptr) {
        Fail(path, "face " + std::to_string(f) + " has no vertices; the file is damaged");
      }
    }
  }
  std::string problem =
      mesh_header::OverLimit(vertices, "vertices", options.max_vertices, "max_vertices");
  if (problem.empty()) {
    problem = mesh_header::OverLimit(faces, "faces", options.max_triangles, "max_triangles");
  }
  if (!problem.empty()) Fail(path, problem);
}

[[noreturn]] void FailWithAssimpError(const std::string& path, const Assimp::Importer& importer) {
  std::string reason = importer.GetErrorString();
  if (reason.empty()) reason = "unknown reason";
  // Assimp's messages can span lines; keep the error to one.
  for (char& c : reason) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  Fail(path, "cannot be read as a mesh: " + reason);
}

// The scene with every face triangulated and every mesh in the root frame; the importer owns it.
// Read and validated first, then checked (CheckScene), then post-processed.
const aiScene& ReadScene(const std::string& path, const MeshImportOptions& options,
                         Assimp::Importer* importer) {
  // Points and lines carry no surface; have assimp drop them instead of mixing them in.
  importer->SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                               aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene = importer->ReadFile(path, aiProcess_ValidateDataStructure);
  if (scene == nullptr) FailWithAssimpError(path, *importer);
  CheckScene(path, *scene, options);
  scene = importer->ApplyPostProcessing(aiProcess_Triangulate | aiProcess_PreTransformVertices |
                                        aiProcess_SortByPType);
  if (scene == nullptr) FailWithAssimpError(path, *importer);
  return *scene;
}

// Appends the scaled vertices and the triangles (renumbered after the vertices already there) of
// one assimp mesh; returns whether it had any triangle.
bool AppendMesh(const std::string& path, const aiMesh& mesh, double scale,
                std::vector<Eigen::Vector3d>* vertices, std::vector<Eigen::Vector3i>* triangles) {
  const int base = static_cast<int>(vertices->size());
  bool used = false;
  for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
    const aiVector3D& p = mesh.mVertices[v];
    vertices->emplace_back(scale * Eigen::Vector3d(p.x, p.y, p.z));
  }
  for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
    const aiFace& face = mesh.mFaces[f];
    if (face.mNumIndices != 3) continue;
    Eigen::Vector3i tri;
    bool valid = true;
    for (int e = 0; e < 3; ++e) {
      valid = valid && face.mIndices[e] < mesh.mNumVertices;
      tri[e] = base + static_cast<int>(face.mIndices[e]);
    }
    if (!valid) Fail(path, "a face refers to a vertex that does not exist");
    triangles->push_back(tri);
    used = true;
  }
  return used;
}

// Every triangle mesh of the scene merged into one, scaled; *source_meshes receives how many
// contributed triangles. Fails if there are no triangles or non-finite coordinates.
TriangleMesh MergeMeshes(const std::string& path, const aiScene& scene, double scale,
                         int* source_meshes) {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;
  for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
    const aiMesh* mesh = scene.mMeshes[m];
    if (mesh == nullptr || !(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    if (AppendMesh(path, *mesh, scale, &vertices, &triangles)) ++*source_meshes;
  }
  if (triangles.empty())
    Fail(path, "the file contains no triangles (only points, lines or nothing)");

  TriangleMesh raw;
  raw.vertices.resize(3, static_cast<Eigen::Index>(vertices.size()));
  for (std::size_t v = 0; v < vertices.size(); ++v) raw.vertices.col(v) = vertices[v];
  raw.triangles.resize(3, static_cast<Eigen::Index>(triangles.size()));
  for (std::size_t t = 0; t < triangles.size(); ++t) raw.triangles.col(t) = triangles[t];
  if (!raw.vertices.allFinite()) Fail(path, "some vertex coordinates are not finite numbers");
  return raw;
}

// Fails if the mesh's size is outside the options' range (a unit mistake); returns its
// bounding-box diagonal (m).
double CheckedDiagonal(const std::string& path, const TriangleMesh& raw,
                       const MeshImportOptions& options) {
  Eigen::Vector3d min, max;
  BoundingBox(raw, &min, &max);
  const double extent = (max - min).maxCoeff();
  if (extent > options.max_extent || extent < options.min_extent) {
    Fail(path, "the mesh is " + Describe(extent) + " m across (after scale " +
                   Describe(options.scale) + "), outside [" + Describe(options.min_extent) + ", " +
                   Describe(options.max_extent) +
                   "] m; give the right scale (0.001 for a file in millimetres)");
  }
  return (max - min).norm();
}

}  // namespace

ImportedMesh ImportTriangleMesh(const std::string& path, const MeshImportOptions& options) {
  CheckInput(path, options);
  Assimp::Importer importer;
  const aiScene& scene = ReadScene(path, options, &importer);

  ImportedMesh result;
  const TriangleMesh raw = MergeMeshes(path, scene, options.scale, &result.source_meshes);
  const double diagonal = CheckedDiagonal(path, raw, options);
  TriangleMesh welded = WeldVertices(raw, options.weld_tolerance * diagonal);
  result.mesh =
      RemoveDegenerateTriangles(welded, 1e-14 * diagonal * diagonal, &result.removed_degenerate);
  if (result.mesh.num_triangles() == 0) Fail(path, "every triangle is degenerate (zero area)");
  result.topology = AnalyzeTopology(result.mesh);
  return result;
}

SolidMesh ImportSolidMesh(const std::string& path, const MeshImportOptions& options) {
  ImportedMesh imported = ImportTriangleMesh(path, options);
  try {
    return SolidMesh(imported.mesh);
  } catch (const std::invalid_argument& e) {
    Fail(path, e.what());
  }
}

}  // namespace msm_sim::core
