#include "msm_sim/experiments/squeeze_experiment.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_set>

#include "msm_sim/dynamics/border_nodes.h"
#include "msm_sim/dynamics/world.h"
#include "msm_sim/mechanics/orientation_barrier.h"

namespace msm_sim::core {
namespace {

// The plates' thickness along z and their width over the body's widest horizontal extent.
constexpr double kPlateThickness = 0.01;
constexpr double kPlateWidthFactor = 3.0;

void CheckOptions(const SqueezeExperimentOptions& o) {
  const double sum = o.approach + o.speed + o.friction + o.step + o.damping_beta + o.start_gap;
  if (!std::isfinite(sum) || !(o.approach > 0.0) || !(o.speed > 0.0) || !(o.friction >= 0.0) ||
      !(o.step > 0.0) || !(o.damping_beta >= 0.0) || !(o.start_gap >= 0.0) || o.samples < 1) {
    throw std::invalid_argument(
        "squeeze: approach, speed and step must be finite and > 0, friction, damping and start "
        "gap finite and >= 0, samples >= 1");
  }
  if (!(o.orientation_threshold == 0.0 ||
        (o.orientation_threshold > 0.0 && o.orientation_threshold < 1.0))) {
    throw std::invalid_argument("squeeze: the orientation threshold must be 0 or in (0, 1)");
  }
  if (!(o.time_step_safety > 0.0 && o.time_step_safety <= 1.0)) {
    throw std::invalid_argument("squeeze: the time step safety must be in (0, 1]");
  }
}

// The body's surface planes above and below the centroid (SqueezeExperimentOptions): the
// highest collision-sphere top and the lowest bottom within one characteristic length of the
// vertical axis through `axis`; the whole body's extent if no border node is that near.
std::pair<double, double> SurfacePlanes(const Model& model, const BorderNodes& border,
                                        const Eigen::Vector2d& axis) {
  const Eigen::Matrix3Xd& x = model.rest_positions();
  const double near = model.characteristic_length();
  double top = -std::numeric_limits<double>::infinity(), bottom = -top;
  double top_all = top, bottom_all = bottom;
  for (std::size_t k = 0; k < border.nodes.size(); ++k) {
    const Eigen::Vector3d p = x.col(border.nodes[k]);
    const double r = border.radii[k];
    top_all = std::max(top_all, p.z() + r);
    bottom_all = std::min(bottom_all, p.z() - r);
    if ((p.head<2>() - axis).squaredNorm() > near * near) continue;
    top = std::max(top, p.z() + r);
    bottom = std::min(bottom, p.z() - r);
  }
  if (!std::isfinite(top - bottom)) return {bottom_all, top_all};
  return {bottom, top};
}

Collider Plate(const std::string& name, double width, const Eigen::Vector2d& axis, double face,
               double side, double speed) {
  Collider plate;
  plate.name = name;
  plate.shape = ColliderShape::Box(Eigen::Vector3d(width, width, kPlateThickness));
  plate.pose.translation() << axis.x(), axis.y(), face + side * 0.5 * kPlateThickness;
  plate.linear_velocity = Eigen::Vector3d(0.0, 0.0, -side * speed);
  return plate;
}

class Squeeze {
 public:
  Squeeze(std::shared_ptr<const Model> model, const SqueezeExperimentOptions& options)
      : options_(options), world_(Options(options)) {
    BodyOptions body_options;
    body_options.damping_beta = options.damping_beta;
    body_options.friction = options.friction;
    body_options.orientation_threshold = options.orientation_threshold;
    body_ = world_.AddBody("object", model, body_options);
    const Eigen::Matrix3Xd& x = model->rest_positions();
    axis_ = (x * model->masses() / model->masses().sum()).head<2>();
    const auto [bottom, top] = SurfacePlanes(*model, world_.border(body_), axis_);
    result_.height = top - bottom;
    result_.nodes = model->num_nodes();
    if (!(options.approach < result_.height)) {
      throw std::invalid_argument("squeeze: an approach of " + std::to_string(options.approach) +
                                  " m makes the plates meet: the body is " +
                                  std::to_string(result_.height) + " m high between them");
    }
    const Eigen::Vector3d extent = x.rowwise().maxCoeff() - x.rowwise().minCoeff();
    const double width = kPlateWidthFactor * extent.head<2>().maxCoeff();
    const double speed = options.speed;
    top_ = world_.AddCollider(Plate("top_plate", width, axis_, top + options.start_gap, 1, speed));
    bottom_ = world_.AddCollider(
        Plate("bottom_plate", width, axis_, bottom - options.start_gap, -1, speed));
    world_.SetPairFriction(body_, top_, options.friction);
    world_.SetPairFriction(body_, bottom_, options.friction);
    top_start_ = top + options.start_gap;
    bottom_start_ = bottom - options.start_gap;
    barrier_ = std::make_unique<OrientationBarrier>(*model, 0.0, 0.5);
  }

  SqueezeExperimentResult Run() {
    const int steps_per_row =
        std::max(1, static_cast<int>(std::lround(options_.approach / options_.samples /
                                                 (2.0 * options_.speed * options_.step))));
    SqueezeSample row;
    int in_row = 0;
    double approach = -2.0 * options_.start_gap;
    while (approach < options_.approach * (1.0 - 1e-9)) {
      StepOnce();
      approach = Approach();
      if (approach <= 0.0) continue;  // not yet at the surface planes
      Accumulate(approach, &row);
      if (++in_row < steps_per_row && approach < options_.approach * (1.0 - 1e-9)) continue;
      row.approach /= in_row;
      row.force /= in_row;
      row.contact_radius /= in_row;
      row.contact_area /= in_row;
      result_.profile.push_back(row);
      row = SqueezeSample{};
      in_row = 0;
      if (Folded()) break;
    }
    result_.seconds_simulated = world_.time();
    return result_;
  }

 private:
  static WorldOptions Options(const SqueezeExperimentOptions& options) {
    WorldOptions world;
    world.gravity.setZero();
    world.integrator = options.integrator;
    world.implicit_max_substep = options.step;
    world.record_contact_points = true;
    world.time_step_safety = options.time_step_safety;
    return world;
  }

  void StepOnce() {
    const StepReport report = world_.Step(options_.step);
    if (!report.accepted) throw std::runtime_error("squeeze: " + report.reason);
  }

  // The plates' total travel past the surface planes.
  double Approach() const {
    const double top = world_.collider(top_).pose.translation().z() - 0.5 * kPlateThickness;
    const double bottom = world_.collider(bottom_).pose.translation().z() + 0.5 * kPlateThickness;
    return (top_start_ - top) + (bottom - bottom_start_) - 2.0 * options_.start_gap;
  }

  // Adds this step's approach, mean plate force and top-plate patch to the row's sums.
  void Accumulate(double approach, SqueezeSample* row) const {
    const auto& wrenches = world_.wrenches(body_);
    row->approach += approach;
    row->force += 0.5 * (wrenches[top_].force.z() - wrenches[bottom_].force.z());
    std::unordered_set<NodeIndex> touching;
    for (const ContactPoint& point : world_.contact_points(body_)) {
      if (point.collider == top_ && point.normal_impulse > 0.0) touching.insert(point.node);
    }
    const Eigen::Matrix3Xd& x = world_.state(body_).positions;
    double radius = 0.0;
    for (const NodeIndex node : touching) {
      radius = std::max(radius, (x.col(node).head<2>() - axis_).norm());
    }
    const double spacing = world_.model(body_).characteristic_length();
    row->contact_radius += radius;
    row->contact_area += static_cast<double>(touching.size()) * spacing * spacing;
  }

  // Whether a lattice corner has turned inside out; records it in the result.
  bool Folded() {
    if (barrier_->num_corners() == 0) return false;
    const Eigen::VectorXd ratios = barrier_->VolumeRatios(world_.state(body_).positions);
    const int folded = static_cast<int>((ratios.array() <= 0.0).count());
    if (folded == 0) return false;
    result_.folded_corners = folded;
    result_.folded_at = result_.profile.back().approach;
    return true;
  }

  SqueezeExperimentOptions options_;
  World world_;
  int body_ = 0;
  int top_ = 0;
  int bottom_ = 0;
  Eigen::Vector2d axis_ = Eigen::Vector2d::Zero();
  double top_start_ = 0.0;
  double bottom_start_ = 0.0;
  std::unique_ptr<OrientationBarrier> barrier_;  // only to measure the corners' J
  SqueezeExperimentResult result_;
};

}  // namespace

SqueezeExperimentResult RunSqueezeExperiment(std::shared_ptr<const Model> model,
                                             const SqueezeExperimentOptions& options) {
  CheckOptions(options);
  Squeeze squeeze(std::move(model), options);
  return squeeze.Run();
}

}  // namespace msm_sim::core
