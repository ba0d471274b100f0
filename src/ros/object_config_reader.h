#pragma once
// The ~objects list of the node's configuration (README "msm_sim_node": objects), each object's
// shape, model, material, clamps and visual mesh checked as it is read.

#include <vector>

#include <xmlrpcpp/XmlRpcValue.h>

#include "simulation_config.h"

namespace msm_sim::ros_interface {

/// root["objects"] as ObjectConfigs, materials named by an object looked up in root["materials"]
/// (config/materials.yaml). Throws ConfigError naming the parameter for a missing or empty list,
/// an unknown key, a bad value, a mesh file that cannot be read, a duplicate object or clamp
/// name, a name that is no ROS name or is one of ReservedNames(world), or a pose beyond
/// world.max_distance.
std::vector<ObjectConfig> ReadObjects(XmlRpc::XmlRpcValue& root, const WorldConfig& world);

}  // namespace msm_sim::ros_interface
