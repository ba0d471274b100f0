#include "msm_sim/lattice/body_shape.h"

#include "msm_sim/geometry/mesh_import.h"
#include "msm_sim/geometry/mesh_primitives.h"

namespace msm_sim::core {

SolidMesh MakeBodySolid(const BodyShape& shape) {
  switch (shape.kind) {
    case BodyShape::Kind::kBox:
      return SolidMesh(MakeBoxMesh(shape.size));
    case BodyShape::Kind::kSphere:
      return SolidMesh(MakeIcosphereMesh(shape.radius, 4));
    case BodyShape::Kind::kCylinder:
      return SolidMesh(MakeCylinderMesh(shape.radius, shape.length, 64));
    case BodyShape::Kind::kMesh:
      break;
  }
  MeshImportOptions options;
  options.scale = shape.mesh_scale;
  return ImportSolidMesh(shape.mesh_path, options);
}

}  // namespace msm_sim::core
