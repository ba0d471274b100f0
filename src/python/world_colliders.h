#pragma once
// The World's colliders, wrenches and contact points in Python (world_colliders.cpp).

#include <pybind11/pybind11.h>

#include "msm_sim/dynamics/world.h"

namespace msm_sim::python {

/// Throws std::invalid_argument (ValueError) unless `body` is one of the world's bodies.
void CheckBody(const core::World& world, int body);

/// add_collider, set_collider_pose, set_collider_twist, wrenches, contact_points, apply_force,
/// add_clamp.
void BindColliders(pybind11::class_<core::World>& world);

}  // namespace msm_sim::python
