#include "runtime_tuning.h"

namespace msm_sim::ros_interface {
namespace {

msm_sim::ObjectMaterialConfig MaterialOf(const ObjectConfig& object) {
  msm_sim::ObjectMaterialConfig config;
  config.youngs = object.youngs;
  config.poisson = object.poisson;
  config.density = object.density;
  config.damping = object.damping;
  config.friction = object.friction;
  return config;
}

bool SameMaterial(const msm_sim::ObjectMaterialConfig& a, const msm_sim::ObjectMaterialConfig& b) {
  return a.youngs == b.youngs && a.poisson == b.poisson && a.density == b.density &&
         a.damping == b.damping && a.friction == b.friction;
}

msm_sim::WorldTuningConfig TuningOf(const WorldConfig& world) {
  msm_sim::WorldTuningConfig config;
  config.publish_rate = world.publish_rate;
  config.real_time = world.real_time;
  return config;
}

}  // namespace

RuntimeTuning::RuntimeTuning(const ros::NodeHandle& private_handle, Simulation* simulation,
                             WorldSetter set_world)
    : simulation_(simulation), set_world_(std::move(set_world)) {
  for (std::size_t i = 0; i < simulation_->num_objects(); ++i) {
    const ObjectConfig& object = simulation_->object_config(i);
    auto server = std::make_unique<ObjectServer>(
        mutex_, ros::NodeHandle(private_handle, "reconfigure/objects/" + object.name));
    // The live values replace whatever an earlier run left on the parameter server; the first
    // callback (from setCallback) then sees no change.
    server->updateConfig(MaterialOf(object));
    server->setCallback(
        [this, i](msm_sim::ObjectMaterialConfig& config, uint32_t) { OnObject(i, config); });
    object_servers_.push_back(std::move(server));
  }
  world_server_ =
      std::make_unique<WorldServer>(mutex_, ros::NodeHandle(private_handle, "reconfigure/world"));
  world_server_->updateConfig(TuningOf(simulation_->config().world));
  world_server_->setCallback(
      [this](msm_sim::WorldTuningConfig& config, uint32_t) { OnWorld(config); });
}

void RuntimeTuning::OnObject(std::size_t index, msm_sim::ObjectMaterialConfig& config) {
  const ObjectConfig object = simulation_->object_config(index);
  const msm_sim::ObjectMaterialConfig current = MaterialOf(object);
  if (SameMaterial(config, current)) return;
  std::string described;
  const std::string problem =
      simulation_->SetMaterial(object.name, config.youngs, config.poisson, config.density,
                               config.damping, config.friction, &described);
  if (problem.empty()) {
    ROS_INFO("msm_sim: '%s' recalibrated: %s", object.name.c_str(), described.c_str());
    return;
  }
  ROS_WARN("msm_sim: ~reconfigure/objects/%s refused: %s; the material is unchanged",
           object.name.c_str(), problem.c_str());
  config = current;
}

void RuntimeTuning::OnWorld(msm_sim::WorldTuningConfig& config) {
  const msm_sim::WorldTuningConfig current = TuningOf(simulation_->config().world);
  if (config.publish_rate == current.publish_rate && config.real_time == current.real_time) {
    return;
  }
  const std::string problem = set_world_(config.publish_rate, config.real_time);
  if (problem.empty()) return;
  ROS_WARN("msm_sim: ~reconfigure/world refused: %s; unchanged", problem.c_str());
  config = current;
}

}  // namespace msm_sim::ros_interface
