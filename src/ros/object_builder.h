#pragma once
// Turns an object's configuration into a calibrated model in the world frame, its visual
// surface and its clamps: the configuration becomes a core::BodyRecipe (the core builds the model
// the way it builds every body), placed at the object's pose.

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "msm_sim/geometry/triangle_mesh.h"
#include "msm_sim/material/material.h"
#include "msm_sim/model/model.h"
#include "simulation_config.h"

namespace msm_sim::ros_interface {

struct BuiltObject {
  std::shared_ptr<const core::Model> model;  ///< rest positions in the world frame
  core::TriangleMesh surface;                ///< what the markers show, world frame at rest
  /// Clamp names and the nodes each fixes.
  std::vector<std::pair<std::string, std::vector<core::NodeIndex>>> clamps;
};

/// Builds the object. Throws ConfigError naming the object's parameters for anything that
/// cannot be built (an unreadable or open mesh, a spacing that fits no node, an empty clamp).
BuiltObject BuildObject(const ObjectConfig& config, const std::string& path);

/// The model alone for another material (same nodes: ~set_material recalibrates in place). A
/// random object with self_calibrate reuses `measured` (the current model's
/// Model::self_calibration) when it was measured for the same conditions, so that a new E alone
/// measures nothing (docs/physics.md §2.2).
std::shared_ptr<const core::Model> BuildObjectModel(
    const ObjectConfig& config, const core::Material& material,
    const std::optional<core::SelfCalibration>& measured = std::nullopt);

}  // namespace msm_sim::ros_interface
