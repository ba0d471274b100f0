#pragma once

#include <string>

#include <Eigen/Core>

#include "msm_sim/geometry/solid_mesh.h"

namespace msm_sim::core {

/// A body's shape as a configuration names it: a primitive centred on the origin, or a closed
/// mesh file in its own frame. Only the fields of `kind` are read.
struct BodyShape {
  enum class Kind { kBox, kSphere, kCylinder, kMesh };
  Kind kind = Kind::kBox;
  Eigen::Vector3d size = Eigen::Vector3d::Constant(0.1);  ///< kBox: edge lengths (m), each > 0
  double radius = 0.05;                                   ///< kSphere, kCylinder: radius (m), > 0
  double length = 0.1;                                    ///< kCylinder: length along z (m), > 0
  std::string mesh_path;    ///< kMesh: a closed triangle mesh file (any format assimp reads)
  double mesh_scale = 1.0;  ///< kMesh: file units times this are metres, > 0
};

/// The closed solid the shape bounds: MakeBoxMesh(size), MakeIcosphereMesh(radius, 4) (5120
/// triangles), MakeCylinderMesh(radius, length, 64) or ImportSolidMesh(mesh_path) scaled by
/// mesh_scale. Throws std::invalid_argument for a non-positive dimension and MeshImportError
/// for a mesh file that cannot be read or does not bound a solid.
SolidMesh MakeBodySolid(const BodyShape& shape);

}  // namespace msm_sim::core
