#pragma once
// The ~objects list of the node's configuration (README "msm_sim_node": objects), each object's
// shape, model, material, clamps and visual mesh checked as it is read.

#include <vector>

#include <xmlrpcpp/XmlRpcValue.h>

#include "simulation_config.h"

namespace msm_sim::ros_interface {

/// root["objects"] as ObjectConfigs, materials named by an object looked up in root["materials"]
/// (config/materials.yaml). Throws ConfigError naming the parameter for a missing or empty list,
/// an unknown key, a bad value, a mesh file that cannot be read or a duplicate object name.
std::vector<ObjectConfig> ReadObjects(XmlRpc::XmlRpcValue& root);

}  // namespace msm_sim::ros_interface
