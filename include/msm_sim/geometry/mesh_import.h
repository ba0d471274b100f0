#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

#include "msm_sim/geometry/solid_mesh.h"
#include "msm_sim/geometry/triangle_mesh.h"

namespace msm_sim::core {

/// A mesh file that cannot be used; what() is one line naming the file and the problem.
class MeshImportError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct MeshImportOptions {
  /// Multiplies every coordinate: 0.001 for a file in millimetres, 0.01 for centimetres.
  double scale = 1.0;
  /// Refuse meshes whose largest bounding-box edge (after scaling) is outside this range (m):
  /// for objects a robot handles that is almost always a unit mistake (a 100 mm part in a file
  /// in millimetres reads as 100 m).
  double min_extent = 1e-4;
  double max_extent = 10.0;
  /// Vertices closer than this fraction of the bounding-box diagonal are merged, so that STL
  /// files (one vertex per triangle corner) share their edges.
  double weld_tolerance = 1e-7;
  /// Bounds on the work of one import, so that a damaged or hostile file is refused with a clear
  /// message instead of taking the machine's memory: files larger than max_file_bytes are not
  /// read, and a file whose header declares (or whose scene holds) more vertices or faces than
  /// these is refused before they are allocated.
  std::uint64_t max_file_bytes = std::uint64_t{512} << 20;
  std::uint64_t max_vertices = 50'000'000;
  std::uint64_t max_triangles = 50'000'000;
};

/// What ImportTriangleMesh did to the file's contents.
struct ImportedMesh {
  TriangleMesh mesh;           ///< all triangles of the file, in the file's root frame, scaled
  int source_meshes = 0;       ///< meshes merged (with their node transforms applied)
  int removed_degenerate = 0;  ///< zero-area triangles dropped
  MeshTopology topology;       ///< of the merged, welded mesh
};

/// Reads any format assimp reads (STL, OBJ, PLY, OFF, DAE, glTF, ...), merges every mesh of the
/// scene in the root frame, drops points, lines and zero-area triangles, welds coincident
/// vertices and applies the scale. It does not require the surface to be closed: SolidMesh
/// checks that (the visual mesh of a skin may be open).
///
/// Throws MeshImportError for a missing or unreadable file, a file over the options' limits, a
/// header that declares more elements than the file holds (OFF, PLY, STL, glTF; checked before
/// assimp allocates them), a format assimp rejects, a scene without triangles, non-finite
/// coordinates, or an absurd size; never crashes on a malformed file that assimp itself survives.
/// Precondition-free: bad options are reported the same way.
ImportedMesh ImportTriangleMesh(const std::string& path, const MeshImportOptions& options = {});

/// ImportTriangleMesh, then the closed solid it bounds (to build a model from). Everything wrong
/// with the file, including an open or non-manifold surface, is a MeshImportError naming it.
SolidMesh ImportSolidMesh(const std::string& path, const MeshImportOptions& options = {});

}  // namespace msm_sim::core
