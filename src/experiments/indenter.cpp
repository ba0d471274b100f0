#include "experiments/indenter.h"

#include <cmath>
#include <stdexcept>

namespace msm_sim::core {

Collider SphereIndenter(const Model& model, const BorderNodes& border, double radius, double gap,
                        double speed) {
  const Eigen::Matrix3Xd& x = model.rest_positions();
  const Eigen::Vector2d axis =
      0.5 * (x.topRows<2>().rowwise().minCoeff() + x.topRows<2>().rowwise().maxCoeff());
  const double touch = SphereTouchdownHeight(x, border, axis, radius);
  if (!std::isfinite(touch)) throw std::invalid_argument("no node lies under the sphere");
  Collider sphere;
  sphere.name = "sphere";
  sphere.shape = ColliderShape::Sphere(radius);
  sphere.pose.translation() = Eigen::Vector3d(axis.x(), axis.y(), touch + gap);
  sphere.linear_velocity = Eigen::Vector3d(0.0, 0.0, -speed);
  return sphere;
}

}  // namespace msm_sim::core
