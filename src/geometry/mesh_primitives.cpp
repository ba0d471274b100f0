#include "msm_sim/geometry/mesh_primitives.h"

#include <cmath>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <utility>
#include <vector>

namespace msm_sim::core {
namespace {

TriangleMesh FromLists(const std::vector<Eigen::Vector3d>& vertices,
                       const std::vector<Eigen::Vector3i>& triangles) {
  TriangleMesh mesh;
  mesh.vertices.resize(3, static_cast<Eigen::Index>(vertices.size()));
  for (std::size_t v = 0; v < vertices.size(); ++v) mesh.vertices.col(v) = vertices[v];
  mesh.triangles.resize(3, static_cast<Eigen::Index>(triangles.size()));
  for (std::size_t t = 0; t < triangles.size(); ++t) mesh.triangles.col(t) = triangles[t];
  return mesh;
}

void RequirePositive(double value, const char* what) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw std::invalid_argument(std::string(what) + " must be finite and > 0");
  }
}

}  // namespace

TriangleMesh MakeBoxMesh(const Eigen::Vector3d& size) {
  for (int axis = 0; axis < 3; ++axis) RequirePositive(size[axis], "box size");
  std::vector<Eigen::Vector3d> v;
  for (int corner = 0; corner < 8; ++corner) {
    v.emplace_back((corner & 1 ? 0.5 : -0.5) * size.x(), (corner & 2 ? 0.5 : -0.5) * size.y(),
                   (corner & 4 ? 0.5 : -0.5) * size.z());
  }
  // Two counter-clockwise (seen from outside) triangles per face.
  const std::vector<Eigen::Vector3i> t = {
      {0, 2, 3}, {0, 3, 1},  // -z
      {4, 5, 7}, {4, 7, 6},  // +z
      {0, 1, 5}, {0, 5, 4},  // -y
      {2, 6, 7}, {2, 7, 3},  // +y
      {0, 4, 6}, {0, 6, 2},  // -x
      {1, 3, 7}, {1, 7, 5},  // +x
  };
  return FromLists(v, t);
}

TriangleMesh MakeIcosphereMesh(double radius, int subdivisions) {
  RequirePositive(radius, "sphere radius");
  if (subdivisions < 0 || subdivisions > 7) {
    throw std::invalid_argument("sphere subdivisions must lie in 0..7");
  }
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> v = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                                    {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                                    {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  for (auto& p : v) p.normalize();
  std::vector<Eigen::Vector3i> t = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    auto middle = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      const int index = static_cast<int>(v.size()) - 1;
      midpoint.emplace(key, index);
      return index;
    };
    std::vector<Eigen::Vector3i> finer;
    finer.reserve(t.size() * 4);
    for (const Eigen::Vector3i& tri : t) {
      const int ab = middle(tri[0], tri[1]);
      const int bc = middle(tri[1], tri[2]);
      const int ca = middle(tri[2], tri[0]);
      finer.emplace_back(tri[0], ab, ca);
      finer.emplace_back(tri[1], bc, ab);
      finer.emplace_back(tri[2], ca, bc);
      finer.emplace_back(ab, bc, ca);
    }
    t = std::move(finer);
  }
  for (auto& p : v) p *= radius;
  return FromLists(v, t);
}

TriangleMesh MakeCylinderMesh(double radius, double height, int segments) {
  RequirePositive(radius, "cylinder radius");
  RequirePositive(height, "cylinder height");
  if (segments < 3) throw std::invalid_argument("a cylinder needs at least 3 segments");
  std::vector<Eigen::Vector3d> v = {{0, 0, -0.5 * height}, {0, 0, 0.5 * height}};
  for (int s = 0; s < segments; ++s) {
    const double angle = 2.0 * M_PI * s / segments;
    v.emplace_back(radius * std::cos(angle), radius * std::sin(angle), -0.5 * height);
    v.emplace_back(radius * std::cos(angle), radius * std::sin(angle), 0.5 * height);
  }
  std::vector<Eigen::Vector3i> t;
  for (int s = 0; s < segments; ++s) {
    const int b0 = 2 + 2 * s, t0 = b0 + 1;
    const int b1 = 2 + 2 * ((s + 1) % segments), t1 = b1 + 1;
    t.emplace_back(0, b1, b0);  // bottom cap, facing -z
    t.emplace_back(1, t0, t1);  // top cap, facing +z
    t.emplace_back(b0, b1, t1);
    t.emplace_back(b0, t1, t0);
  }
  return FromLists(v, t);
}

TriangleMesh MakeTorusMesh(double major, double minor, int major_segments, int minor_segments) {
  RequirePositive(major, "torus major radius");
  RequirePositive(minor, "torus minor radius");
  if (minor >= major) throw std::invalid_argument("torus minor radius must be < major radius");
  if (major_segments < 3 || minor_segments < 3) {
    throw std::invalid_argument("a torus needs at least 3 segments each way");
  }
  std::vector<Eigen::Vector3d> v;
  for (int i = 0; i < major_segments; ++i) {
    const double u = 2.0 * M_PI * i / major_segments;
    for (int j = 0; j < minor_segments; ++j) {
      const double w = 2.0 * M_PI * j / minor_segments;
      const double r = major + minor * std::cos(w);
      v.emplace_back(r * std::cos(u), r * std::sin(u), minor * std::sin(w));
    }
  }
  auto index = [&](int i, int j) {
    return (i % major_segments) * minor_segments + (j % minor_segments);
  };
  std::vector<Eigen::Vector3i> t;
  for (int i = 0; i < major_segments; ++i) {
    for (int j = 0; j < minor_segments; ++j) {
      t.emplace_back(index(i, j), index(i + 1, j), index(i + 1, j + 1));
      t.emplace_back(index(i, j), index(i + 1, j + 1), index(i, j + 1));
    }
  }
  return FromLists(v, t);
}

}  // namespace msm_sim::core
