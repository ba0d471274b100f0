// A World body: built at rest from its model, its stable step, its kinematic groups' frames.
#include "dynamics/world_body.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "msm_sim/mechanics/stable_time_step.h"

namespace msm_sim::core::internal {
namespace {

// Nodes of one body collide only if they were at least this many longest springs apart at rest.
constexpr double kSelfContactRestDistance = 2.5;

}  // namespace

Body::Body(const std::string& body_name, std::shared_ptr<const Model> body_model,
           const BodyOptions& body_options, const WorldOptions& world_options)
    : name(body_name),
      model(std::move(body_model)),
      options(body_options),
      state(State::AtRest(*model)),
      evaluator(*model, SpringKernels::kAuto, world_options.threads),
      border(FindBorderNodes(*model)),
      constrained(model->num_nodes(), 0),
      inverse_masses(model->masses().cwiseInverse()),
      forces(Eigen::Matrix3Xd::Zero(3, model->num_nodes())) {
  const double longest = model->num_springs() > 0
                             ? *std::max_element(model->spring_rest_length().begin(),
                                                 model->spring_rest_length().end())
                             : model->characteristic_length();
  self_contact_rest_distance_sq = std::pow(kSelfContactRestDistance * longest, 2);
  evaluator.set_precision(world_options.spring_precision);
  if (body_options.orientation_threshold > 0.0) {
    const double modulus = body_options.orientation_modulus > 0.0
                               ? body_options.orientation_modulus
                               : model->material().youngs_modulus();
    evaluator.set_orientation_barrier(std::make_shared<const OrientationBarrier>(
        *model, modulus, body_options.orientation_threshold));
  }
  UpdateStableStep(world_options);
}

void Body::UpdateStableStep(const WorldOptions& world_options) {
  StableTimeStepOptions step;
  step.damping_beta = options.damping_beta;
  step.safety = world_options.time_step_safety;
  step.fixed_nodes = ConstrainedNodes();
  stable_step = StableTimeStep(*model, step);
}

std::vector<NodeIndex> Body::ConstrainedNodes() const {
  std::vector<NodeIndex> nodes;
  for (NodeIndex node = 0; node < static_cast<NodeIndex>(constrained.size()); ++node) {
    if (constrained[node]) nodes.push_back(node);
  }
  return nodes;
}

void ImpulseSum::Merge(const ImpulseSum& other) {
  impulse += other.impulse;
  moment += other.moment;
  weighted_point += other.weighted_point;
  weight += other.weight;
  count += other.count;
  normal_impulses += other.normal_impulses;
  normal_impulse += other.normal_impulse;
  area_time += other.area_time;
}

Eigen::Isometry3d GroupPose(const Group& group, double t) {
  return group.spec.pose ? group.spec.pose(t) : group.initial_pose;
}

std::vector<Eigen::Isometry3d> GroupPoses(const Body& body, double t) {
  std::vector<Eigen::Isometry3d> poses;
  poses.reserve(body.groups.size());
  for (const Group& group : body.groups) poses.push_back(GroupPose(group, t));
  return poses;
}

int AddPush(Push push, const WorldOptions& options, std::vector<Push>* pushes) {
  double force_sum = push.force_sum;
  for (const Push& pending : *pushes) force_sum += pending.force_sum;
  std::size_t dropped = 0;
  while (dropped < pushes->size() &&
         (pushes->size() - dropped + 1 > static_cast<std::size_t>(options.max_pending_pushes) ||
          force_sum > options.max_pending_force)) {
    force_sum -= (*pushes)[dropped].force_sum;
    ++dropped;
  }
  pushes->erase(pushes->begin(), pushes->begin() + static_cast<std::ptrdiff_t>(dropped));
  pushes->push_back(std::move(push));
  return static_cast<int>(dropped);
}

void PlaceGroupNodes(Body* body, const std::vector<Eigen::Isometry3d>& poses, int begin, int end) {
  for (std::size_t g = 0; g < body->groups.size(); ++g) {
    const Group& group = body->groups[g];
    for (std::size_t k = 0; k < group.spec.nodes.size(); ++k) {
      const NodeIndex node = group.spec.nodes[k];
      if (node >= begin && node < end) {
        body->state.positions.col(node) = poses[g] * Eigen::Vector3d(group.local.col(k));
      }
    }
  }
}

void PlaceGroups(Body* body, double t) {
  PlaceGroupNodes(body, GroupPoses(*body, t), 0, body->model->num_nodes());
}

}  // namespace msm_sim::core::internal
