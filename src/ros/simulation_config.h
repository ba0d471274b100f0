#pragma once
// The node's configuration (README "msm_sim_node": parameters), read from the parameter server
// into plain structs, each value checked; a bad value is a ConfigError naming the parameter.

#include <cstdint>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <ros/node_handle.h>
#include <xmlrpcpp/XmlRpcValue.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "msm_sim/dynamics/world.h"
#include "msm_sim/lattice/body_recipe.h"
#include "msm_sim/lattice/body_shape.h"
#include "msm_sim/lattice/lattice_options.h"
#include "msm_sim/material/spring_law.h"

namespace msm_sim::ros_interface {

/// A configuration the node cannot run with; what() names the parameter and what is wrong.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Nodes fixed in place: those inside a box or behind a plane, in the world frame at start.
struct ClampConfig {
  std::string name;
  bool is_box = true;
  Eigen::Vector3d min = Eigen::Vector3d::Zero(), max = Eigen::Vector3d::Zero();  ///< box, m
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    ///< half-space: a point of the plane, m
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< the half-space is behind the plane
};

/// The largest Young's modulus (Pa) and density (kg/m^3) the node takes, from a scene or
/// ~set_material (the ranges of cfg/ObjectMaterial.cfg): larger finite values overflowed the
/// clamps' reactions to Inf (README "Bad input").
inline constexpr double kMaxYoungs = 1e10;
inline constexpr double kMaxDensity = 1e5;

/// Empty if the material is one the node takes (E in (0, kMaxYoungs], nu in (-1, 0.5), density in
/// (0, kMaxDensity], all finite); else why not, naming the quantity.
std::string MaterialProblem(double youngs, double poisson, double density);

/// objects[]/self_calibrate when a random object does not give it
/// (docs/design/node-self-calibration.md).
inline constexpr bool kSelfCalibrateDefault = false;

struct ObjectConfig {
  std::string name;
  core::BodyShape shape;  ///< YAML shape: type box | sphere | cylinder | mesh (uri, scale)
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< object frame in the world
  core::LatticeKind model = core::LatticeKind::kCubic;     ///< YAML: cubic | random | baudet
  /// The builders' shared options, handed to the object's BodyRecipe as they are. YAML:
  /// spacing (m; 0 with target_nodes > 0), spring (linear | nonlinear | power) and the power
  /// law's tensile_law {alpha, beta} on the object or its material (spring_law_reader.h); the node
  /// limit and the rotation keep LatticeOptions's defaults.
  core::LatticeOptions lattice;
  int target_nodes = 0;  ///< choose the spacing for about this many nodes
  bool antialias = true;
  /// Cubic models' surface, handed to the BodyRecipe as it is. YAML: free_face_bending
  /// (docs/physics.md §2.1; boxes of whole cells only) and surface_dispersion (docs/physics.md §7:
  /// the share of its eMSM bulk the outer node layer keeps, in (0, 1]) and mass_scaling (§7
  /// "Selective mass scaling": the bound on the mass added to cut cells, in [0, 0.1], default
  /// 0.01). Anchored planes come from
  /// the clamps when the object is built (ObjectRecipe); compensate_surface keeps its default.
  core::NodeCentredSurfaceOptions surface;
  std::uint64_t seed = 1;  ///< random models
  /// Random models: correct k and q by a virtual measurement (docs/physics.md §2.2); the scene's
  /// objects[]/self_calibrate, default kSelfCalibrateDefault. Ignored by other lattices.
  bool self_calibrate = false;
  double youngs = 0.0, poisson = 0.0, density = 0.0;  ///< Pa, -, kg/m^3
  double damping = 0.0;                               ///< s, spring dampers c = damping k
  double friction = 0.5;                              ///< Coulomb coefficient of the surface
  double restitution = 1.0;                           ///< e of its microcollisions
  /// Cubic models: the orientation barrier's threshold, 0 off (core::BodyOptions).
  double orientation_threshold = 0.0;
  std::vector<ClampConfig> clamps;
  std::string visual_mesh_path;  ///< optional finer surface for the markers
  double visual_scale = 1.0;
};

struct WrenchInputConfig {
  std::string topic;     ///< geometry_msgs/WrenchStamped
  std::string object;    ///< applied at the origin of the message's frame
  double radius = 0.02;  ///< m, nodes within it share the wrench
};

struct WorldConfig {
  std::string frame = "world";
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
  bool ground = true;
  double ground_height = 0.0;  ///< m, along z of the world frame
  double ground_friction = 0.5;
  double time_step = 1e-3;     ///< s per simulation step (subdivided when unstable)
  double publish_rate = 30.0;  ///< Hz of markers, contacts, state, tf, diagnostics
  bool real_time = true;       ///< false: as fast as possible
  /// Publish /clock with the simulated time, as gazebo_ros does: the rest of the stack runs with
  /// use_sim_time and follows the simulation whatever its real-time factor. real_time then
  /// only keeps the simulation from running ahead of the wall clock.
  bool publish_clock = false;
  double max_force = 1e4;  ///< N; larger applied forces are dropped as absurd
  /// m: a pose or point farther than this from the world origin (a link's tf, a message's
  /// frame or point, an object's pose, the ground) is refused as absurd (docs/robustness.md).
  double max_distance = 500.0;
  /// Per object, the ~apply_force pushes still acting (duration > 0) at most, and the sum of
  /// their |force| (N) at most: beyond either the oldest are dropped (core::WorldOptions).
  int max_pending_pushes = 100;
  double max_pending_force = 1e4;
  /// Fraction of the explicit stability limit used as substep, (0, 1]: lower is slower but
  /// resolves contacts more finely (docs/physics.md §7).
  double time_step_safety = 0.8;
  /// Explicit: a step that diverges is taken again with up to this many times finer substeps,
  /// kept from then on (core::WorldOptions::max_substep_refinement); a power of 2, 1 = off.
  int max_substep_refinement = 8;
  /// explicit (position Verlet in stable substeps) or implicit (one linearly implicit substep of
  /// up to 1 ms, docs/physics.md §7.1).
  core::Integrator integrator = core::Integrator::kExplicit;
  /// The threads of a body's spring loops and per-node stages (core::WorldOptions::threads).
  int threads = 1;
  /// The spring loops' arithmetic in the dynamics (core::WorldOptions::spring_precision).
  core::SpringPrecision spring_precision = core::SpringPrecision::kSingle;
  /// s, > 0: an overlap (or a collider's way back in) shrinks as exp(-t / this) once below this
  /// times penetration_max_speed (core::WorldOptions, docs/physics.md §7.2).
  double penetration_recovery_time = 0.05;
  /// m/s, >= 0: the fastest a node (or a collider pressed back in) is recovered at; 0: off.
  double penetration_max_speed = 0.1;
};

struct MarkerConfig {
  bool colour_by_strain = true;  ///< colour the surface by its strain
  double strain_range = 0.2;     ///< strain shown at full colour
  bool nodes = false;            ///< also the nodes (SPHERE_LIST)
  bool springs = false;          ///< also the springs (LINE_LIST)
};

/// Robot links as colliders (README "Robot in the loop").
struct RobotConfig {
  bool enabled = false;                                 ///< a ~robot section is present
  std::string description_param = "robot_description";  ///< URDF, looked up with searchParam
  std::vector<std::string> links;  ///< empty: every link with collision geometry
  double friction = 0.5;
  std::map<std::string, double> link_friction;  ///< per link, overrides `friction`
  double tf_timeout = 0.25;  ///< s: a link whose tf is older has its contacts off
  /// s, >= 0: the links follow tf this far behind the simulated time, so that they move along
  /// tf's samples (interpolated) instead of waiting at the latest one for the next; at least
  /// the period of the joint states plus one publication period.
  double tf_delay = 0.1;
  /// m/s: a link's tf pose that would move it faster than this is refused, as a pose beyond
  /// world/max_distance is: its contacts turn off until tf is sane again.
  double max_link_speed = 10.0;
};

struct SimulationConfig {
  WorldConfig world;
  std::vector<ObjectConfig> objects;
  std::vector<WrenchInputConfig> wrench_inputs;
  MarkerConfig markers;
  RobotConfig robot;
};

/// The names no object, clamp or robot collider may take: the world frame and "ground".
std::set<std::string> ReservedNames(const WorldConfig& world);

/// Reads ~world, ~objects, ~wrench_inputs and ~markers (and ~materials for objects that name a
/// material) from the private namespace. Mesh URIs (package://, file://, plain paths) are
/// resolved to paths. Throws ConfigError.
SimulationConfig LoadSimulationConfig(const ros::NodeHandle& private_handle);

/// The same from a parameter tree (a dictionary with the keys world, objects, ...), e.g. a YAML
/// file read by msm_replay.
SimulationConfig LoadSimulationConfig(XmlRpc::XmlRpcValue root);

/// Resolves package://pkg/path, file:///path or a plain path; throws ConfigError naming
/// `parameter` for an unknown package.
std::string ResolveUri(const std::string& uri, const std::string& parameter);

}  // namespace msm_sim::ros_interface
