#include "msm_sim/geometry/solid_mesh.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <Eigen/Geometry>

namespace msm_sim::core {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Surface = CGAL::Surface_mesh<Point>;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<Surface>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
using SideOf = CGAL::Side_of_triangle_mesh<Surface, Kernel, CGAL::Default, Tree>;
namespace pmp = CGAL::Polygon_mesh_processing;

Point ToPoint(const Eigen::Vector3d& p) { return Point(p.x(), p.y(), p.z()); }

// Throws std::invalid_argument, saying what to fix, unless the mesh is a finite surface whose
// every edge is used an even number of times (so that it separates an inside from an outside).
void CheckClosedAndFinite(const TriangleMesh& mesh) {
  if (mesh.num_triangles() == 0) throw std::invalid_argument("the mesh has no triangles");
  if (!mesh.vertices.allFinite()) {
    throw std::invalid_argument("the mesh has vertices with non-finite coordinates");
  }
  const MeshTopology topology = AnalyzeTopology(mesh);
  if (topology.boundary_edges > 0) {
    throw std::invalid_argument(
        "the surface is open: " + std::to_string(topology.boundary_edges) +
        " boundary edges (holes), so it does not bound a volume; close the holes (e.g. in "
        "MeshLab or Blender) and export it again");
  }
  if (topology.odd_non_manifold_edges > 0) {
    throw std::invalid_argument(
        "the surface has " + std::to_string(topology.odd_non_manifold_edges) +
        " edges shared by an odd number of triangles (3 or more), so its inside is not well "
        "defined; repair the mesh");
  }
}

// Fills *surface with the mesh and *tree with the surface's faces, built for distance queries.
// CGAL's AABB tree wants a face graph; orient_polygon_soup makes one out of any soup,
// duplicating vertices at non-manifold edges. The inside test is ray parity, which only needs
// every edge used an even number of times (CheckClosedAndFinite), not a manifold.
void BuildTree(const TriangleMesh& mesh, Surface* surface, Tree* tree) {
  std::vector<Point> points;
  points.reserve(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) points.push_back(ToPoint(mesh.vertices.col(v)));
  std::vector<std::vector<std::size_t>> polygons(mesh.num_triangles());
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    polygons[t] = {static_cast<std::size_t>(mesh.triangles(0, t)),
                   static_cast<std::size_t>(mesh.triangles(1, t)),
                   static_cast<std::size_t>(mesh.triangles(2, t))};
  }
  pmp::orient_polygon_soup(points, polygons);
  pmp::polygon_soup_to_polygon_mesh(points, polygons, *surface);
  tree->insert(faces(*surface).first, faces(*surface).second, *surface);
  tree->build();
  tree->accelerate_distance_queries();
}

// Flips, in *oriented (a copy of mesh), every triangle of the mesh whose normal points inside,
// asking the inside test which side it points to: this works where a consistent orientation
// does not exist globally (pieces joined at non-manifold edges), and makes SignedVolume and
// CrossSectionArea exact. `extent` is the largest edge of the mesh's bounding box.
void OrientOutwards(const TriangleMesh& mesh, const SideOf& side_of, double extent,
                    TriangleMesh* oriented) {
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const Eigen::Vector3d a = mesh.vertices.col(mesh.triangles(0, t));
    const Eigen::Vector3d b = mesh.vertices.col(mesh.triangles(1, t));
    const Eigen::Vector3d c = mesh.vertices.col(mesh.triangles(2, t));
    const Eigen::Vector3d normal = (b - a).cross(c - a);
    const double length = normal.norm();
    if (!(length > 0.0)) continue;  // zero area: no contribution either way
    // Probe just off the centroid, closer than any other part of the surface can plausibly be.
    const double offset = 1e-6 * std::min(extent, std::sqrt(length));
    const Eigen::Vector3d probe = (a + b + c) / 3.0 + offset * normal / length;
    if (side_of(ToPoint(probe)) == CGAL::ON_BOUNDED_SIDE) {
      std::swap(oriented->triangles(1, t), oriented->triangles(2, t));
    }
  }
}

}  // namespace

struct SolidMesh::Impl {
  TriangleMesh oriented;
  Surface surface;
  Tree tree;
  std::unique_ptr<SideOf> side_of;
  double volume = 0.0;
  Eigen::Vector3d min_corner;
  Eigen::Vector3d max_corner;
};

SolidMesh::SolidMesh(const TriangleMesh& mesh) : impl_(std::make_unique<Impl>()) {
  CheckClosedAndFinite(mesh);
  Impl& impl = *impl_;
  BuildTree(mesh, &impl.surface, &impl.tree);
  impl.side_of = std::make_unique<SideOf>(impl.tree);

  impl.oriented = mesh;
  BoundingBox(mesh, &impl.min_corner, &impl.max_corner);
  const double extent = (impl.max_corner - impl.min_corner).maxCoeff();
  OrientOutwards(mesh, *impl.side_of, extent, &impl.oriented);
  const double volume = SignedVolume(impl.oriented);
  if (!(volume > 1e-9 * extent * extent * extent)) {
    throw std::invalid_argument("the closed surface encloses no volume (flat or degenerate)");
  }
  impl.volume = volume;
}

SolidMesh::~SolidMesh() = default;
SolidMesh::SolidMesh(SolidMesh&&) noexcept = default;
SolidMesh& SolidMesh::operator=(SolidMesh&&) noexcept = default;

const TriangleMesh& SolidMesh::surface() const { return impl_->oriented; }
double SolidMesh::volume() const { return impl_->volume; }
const Eigen::Vector3d& SolidMesh::min_corner() const { return impl_->min_corner; }
const Eigen::Vector3d& SolidMesh::max_corner() const { return impl_->max_corner; }

bool SolidMesh::Contains(const Eigen::Vector3d& p) const {
  return (*impl_->side_of)(ToPoint(p)) != CGAL::ON_UNBOUNDED_SIDE;
}

bool SolidMesh::BoxTouchesSurface(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const {
  return impl_->tree.do_intersect(CGAL::Bbox_3(lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z()));
}

bool SolidMesh::SegmentCrossesSurface(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
  return impl_->tree.do_intersect(Kernel::Segment_3(ToPoint(a), ToPoint(b)));
}

Eigen::Vector3d SolidMesh::ClosestPoint(const Eigen::Vector3d& p, int* triangle) const {
  const auto [point, face] = impl_->tree.closest_point_and_primitive(ToPoint(p));
  if (triangle != nullptr) *triangle = static_cast<int>(face.idx());
  return Eigen::Vector3d(point.x(), point.y(), point.z());
}

std::vector<int> SolidMesh::TrianglesTouchingBox(const Eigen::Vector3d& lo,
                                                 const Eigen::Vector3d& hi) const {
  std::vector<Primitive::Id> faces_hit;
  impl_->tree.all_intersected_primitives(
      CGAL::Bbox_3(lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z()), std::back_inserter(faces_hit));
  // The surface mesh's faces were added in the order of the triangles.
  std::vector<int> triangles;
  triangles.reserve(faces_hit.size());
  for (const Primitive::Id& face : faces_hit) triangles.push_back(static_cast<int>(face.idx()));
  return triangles;
}

SolidMesh TransformedSolid(const SolidMesh& solid, const Eigen::Matrix3d& rotation,
                           const Eigen::Vector3d& translation) {
  TriangleMesh moved = solid.surface();
  moved.vertices = (rotation * moved.vertices).colwise() + translation;
  return SolidMesh(moved);
}

}  // namespace msm_sim::core
