#pragma once

#include <Eigen/Core>

#include "msm_sim/geometry/solid_mesh.h"

namespace msm_sim::core {

/// Volume (m^3) of the part of the solid inside the axis-aligned box [lo, hi], by exact
/// clipping (docs/physics.md §5 "exact clipping"; anti-aliasing's chi = this / cell volume).
///
/// Divergence theorem with the field (x - lo.x, 0, 0): the volume is the flux through the
/// surface triangles clipped to the box, plus (hi.x - lo.x) times the area of the box's +x face
/// inside the solid; that area is, by Green's theorem in the face, the section's edges clipped
/// to the face plus (hi.y - lo.y) times the length of one face edge inside the solid, found by
/// intersecting it with the surface. The +x face, its +y edge and the edge's ends are moved
/// 1e-9 of the box inwards, so that surfaces lying exactly on the box (a lattice-aligned body)
/// are on a definite side; the result is off by at most that much.
///
/// Precondition: lo < hi componentwise, finite.
double VolumeInsideBox(const SolidMesh& solid, const Eigen::Vector3d& lo,
                       const Eigen::Vector3d& hi);

}  // namespace msm_sim::core
