#include "geometry/box_clipping.h"

#include <algorithm>
#include <array>
#include <vector>

#include <Eigen/Geometry>

namespace msm_sim::core {
namespace {

using Polygon = std::vector<Eigen::Vector3d>;
using Triangle = std::array<Eigen::Vector3d, 3>;

// Sutherland-Hodgman: the part of the polygon with sign * (p[axis] - bound) <= 0.
Polygon ClipAgainst(const Polygon& polygon, int axis, double bound, double sign) {
  Polygon kept;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& p = polygon[i];
    const Eigen::Vector3d& q = polygon[(i + 1) % n];
    const double dp = sign * (p[axis] - bound);
    const double dq = sign * (q[axis] - bound);
    if (dp <= 0.0) kept.push_back(p);
    if ((dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0)) {
      kept.push_back(p + (dp / (dp - dq)) * (q - p));
    }
  }
  return kept;
}

// Liang-Barsky: clips the segment p + t (q - p), t in [0, 1], to lo <= (y, z) <= hi.
bool ClipSegment2d(Eigen::Vector3d* p, Eigen::Vector3d* q, const Eigen::Vector2d& lo,
                   const Eigen::Vector2d& hi) {
  double t0 = 0.0, t1 = 1.0;
  const Eigen::Vector3d d = *q - *p;
  for (int k = 0; k < 2; ++k) {
    const int axis = k + 1;
    for (const double side : {-1.0, 1.0}) {
      // side * (p + t d)[axis] <= side * bound
      const double bound = side < 0 ? lo[k] : hi[k];
      const double num = side * (bound - (*p)[axis]);
      const double den = side * d[axis];
      if (den == 0.0) {
        if (num < 0.0) return false;
      } else if (den > 0.0) {
        t1 = std::min(t1, num / den);
      } else {
        t0 = std::max(t0, num / den);
      }
    }
  }
  if (t0 >= t1) return false;
  const Eigen::Vector3d start = *p;
  *p = start + t0 * d;
  *q = start + t1 * d;
  return true;
}

// Parameter s in (0, 1) where the segment a + s (b - a) crosses triangle (v0, v1, v2), or -1.
double SegmentTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                       const Eigen::Vector3d& v0, const Eigen::Vector3d& v1,
                       const Eigen::Vector3d& v2) {
  const Eigen::Vector3d d = b - a;
  const Eigen::Vector3d e1 = v1 - v0, e2 = v2 - v0;
  const Eigen::Vector3d h = d.cross(e2);
  const double det = e1.dot(h);
  if (det == 0.0) return -1.0;  // parallel: the segment lies off the triangle's plane (moved)
  const Eigen::Vector3d r = a - v0;
  const double u = r.dot(h) / det;
  if (u < 0.0 || u > 1.0) return -1.0;
  const Eigen::Vector3d qv = r.cross(e1);
  const double v = d.dot(qv) / det;
  if (v < 0.0 || u + v > 1.0) return -1.0;
  const double s = e2.dot(qv) / det;
  return (s > 0.0 && s < 1.0) ? s : -1.0;
}

// The corners of triangle t of the mesh.
Triangle TriangleOf(const TriangleMesh& mesh, int t) {
  return {mesh.vertices.col(mesh.triangles(0, t)), mesh.vertices.col(mesh.triangles(1, t)),
          mesh.vertices.col(mesh.triangles(2, t))};
}

// Adds to *flux the integral of (x - lo.x) n_x over the part of the triangle inside the box
// [lo, (x1, hi.y, hi.z)]: the triangle clipped to the box, fanned from its first corner.
void AddClippedFlux(const Triangle& v, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                    double x1, double* flux) {
  Polygon polygon = {v[0], v[1], v[2]};
  for (int axis = 0; axis < 3 && !polygon.empty(); ++axis) {
    polygon = ClipAgainst(polygon, axis, lo[axis], -1.0);
    if (!polygon.empty()) polygon = ClipAgainst(polygon, axis, axis == 0 ? x1 : hi[axis], 1.0);
  }
  for (std::size_t i = 1; i + 1 < polygon.size(); ++i) {
    const Eigen::Vector3d area = 0.5 * (polygon[i] - polygon[0]).cross(polygon[i + 1] - polygon[0]);
    const double centroid_x = (polygon[0].x() + polygon[i].x() + polygon[i + 1].x()) / 3.0;
    *flux += (centroid_x - lo.x()) * area.x();
  }
}

// Adds to *face_area the triangle's share of the area of the face x = x1, lo.y <= y <= y1,
// lo.z <= z <= hi.z inside the solid. The triangle's trace on the plane x = x1, oriented along
// +x cross n (inside on its left seen from +x), clipped to the face; Green: area = sum of
// integral (y - lo.y) dz. Adds nothing if the triangle does not cross the plane in a segment.
void AddFaceTraceArea(const Triangle& v, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                      double x1, double y1, double* face_area) {
  std::array<Eigen::Vector3d, 2> trace;
  int crossings = 0;
  for (int e = 0; e < 3; ++e) {
    const Eigen::Vector3d& p = v[e];
    const Eigen::Vector3d& q = v[(e + 1) % 3];
    const bool p_above = p.x() >= x1, q_above = q.x() >= x1;
    if (p_above == q_above) continue;
    const double s = (x1 - p.x()) / (q.x() - p.x());
    if (crossings < 2) trace[crossings] = p + s * (q - p);
    ++crossings;
  }
  if (crossings != 2) return;
  const Eigen::Vector3d normal = (v[1] - v[0]).cross(v[2] - v[0]);
  Eigen::Vector3d p = trace[0], q = trace[1];
  if ((q - p).dot(Eigen::Vector3d::UnitX().cross(normal)) < 0.0) std::swap(p, q);
  if (!ClipSegment2d(&p, &q, Eigen::Vector2d(lo.y(), lo.z()), Eigen::Vector2d(y1, hi.z()))) {
    return;
  }
  *face_area += (0.5 * (p.y() + q.y()) - lo.y()) * (q.z() - p.z());
}

// Parameters s in (0, 1), ascending and without repeats, where the segment start + s (end -
// start) crosses one of the candidate triangles.
std::vector<double> SortedCrossings(const TriangleMesh& mesh, const std::vector<int>& candidates,
                                    const Eigen::Vector3d& start, const Eigen::Vector3d& end) {
  std::vector<double> crossings;
  for (const int t : candidates) {
    const Triangle v = TriangleOf(mesh, t);
    const double s = SegmentTriangle(start, end, v[0], v[1], v[2]);
    if (s > 0.0) crossings.push_back(s);
  }
  std::sort(crossings.begin(), crossings.end());
  // Through a shared edge or vertex the same crossing is reported by each triangle there.
  crossings.erase(std::unique(crossings.begin(), crossings.end(),
                              [](double a, double b) { return b - a < 1e-12; }),
                  crossings.end());
  return crossings;
}

// Length of the segment [start, end] inside the solid, from where it crosses the surface and
// whether its start is inside. Precondition: the segment runs along +z (start and end differ
// only in z) and every triangle it crosses is among the candidates.
double LengthInside(const SolidMesh& solid, const std::vector<int>& candidates,
                    const Eigen::Vector3d& start, const Eigen::Vector3d& end) {
  bool inside = solid.Contains(start);
  double previous = 0.0, inside_length = 0.0;
  for (const double s : SortedCrossings(solid.surface(), candidates, start, end)) {
    if (inside) inside_length += s - previous;
    inside = !inside;
    previous = s;
  }
  if (inside) inside_length += 1.0 - previous;
  return inside_length * (end.z() - start.z());
}

}  // namespace

double VolumeInsideBox(const SolidMesh& solid, const Eigen::Vector3d& lo,
                       const Eigen::Vector3d& hi) {
  const Eigen::Vector3d size = hi - lo;
  const double shift = 1e-9 * size.minCoeff();
  const std::vector<int> candidates = solid.TrianglesTouchingBox(lo, hi);
  if (candidates.empty()) return solid.Contains(0.5 * (lo + hi)) ? size.prod() : 0.0;
  const TriangleMesh& mesh = solid.surface();
  const double x1 = hi.x() - shift;  // the +x face, moved inwards
  const double y1 = hi.y() - shift;  // its +y edge, moved inwards

  double flux = 0.0;       // integral of (x - lo.x) n_x over the surface inside the box
  double face_area = 0.0;  // area of the +x face inside the solid
  for (const int t : candidates) {
    const Triangle v = TriangleOf(mesh, t);
    AddClippedFlux(v, lo, hi, x1, &flux);
    AddFaceTraceArea(v, lo, hi, x1, y1, &face_area);
  }

  // The face's +y edge, along z, with its ends moved inwards.
  const Eigen::Vector3d start(x1, y1, lo.z() + shift);
  const Eigen::Vector3d end(x1, y1, hi.z() - shift);
  face_area += (y1 - lo.y()) * LengthInside(solid, candidates, start, end);
  return flux + (x1 - lo.x()) * face_area;
}

}  // namespace msm_sim::core
