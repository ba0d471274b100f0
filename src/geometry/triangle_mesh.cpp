#include "msm_sim/geometry/triangle_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <Eigen/Geometry>

namespace msm_sim::core {
namespace {

std::uint64_t EdgeKey(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}

bool HasRepeatedVertex(const Eigen::Vector3i& t) {
  return t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
}

double TriangleArea(const TriangleMesh& mesh, int t) {
  const Eigen::Vector3d a = mesh.vertices.col(mesh.triangles(0, t));
  const Eigen::Vector3d b = mesh.vertices.col(mesh.triangles(1, t));
  const Eigen::Vector3d c = mesh.vertices.col(mesh.triangles(2, t));
  return 0.5 * (b - a).cross(c - a).norm();
}

}  // namespace

MeshTopology AnalyzeTopology(const TriangleMesh& mesh) {
  MeshTopology topology;
  std::unordered_map<std::uint64_t, int> edge_uses;
  edge_uses.reserve(static_cast<std::size_t>(mesh.num_triangles()) * 2);
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const Eigen::Vector3i tri = mesh.triangles.col(t);
    if (HasRepeatedVertex(tri) || !(TriangleArea(mesh, t) > 0.0)) ++topology.degenerate_triangles;
    for (int e = 0; e < 3; ++e) ++edge_uses[EdgeKey(tri[e], tri[(e + 1) % 3])];
  }
  for (const auto& [edge, uses] : edge_uses) {
    if (uses == 1) ++topology.boundary_edges;
    if (uses > 2) ++topology.non_manifold_edges;
    if (uses > 2 && uses % 2 == 1) ++topology.odd_non_manifold_edges;
  }
  return topology;
}

TriangleMesh WeldVertices(const TriangleMesh& mesh, double tolerance) {
  // Quantise to cells of edge `tolerance` and look for a representative in the 27 cells around
  // each vertex, so that vertices closer than the tolerance merge even across cell borders.
  const double cell = tolerance > 0.0 ? tolerance : 1.0;
  using Cell = Eigen::Matrix<std::int64_t, 3, 1>;
  // Cell coordinates in 64 bits, clamped (NaN to 0): a far or non-finite vertex, or a tiny
  // tolerance, made the int cast overflow (UB) and the neighbour offsets overflow again.
  auto cell_of = [&](const Eigen::Vector3d& p) {
    Cell c;
    for (int i = 0; i < 3; ++i) {
      const double f = std::floor(p[i] / cell);
      c[i] = f == f ? static_cast<std::int64_t>(std::clamp(f, -1e15, 1e15)) : 0;
    }
    return c;
  };
  auto key = [](const Cell& c) {
    return (static_cast<std::uint64_t>(c.x() & 0x1FFFFF) << 42) |
           (static_cast<std::uint64_t>(c.y() & 0x1FFFFF) << 21) |
           static_cast<std::uint64_t>(c.z() & 0x1FFFFF);
  };
  std::unordered_map<std::uint64_t, std::vector<int>> cells;
  std::vector<int> representative(mesh.num_vertices(), -1);
  std::vector<int> new_index(mesh.num_vertices(), -1);
  std::vector<Eigen::Vector3d> kept;
  const double tolerance_sq = tolerance * tolerance;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Eigen::Vector3d p = mesh.vertices.col(v);
    const Cell c = cell_of(p);
    int found = -1;
    for (int dz = -1; dz <= 1 && found < 0; ++dz) {
      for (int dy = -1; dy <= 1 && found < 0; ++dy) {
        for (int dx = -1; dx <= 1 && found < 0; ++dx) {
          const auto it = cells.find(key(c + Cell(dx, dy, dz)));
          if (it == cells.end()) continue;
          for (const int k : it->second) {
            if ((kept[k] - p).squaredNorm() <= tolerance_sq) {
              found = k;
              break;
            }
          }
        }
      }
    }
    if (found < 0) {
      found = static_cast<int>(kept.size());
      kept.push_back(p);
      cells[key(c)].push_back(found);
    }
    new_index[v] = found;
  }
  TriangleMesh welded;
  welded.vertices.resize(3, static_cast<Eigen::Index>(kept.size()));
  for (std::size_t k = 0; k < kept.size(); ++k) welded.vertices.col(k) = kept[k];
  welded.triangles.resize(3, mesh.num_triangles());
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    for (int e = 0; e < 3; ++e) welded.triangles(e, t) = new_index[mesh.triangles(e, t)];
  }
  return welded;
}

TriangleMesh RemoveDegenerateTriangles(const TriangleMesh& mesh, double min_area, int* removed) {
  std::vector<int> keep;
  keep.reserve(mesh.num_triangles());
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    if (!HasRepeatedVertex(mesh.triangles.col(t)) && TriangleArea(mesh, t) > min_area) {
      keep.push_back(t);
    }
  }
  if (removed != nullptr) *removed = mesh.num_triangles() - static_cast<int>(keep.size());
  TriangleMesh result;
  result.vertices = mesh.vertices;
  result.triangles.resize(3, static_cast<Eigen::Index>(keep.size()));
  for (std::size_t k = 0; k < keep.size(); ++k)
    result.triangles.col(k) = mesh.triangles.col(keep[k]);
  return result;
}

double SignedVolume(const TriangleMesh& mesh) {
  if (mesh.num_vertices() == 0) return 0.0;
  // Tetrahedra from a point near the mesh keep the sum well conditioned far from the origin.
  const Eigen::Vector3d origin = mesh.vertices.col(0);
  double six_volume = 0.0;
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const Eigen::Vector3d a = mesh.vertices.col(mesh.triangles(0, t)) - origin;
    const Eigen::Vector3d b = mesh.vertices.col(mesh.triangles(1, t)) - origin;
    const Eigen::Vector3d c = mesh.vertices.col(mesh.triangles(2, t)) - origin;
    six_volume += a.dot(b.cross(c));
  }
  return six_volume / 6.0;
}

double CrossSectionArea(const TriangleMesh& mesh, const Eigen::Vector3d& point,
                        const Eigen::Vector3d& normal) {
  const Eigen::Vector3d n = normal.normalized();
  // Each triangle crossing the plane contributes one edge of the section's boundary. Oriented
  // along n x n_t it has the inside of the body on its left (seen from n), so Green's theorem
  // sums 1/2 n . (p x q) over the edges to the enclosed area.
  double twice_area = 0.0;
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    std::array<Eigen::Vector3d, 3> v;
    std::array<double, 3> d;
    for (int e = 0; e < 3; ++e) {
      v[e] = mesh.vertices.col(mesh.triangles(e, t)) - point;
      d[e] = v[e].dot(n);
    }
    // Points exactly on the plane count as above it: a consistent tie-break keeps loops closed.
    std::array<bool, 3> above{d[0] >= 0.0, d[1] >= 0.0, d[2] >= 0.0};
    std::vector<Eigen::Vector3d> crossing;
    for (int e = 0; e < 3; ++e) {
      const int f = (e + 1) % 3;
      if (above[e] == above[f]) continue;
      const double s = d[e] / (d[e] - d[f]);
      crossing.push_back(v[e] + s * (v[f] - v[e]));
    }
    if (crossing.size() != 2) continue;
    const Eigen::Vector3d face_normal = (v[1] - v[0]).cross(v[2] - v[0]);
    Eigen::Vector3d p = crossing[0];
    Eigen::Vector3d q = crossing[1];
    if ((q - p).dot(n.cross(face_normal)) < 0.0) std::swap(p, q);
    twice_area += n.dot(p.cross(q));
  }
  return 0.5 * std::abs(twice_area);
}

void BoundingBox(const TriangleMesh& mesh, Eigen::Vector3d* min, Eigen::Vector3d* max) {
  *min = mesh.vertices.rowwise().minCoeff();
  *max = mesh.vertices.rowwise().maxCoeff();
}

Eigen::Matrix3Xd VertexNormals(const TriangleMesh& mesh, const Eigen::Matrix3Xd& positions) {
  Eigen::Matrix3Xd normals = Eigen::Matrix3Xd::Zero(3, positions.cols());
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const Eigen::Vector3i tri = mesh.triangles.col(t);
    // The unnormalised cross product weighs each face by its area.
    const Eigen::Vector3d face = (positions.col(tri[1]) - positions.col(tri[0]))
                                     .cross(positions.col(tri[2]) - positions.col(tri[0]));
    for (int e = 0; e < 3; ++e) normals.col(tri[e]) += face;
  }
  for (Eigen::Index v = 0; v < normals.cols(); ++v) {
    const double length = normals.col(v).norm();
    if (length > 0.0) normals.col(v) /= length;
  }
  return normals;
}

}  // namespace msm_sim::core
