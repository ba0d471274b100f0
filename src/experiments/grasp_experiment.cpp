#include "msm_sim/experiments/grasp_experiment.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "msm_sim/dynamics/border_nodes.h"
#include "msm_sim/dynamics/world.h"

namespace msm_sim::core {
namespace {

// The pads start this far (m) outside the body's collision spheres.
constexpr double kStartGap = 1e-3;
// The squeeze counts as reached when both pads' normal forces are within this fraction of it.
constexpr double kSqueezeTolerance = 0.05;
// The fraction of close_speed a pad closes at once it touches the object.
constexpr double kTouchingSpeed = 0.25;
// The fraction of the estimated position error the force control corrects in one step.
constexpr double kCorrectionGain = 0.2;
// Steps after which a right stiffness estimate has closed all but (1 - kCorrectionGain)^25,
// under 1 %, of a force error.
constexpr int kSettleSteps = 25;

void CheckOptions(const GraspExperimentOptions& o) {
  const double sum = o.friction + o.force_ratio + o.pad_size + o.pad_thickness + o.close_speed +
                     o.close_timeout + o.hold_time + o.lift + o.lift_time + o.final_hold +
                     o.gravity + o.damping_beta + o.step + o.held_rise + o.held_slip;
  if (!std::isfinite(sum) || !(o.friction > 0.0) || !(o.force_ratio > 0.0) || !(o.pad_size > 0.0) ||
      !(o.pad_thickness > 0.0) || !(o.close_speed > 0.0) || !(o.close_timeout > 0.0) ||
      !(o.hold_time >= 0.0) || !(o.lift >= 0.0) || !(o.lift_time > 0.0) || !(o.final_hold >= 0.0) ||
      !(o.gravity > 0.0) || !(o.damping_beta >= 0.0) || !(o.step > 0.0) || !(o.held_rise > 0.0) ||
      !(o.held_slip > 0.0)) {
    throw std::invalid_argument(
        "grasp: friction, force ratio, pad size and thickness, close speed and timeout, lift "
        "time, gravity, step and the held criteria must be finite and > 0; hold times, lift and "
        "damping finite and >= 0");
  }
}

Eigen::AlignedBox3d BoundsOfSpheres(const Eigen::Matrix3Xd& positions, const BorderNodes& border) {
  if (border.nodes.empty()) throw std::invalid_argument("grasp: the model has no border nodes");
  Eigen::AlignedBox3d bounds;
  for (std::size_t k = 0; k < border.nodes.size(); ++k) {
    const Eigen::Vector3d x = positions.col(border.nodes[k]);
    const Eigen::Vector3d radius = Eigen::Vector3d::Constant(border.radii[k]);
    bounds.extend(x - radius);
    bounds.extend(x + radius);
  }
  return bounds;
}

Eigen::Vector3d Centroid(const Eigen::Matrix3Xd& positions, const Eigen::VectorXd& masses) {
  return positions * masses / masses.sum();
}

// A pad: a box `thickness` along the closing axis with a square face of edge `size` (clipped to
// the body's extent across and along z), its face at `face` on that axis, on the side `side`
// (-1: the near pad, facing +axis).
Collider Pad(const std::string& name, const Eigen::AlignedBox3d& body,
             const Eigen::Vector3d& centre, int axis, double face, double side,
             const GraspExperimentOptions& options) {
  const Eigen::Vector3d extent = body.sizes();
  const int across = 1 - axis;
  Eigen::Vector3d size;
  size[axis] = options.pad_thickness;
  size[across] = std::min(options.pad_size, extent[across]);
  size.z() = std::min(options.pad_size, extent.z());
  Collider pad;
  pad.name = name;
  pad.shape = ColliderShape::Box(size);
  pad.pose.translation() = centre;
  pad.pose.translation()[axis] = face + side * 0.5 * options.pad_thickness;
  pad.friction = options.friction;
  return pad;
}

// A pad's force control: side -1 is the left pad (facing +axis). Travel (m) is how far it has
// closed; touch its travel when it first pressed; stiffness (N/m) 0 until the first crossing;
// error (N) the force it lacked at the last step.
struct PadControl {
  int collider = 0;
  double side = 0.0;
  double travel = 0.0;
  double touch = -1.0;
  double stiffness = 0.0;
  double error = 0.0;
  int same_sign_steps = 0;  // consecutive steps whose error kept its sign
};

// One grasp over one World: the stages in order, each stepping the World and keeping the
// figures every stage reports.
class Grasp {
 public:
  Grasp(std::shared_ptr<const Model> model, const GraspExperimentOptions& options)
      : options_(options), world_(Options(options)) {
    BodyOptions body_options;
    body_options.damping_beta = options.damping_beta;
    body_options.friction = options.friction;
    body_options.orientation_threshold = options.orientation_threshold;
    body_ = world_.AddBody("object", model, body_options);
    const Eigen::Matrix3Xd& x = model->rest_positions();
    const BorderNodes& border = world_.border(body_);
    const Eigen::AlignedBox3d bounds = BoundsOfSpheres(x, border);
    const Eigen::Vector3d centre = Centroid(x, model->masses());
    world_.AddCollider(GroundTouching(x, border, options.friction));
    // Across the narrower horizontal extent, as a gripper takes an object.
    axis_ = bounds.sizes().y() < bounds.sizes().x() ? 1 : 0;
    left_ = world_.AddCollider(
        Pad("left_pad", bounds, centre, axis_, bounds.min()[axis_] - kStartGap, -1.0, options));
    right_ = world_.AddCollider(
        Pad("right_pad", bounds, centre, axis_, bounds.max()[axis_] + kStartGap, +1.0, options));
    pads_[0] = {left_, -1.0};
    pads_[1] = {right_, +1.0};
    result_.nodes = model->num_nodes();
    result_.mass = model->masses().sum();
    // docs/physics.md §7: Coulomb friction on both pads carries up to 2 mu F_n.
    result_.target_force =
        options.force_ratio * result_.mass * options.gravity / (2.0 * options.friction);
  }

  GraspExperimentResult Run() {
    const auto start = std::chrono::steady_clock::now();
    Squeeze();
    result_.squeeze_force = Hold(options_.hold_time);
    Lift();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    result_.simulated_time = world_.time();
    result_.real_time_factor = seconds > 0.0 ? world_.time() / seconds : 0.0;
    result_.solver_iterations = steps_taken_ > 0 ? double(solver_iterations_) / steps_taken_ : 0.0;
    result_.held =
        result_.rise >= options_.held_rise * options_.lift && result_.slip <= options_.held_slip;
    return result_;
  }

 private:
  static WorldOptions Options(const GraspExperimentOptions& options) {
    WorldOptions world;
    world.gravity = Eigen::Vector3d(0.0, 0.0, -options.gravity);
    world.integrator = options.integrator;
    world.implicit_max_substep = options.step;
    world.implicit_energy_tolerance = options.implicit_energy_tolerance;
    return world;
  }

  // Each pad's normal force: what the body pushes it outwards with, along the closing axis.
  double PadForce(int pad, double side) const {
    return side * world_.wrenches(body_)[pad].force[axis_];
  }

  // Force control of the squeeze, per pad: close at close_speed until the pad first presses the
  // target force, then correct its position by a fraction of what the force lacks over the
  // contact's stiffness (the secant from first touch to that first crossing, an under-estimate
  // of the tangent for a convex contact). A fixed proportional gain would have to be slow for a
  // flat face's stiff contact or chatter on it. The secant can still be far too soft (a pad that
  // first meets a few nodes reads their impacts), so each overshoot past the tolerance that does
  // not at least halve the force error (its sign changing from one step to the next) doubles the
  // stiffness estimate; an error that keeps its sign for kSettleSteps, long after a right
  // estimate would have closed it, halves it (the doubling can run away on a few nodes' impacts).
  void ControlSqueeze(double vertical_speed) {
    for (PadControl& pad : pads_) {
      const double force = PadForce(pad.collider, pad.side);
      if (force > 0.0 && !(pad.touch >= 0.0)) pad.touch = pad.travel;
      const double error = result_.target_force - force;
      AdaptStiffness(force, error, &pad);
      pad.error = error;
      // Touching, a quarter of the speed: a pad striking the object at full speed reads impacts.
      double closing =
          pad.touch >= 0.0 ? kTouchingSpeed * options_.close_speed : options_.close_speed;
      if (pad.stiffness > 0.0) {
        closing = std::clamp(kCorrectionGain * error / (pad.stiffness * options_.step),
                             -options_.close_speed, options_.close_speed);
      }
      pad.travel += closing * options_.step;
      Eigen::Vector3d velocity(0.0, 0.0, vertical_speed);
      velocity[axis_] = -pad.side * closing;
      world_.collider(pad.collider).linear_velocity = velocity;
    }
  }

  // The stiffness estimate's first secant, doubling and halving (ControlSqueeze).
  void AdaptStiffness(double force, double error, PadControl* pad) const {
    const bool outside = std::abs(error) > kSqueezeTolerance * result_.target_force;
    pad->same_sign_steps = error * pad->error > 0.0 ? pad->same_sign_steps + 1 : 0;
    if (pad->stiffness == 0.0 && force >= result_.target_force) {
      pad->stiffness =
          force / std::max(pad->travel - pad->touch, options_.close_speed * options_.step);
    } else if (pad->stiffness > 0.0 && error * pad->error < 0.0 && outside &&
               std::abs(error) > 0.5 * std::abs(pad->error)) {
      pad->stiffness *= 2.0;
    } else if (pad->stiffness > 0.0 && outside && pad->same_sign_steps >= kSettleSteps) {
      pad->stiffness *= 0.5;
      pad->same_sign_steps = 0;
    }
  }

  void StepOnce() {
    const StepReport report = world_.Step(options_.step);
    if (!report.accepted) throw std::runtime_error("grasp: " + report.reason);
    solver_iterations_ += report.solver_iterations;
    ++steps_taken_;
    const State& state = world_.state(body_);
    result_.max_node_speed =
        std::max(result_.max_node_speed, state.velocities.colwise().norm().maxCoeff());
    const Energies energies = world_.ComputeEnergies(body_);
    result_.energy_max = std::max(result_.energy_max, energies.kinetic + energies.elastic);
  }

  bool SqueezeReached() const {
    const double tolerance = kSqueezeTolerance * result_.target_force;
    return std::abs(PadForce(left_, -1.0) - result_.target_force) <= tolerance &&
           std::abs(PadForce(right_, +1.0) - result_.target_force) <= tolerance;
  }

  void Squeeze() {
    const int most = StepsIn(options_.close_timeout);
    for (int k = 0; k < most && (k == 0 || !SqueezeReached()); ++k) {
      ControlSqueeze(0.0);
      StepOnce();
    }
  }

  // Holds still under force control; returns the pads' mean normal force over the hold.
  double Hold(double seconds) {
    const int steps = StepsIn(seconds);
    double sum = 0.0;
    for (int k = 0; k < steps; ++k) {
      ControlSqueeze(0.0);
      StepOnce();
      sum += 0.5 * (PadForce(left_, -1.0) + PadForce(right_, +1.0));
      TrackSlip();
    }
    return steps > 0 ? sum / steps : 0.5 * (PadForce(left_, -1.0) + PadForce(right_, +1.0));
  }

  // The lift: a quintic rise (zero speed and acceleration at both ends), then the final hold.
  void Lift() {
    pad_start_ = world_.collider(left_).pose.translation().z();
    body_start_ = CentroidZ();
    tracking_ = true;
    const int steps = StepsIn(options_.lift_time);
    for (int k = 0; k < steps; ++k) {
      // The speed at the middle of the step, so that the pads follow the profile's integral.
      const double s = (k + 0.5) / steps;
      const double speed =
          options_.lift / options_.lift_time * 30.0 * s * s * (1.0 - s) * (1.0 - s);
      ControlSqueeze(speed);
      StepOnce();
      TrackSlip();
    }
    Hold(options_.final_hold);
    result_.rise = CentroidZ() - body_start_;
  }

  void TrackSlip() {
    if (!tracking_) return;
    const double pad_rise = world_.collider(left_).pose.translation().z() - pad_start_;
    result_.slip = std::max(result_.slip, pad_rise - (CentroidZ() - body_start_));
  }

  double CentroidZ() const {
    return Centroid(world_.state(body_).positions, world_.model(body_).masses()).z();
  }

  int StepsIn(double seconds) const {
    return std::max(0, static_cast<int>(std::lround(seconds / options_.step)));
  }

  GraspExperimentOptions options_;
  World world_;
  int body_ = 0;
  int axis_ = 0;  // the pads close along x (0) or y (1)
  int left_ = 0;
  int right_ = 0;
  PadControl pads_[2];
  bool tracking_ = false;
  double pad_start_ = 0.0;
  double body_start_ = 0.0;
  GraspExperimentResult result_;
  long solver_iterations_ = 0;  // over every step so far
  long steps_taken_ = 0;
};

}  // namespace

GraspExperimentResult RunGraspExperiment(std::shared_ptr<const Model> model,
                                         const GraspExperimentOptions& options) {
  CheckOptions(options);
  Grasp grasp(std::move(model), options);
  return grasp.Run();
}

}  // namespace msm_sim::core
