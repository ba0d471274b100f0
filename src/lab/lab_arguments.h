#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "msm_sim/dynamics/integrator.h"
#include "msm_sim/dynamics/world_options.h"

namespace msm_sim::lab {

/// Which model the lab builds, as given on the command line (SI units).
struct ModelArguments {
  std::string model = "cubic";  ///< cubic | random | baudet
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  double spacing = 0.0;
  double youngs = 0.0;
  double poisson = 0.25;
  double density = 1000.0;
  std::string construction = "node";         ///< node | corner (cubic only)
  std::optional<Eigen::Vector4d> rotate;     ///< axis x, y, z and angle in degrees (cubic only)
  std::uint64_t seed = 1;                    ///< random only
  double min_dist = 0.8;                     ///< random only, multiple of l
  double max_dist = 1.9;                     ///< random only, multiple of l
  std::string stiffness = "inverse-square";  ///< random only: uniform | inverse-square
  bool self_calibrate = false;               ///< random only: docs/physics.md §2.2
  std::string spring = "linear";             ///< linear | nonlinear | power
  /// --spring power: the law's alpha and beta (docs/physics.md §4.1), both required then.
  std::optional<double> alpha, beta;
  std::string mesh;                 ///< closed mesh file filling the body instead of the --size box
  double scale = 1.0;               ///< mesh coordinates times this are metres
  bool antialias = true;            ///< mesh + cubic: docs/physics.md §5 anti-aliasing
  bool free_face_bending = false;   ///< node-centred cubic: docs/physics.md §2.1
  double surface_dispersion = 1.0;  ///< node-centred cubic: docs/physics.md §7, in (0, 1]
  int target_nodes = 0;             ///< > 0: choose the spacing for about this many nodes
  /// node-centred cubic: the bound on the mass added to cut cells, a fraction of the body's, in
  /// [0, 0.1] (docs/physics.md §7 "Selective mass scaling"); 0: off
  double mass_scaling = 0.01;
};

enum class LabCommand {
  kCompression,
  kDeflection,
  kPoissonSweep,
  kBuild,
  kSlide,
  kRealtime,
  kIndent,
  kFit,
  kGrip,
  kGrasp,
  kMaterial,
  kSqueeze
};

/// `msm_lab slide`: a box of nodes sliding to a stop on the ground (thesis 6.4).
struct SlideArguments {
  Eigen::Vector3i nodes = Eigen::Vector3i::Zero();  ///< NX NY NZ, each >= 2
  Eigen::Vector3d size = Eigen::Vector3d::Zero();   ///< m
  double mass = 0.0;                                ///< kg
  double v0 = 0.0;                                  ///< m/s along +x
  double mu = 0.0;                                  ///< Coulomb coefficient with the ground
  double youngs = 1e5;                              ///< Pa
  double poisson = 0.25;
};

/// `msm_lab realtime` and `msm_lab indent`: a rigid sphere pressed into the top of a block.
struct ContactArguments {
  double sphere_radius = 0.01;  ///< m (the demo robot's fingertip)
  double damping = 1e-4;        ///< s, spring dampers c = beta k
  double seconds = 0.5;         ///< realtime: simulated time, s
  double depth = 0.0;           ///< indent: indentation past first contact, m
  double speed = 0.005;         ///< indent: the sphere's speed, m/s
  double friction = 0.5;        ///< indent: Coulomb coefficient between sphere and block
  /// indent: > 0, also start the sphere this far inside the block and hold it (m)
  double start_depth = 0.0;
  std::string integrator = "explicit";  ///< explicit | implicit (WorldOptions::integrator)
  int threads = 1;                      ///< realtime: WorldOptions::threads
  double time_step_safety = 0.8;        ///< realtime: WorldOptions::time_step_safety, (0, 1]
  std::string precision = "single";     ///< single | double (WorldOptions::spring_precision)
};

/// `msm_lab fit`: the Young's modulus that reproduces a measured indentation curve.
struct FitArguments {
  std::string curve;                     ///< CSV of depth_m,force_N rows
  std::string yaml;                      ///< write the fitted material here, empty for none
  std::string name = "fitted_material";  ///< the material's name in the YAML entry
  /// --fit-poisson: nu too, from a second curve on a block of another thickness.
  bool fit_poisson = false;
  std::string second_curve;                               ///< its CSV
  Eigen::Vector3d second_size = Eigen::Vector3d::Zero();  ///< its block (m)
  /// --tensile: E and the spring law from a uniaxial tensile curve instead (lab_fit_tensile.cpp).
  std::string tensile;        ///< its CSV, empty for an indentation fit
  std::string strain_column;  ///< a name, or a whole number: a 0-based index; empty: default
  std::string stress_column;
  std::string stress_unit;  ///< Pa | kPa | MPa; empty: from the stress column's name
  double max_strain = 1.0;  ///< fit the curve up to this engineering strain
};

/// `msm_lab grip`: a block squeezed between two rigid jaws and lifted
/// (core::RunGripExperiment; its defaults).
struct GripArguments {
  double ratio = 1.3;                   ///< 2 mu F_n / (m g) the friction is chosen for
  double squeeze = 2e-4;                ///< m, each jaw's travel into the block
  double damping = 1e-3;                ///< s, spring dampers c = beta k
  double lift_time = 2.0;               ///< s
  std::string integrator = "explicit";  ///< explicit | implicit (WorldOptions::integrator)
};

/// `msm_lab grasp`: a parallel gripper closes on an object, holds and lifts it
/// (core::RunGraspExperiment; its defaults).
struct GraspArguments {
  std::string shape = "box";           ///< box | sphere | cylinder | ellipsoid | mesh
  double radius = 0.0;                 ///< m, sphere and cylinder
  double length = 0.0;                 ///< m, cylinder (its axis along y, across the pads)
  double friction = 0.8;               ///< mu between the object and the pads (and the ground)
  double force_ratio = 1.5;            ///< Q = 2 mu F_n / (m g)
  double lift = 0.05;                  ///< m
  double lift_time = 1.0;              ///< s
  double damping = 1e-3;               ///< s, spring dampers c = beta k
  double orientation_threshold = 0.2;  ///< 0 (off) or in (0, 1): core::BodyOptions
  /// implicit | explicit: implicit by default, the faster of the two on grasp-sized rubber
  /// objects (docs/design/mass-scaling.md, docs/validation.md "Grasp scene").
  std::string integrator = "implicit";
};

/// `msm_lab squeeze`: an object between two rigid flat plates closing on it
/// (core::RunSqueezeExperiment; its defaults). The object is GraspArguments' shape, radius and
/// length.
struct SqueezeArguments {
  double approach = 0.0;                ///< m, both plates together
  double speed = 0.005;                 ///< m/s, each plate
  double friction = 0.0;                ///< Coulomb coefficient with the plates
  double damping = 1e-4;                ///< s, spring dampers c = beta k
  double orientation_threshold = 0.5;   ///< 0 (off) or in (0, 1): core::BodyOptions
  int samples = 30;                     ///< rows of the profile
  std::string integrator = "explicit";  ///< explicit | implicit
  double time_step_safety = 0.8;        ///< WorldOptions::time_step_safety, (0, 1]
};

/// `msm_lab material`: Young's modulus from a datasheet's Shore hardness (exactly one of them).
struct HardnessArguments {
  double shore_a = 0.0;
  double shore_00 = 0.0;
  bool from_shore_00 = false;  ///< --shore-00 was given (else --shore-a)
  double poisson = 0.0;
  bool has_poisson = false;  ///< --poisson was given: also print the shear modulus
};

struct LabArguments {
  LabCommand command = LabCommand::kCompression;
  ModelArguments model;
  double strain = 0.01;  ///< compression and poisson-sweep
  double force = 0.0;    ///< deflection only, N
  /// deflection: "faces" (clamp the face x = 0 by anchors, load the face x = L), "layers" (the
  /// thesis' frozen and loaded node layers) or "" (faces for an unrotated node-centred cubic
  /// lattice, the only one anchors are built for; layers otherwise)
  std::string ends;
  std::string reference;  ///< deflection: "calculix" adds a finite-element reference, "" none
  /// deflection --reference: its mesh NX NY NZ; zero: chosen from the size (lab_reference.h)
  Eigen::Vector3i reference_elements = Eigen::Vector3i::Zero();
  std::vector<double> targets = {-0.9, -0.5, 0.0, 0.25, 0.33, 0.45, 0.49};  ///< poisson-sweep
  std::string plot;  ///< poisson-sweep, indent and fit --tensile: PNG to write, empty for none
  std::string out;   ///< build: model file to write, empty for none
  std::string vtk;   ///< build: .vtu file to write, empty for none
  SlideArguments slide;
  ContactArguments contact;
  FitArguments fit;
  GripArguments grip;
  GraspArguments grasp;
  SqueezeArguments squeeze;
  HardnessArguments hardness;
  bool json = false;
};

/// Outcome of parsing: either arguments to run, or a message and exit code (help: 0, error: 2).
struct ParseOutcome {
  std::optional<LabArguments> arguments;
  std::string message;
  int exit_code = 0;
};

/// Parses `msm_lab <command> [options]`. Never throws and never exits the process.
ParseOutcome ParseLabArguments(const std::vector<std::string>& argv);

}  // namespace msm_sim::lab
