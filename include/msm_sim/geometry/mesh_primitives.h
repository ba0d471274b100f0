#pragma once

#include "msm_sim/geometry/triangle_mesh.h"

namespace msm_sim::core {

// Closed, outward-oriented triangle meshes of simple solids, centred at the origin. They are the
// primitives a configuration can name instead of a mesh file, and the shapes tests build from.

/// A box of edge lengths `size` (m, each > 0), 12 triangles.
TriangleMesh MakeBoxMesh(const Eigen::Vector3d& size);

/// A sphere of `radius` (m, > 0): an icosahedron subdivided `subdivisions` times (0..7) with its
/// vertices on the sphere, 20 * 4^subdivisions triangles.
TriangleMesh MakeIcosphereMesh(double radius, int subdivisions);

/// A cylinder of `radius` and `height` (m, > 0) along z with `segments` (>= 3) sides.
TriangleMesh MakeCylinderMesh(double radius, double height, int segments);

/// A torus about z with tube centre radius `major` and tube radius `minor` (0 < minor < major),
/// `major_segments` x `minor_segments` quads split into triangles (each >= 3).
TriangleMesh MakeTorusMesh(double major, double minor, int major_segments, int minor_segments);

}  // namespace msm_sim::core
