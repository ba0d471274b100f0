#include "object_config_reader.h"

#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

#include "msm_sim/io/regular_file.h"
#include "msm_sim/material/shore_hardness.h"
#include "parameter_tree.h"
#include "spring_law_reader.h"

namespace msm_sim::ros_interface {
namespace {

using XmlRpc::XmlRpcValue;

using param::Fail;
using param::FailNotOneOf;
using param::Flag;
using param::Get;
using param::Has;
using param::KnownKeys;
using param::NonNegative;
using param::Number;
using param::OneOf;
using param::Positive;
using param::Text;
using param::Vector;

// The keys an object and its shape take (README "msm_sim_node").
const std::set<std::string> kObjectKeys = {"name",
                                           "shape",
                                           "pose",
                                           "model",
                                           "spacing",
                                           "target_nodes",
                                           "spring",
                                           "tensile_law",
                                           "antialias",
                                           "free_face_bending",
                                           "surface_dispersion",
                                           "mass_scaling",
                                           "seed",
                                           "self_calibrate",
                                           "material",
                                           "youngs",
                                           "poisson",
                                           "density",
                                           "damping",
                                           "friction",
                                           "restitution",
                                           "clamps",
                                           "visual_mesh",
                                           "visual_scale",
                                           "shore_a",
                                           "shore_00",
                                           "orientation_threshold"};
const std::set<std::string> kShapeKeys = {"type", "size", "radius", "length", "uri", "scale"};
// A random model's seed is read as a double: whole numbers above 2^53 are not all representable.
constexpr double kMaxSeed = 9007199254740992.0;

// A missing mesh file is the configuration's error, reported before any object is built; the
// file is never opened here, so a FIFO cannot hang start-up.
void RequireReadable(const std::string& file, const std::string& parameter) {
  const std::string problem = core::RegularFileProblem(file);
  if (!problem.empty()) Fail(parameter, "cannot read the file '" + file + "': " + problem);
}

// shore_a or shore_00 instead of youngs: E by the core's conversion (docs/materials.md). At most
// one of the three; a reading outside the conversion's range fails naming it and the range.
void ReadHardness(XmlRpcValue& object, const std::string& path, ObjectConfig* config) {
  const bool has_a = Has(object, "shore_a"), has_00 = Has(object, "shore_00");
  if (!has_a && !has_00) return;
  const std::string key = has_a ? "shore_a" : "shore_00";
  if ((has_a && has_00) || Has(object, "youngs")) {
    Fail(path + "/" + key, "object '" + config->name +
                               "': give one of youngs (Pa), shore_a and shore_00, not several");
  }
  const double reading = Number(object, key, 0.0, path);
  try {
    config->youngs =
        has_a ? core::YoungsFromShoreA(reading).youngs : core::YoungsFromShore00(reading).youngs;
  } catch (const std::out_of_range& error) {
    Fail(path + "/" + key,
         "object '" + config->name + "': " + error.what() + "; give youngs (Pa) instead");
  }
}

// The ~materials entry the object's `material` names (none without the key).
NamedMaterial FindMaterial(XmlRpcValue& object, XmlRpcValue* materials, const std::string& path) {
  if (!Has(object, "material")) return {};
  const std::string name = Text(object, "material", "", path);
  if (materials == nullptr || !Has(*materials, name)) {
    Fail(path + "/material", "unknown material '" + name +
                                 "' (load config/materials.yaml into ~materials, or give "
                                 "youngs, poisson and density)");
  }
  return {&(*materials)[name], "~materials/" + name};
}

void ReadMaterial(XmlRpcValue& object, const NamedMaterial& material, const std::string& path,
                  ObjectConfig* config) {
  config->poisson = 0.25;
  if (material.entry != nullptr) {
    config->youngs = Positive(*material.entry, "youngs", 0.0, material.path);
    config->poisson = Number(*material.entry, "poisson", 0.25, material.path);
    config->density = Positive(*material.entry, "density", 0.0, material.path);
  }
  // Explicit values override the named material.
  if (Has(object, "youngs")) config->youngs = Positive(object, "youngs", 0.0, path);
  ReadHardness(object, path, config);
  if (Has(object, "poisson")) config->poisson = Number(object, "poisson", 0.25, path);
  if (Has(object, "density")) config->density = Positive(object, "density", 0.0, path);
  if (!(config->youngs > 0.0)) {
    Fail(path + "/youngs", "missing (or give material, shore_a or shore_00)");
  }
  if (!(config->density > 0.0)) Fail(path + "/density", "missing (or give material)");
  if (!(config->poisson > -1.0 && config->poisson < 0.5)) {
    Fail(path + "/poisson", "must lie in (-1, 0.5), got " + std::to_string(config->poisson));
  }
  if (config->youngs > kMaxYoungs) Fail(path + "/youngs", MaterialProblem(config->youngs, 0, 1));
  if (config->density > kMaxDensity) {
    Fail(path + "/density", MaterialProblem(1, 0, config->density));
  }
}

// A shape so large that its volume overflows would reach the builders as a degenerate solid.
void RequireFiniteVolume(const core::BodyShape& shape, const std::string& path) {
  const auto finite_cube = [](double length) { return std::isfinite(length * length * length); };
  if (shape.kind == core::BodyShape::Kind::kBox && !finite_cube(shape.size.maxCoeff())) {
    Fail(path + "/size", "too large: the volume overflows");
  }
  if (!finite_cube(shape.radius) || !finite_cube(shape.length)) {
    Fail(path + (finite_cube(shape.radius) ? "/length" : "/radius"),
         "too large: the volume overflows");
  }
}

core::BodyShape ReadShape(XmlRpcValue& object, const std::string& path) {
  if (!Has(object, "shape")) Fail(path + "/shape", "missing (box, sphere, cylinder or mesh)");
  XmlRpcValue& shape = object["shape"];
  const std::string shape_path = path + "/shape";
  KnownKeys(shape, kShapeKeys, shape_path);
  const std::string type = Text(shape, "type", "", shape_path);
  OneOf(type, {"box", "sphere", "cylinder", "mesh"}, shape_path + "/type");
  core::BodyShape config;
  if (type == "box") {
    config.kind = core::BodyShape::Kind::kBox;
    config.size = Vector(shape, "size", Eigen::Vector3d::Zero(), shape_path);
    if ((config.size.array() <= 0.0).any()) Fail(shape_path + "/size", "each must be > 0");
  } else if (type == "sphere") {
    config.kind = core::BodyShape::Kind::kSphere;
    config.radius = Positive(shape, "radius", 0.0, shape_path);
  } else if (type == "cylinder") {
    config.kind = core::BodyShape::Kind::kCylinder;
    config.radius = Positive(shape, "radius", 0.0, shape_path);
    config.length = Positive(shape, "length", 0.0, shape_path);
  } else {
    config.kind = core::BodyShape::Kind::kMesh;
    config.mesh_path = ResolveUri(Text(shape, "uri", "", shape_path), shape_path + "/uri");
    RequireReadable(config.mesh_path, shape_path + "/uri");
    config.mesh_scale = Positive(shape, "scale", 1.0, shape_path);
  }
  RequireFiniteVolume(config, shape_path);
  return config;
}

// The lattice, by the core's names.
core::LatticeKind ReadLatticeKind(XmlRpcValue& object, core::LatticeKind fallback,
                                  const std::string& path) {
  const std::string name = Text(object, "model", core::LatticeKindName(fallback), path);
  core::LatticeKind kind = fallback;
  if (!core::ParseLatticeKind(name, &kind)) {
    const std::vector<std::string>& names = core::LatticeKindNames();
    FailNotOneOf(name, {names.begin(), names.end()}, path + "/model");
  }
  return kind;
}

Eigen::Isometry3d ReadPose(XmlRpcValue& object, double max_distance, const std::string& path) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  if (!Has(object, "pose")) return pose;
  XmlRpcValue& p = object["pose"];
  KnownKeys(p, {"position", "rpy"}, path + "/pose");
  pose.translation() = Vector(p, "position", Eigen::Vector3d::Zero(), path + "/pose");
  param::AtMost(pose.translation().norm(), max_distance, "position", path + "/pose",
                "its distance (m) from the world origin is beyond ~world/max_distance");
  const Eigen::Vector3d rpy = Vector(p, "rpy", Eigen::Vector3d::Zero(), path + "/pose");
  pose.linear() = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
                   Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                   Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                      .toRotationMatrix();
  return pose;
}

ClampConfig ReadClamp(XmlRpcValue& clamp, const std::set<std::string>& reserved,
                      const std::string& path) {
  KnownKeys(clamp, {"name", "box", "half_space"}, path);
  ClampConfig config;
  config.name = param::Name(clamp, "name", reserved, path);
  if (Has(clamp, "box")) {
    config.is_box = true;
    KnownKeys(clamp["box"], {"min", "max"}, path + "/box");
    config.min = Vector(clamp["box"], "min", Eigen::Vector3d::Zero(), path + "/box");
    config.max = Vector(clamp["box"], "max", Eigen::Vector3d::Zero(), path + "/box");
    if ((config.max.array() < config.min.array()).any()) Fail(path + "/box", "max < min");
  } else if (Has(clamp, "half_space")) {
    config.is_box = false;
    KnownKeys(clamp["half_space"], {"point", "normal"}, path + "/half_space");
    config.point =
        Vector(clamp["half_space"], "point", Eigen::Vector3d::Zero(), path + "/half_space");
    config.normal =
        Vector(clamp["half_space"], "normal", Eigen::Vector3d::UnitZ(), path + "/half_space");
    if (config.normal.norm() == 0.0) Fail(path + "/half_space/normal", "must not be zero");
  } else {
    Fail(path, "needs a box {min, max} or a half_space {point, normal}");
  }
  return config;
}

// mass_scaling (docs/physics.md §7 "Selective mass scaling"): the bound on the mass added to cut
// cells, as a fraction of the body's; cubic models in a mesh or a primitive read it, others
// ignore it.
double ReadMassScaling(XmlRpcValue& object, const std::string& path) {
  const double bound = Number(object, "mass_scaling", 0.01, path);
  if (!(bound >= 0.0 && bound <= 0.1)) {
    Fail(path + "/mass_scaling",
         "must lie in [0, 0.1] (the most mass added to cut cells, as a fraction of the body's; 0: "
         "off), got " +
             std::to_string(bound));
  }
  return bound;
}

// The lattice keys: model, spacing or target_nodes, anti-aliasing, the free faces' bending, the
// outer layer's dispersion, mass scaling, the random seed and self-calibration (the spring law is
// read with the material: ReadSpringLaw).
void ReadLatticeKeys(XmlRpcValue& object, const std::string& path, ObjectConfig* config) {
  config->model = ReadLatticeKind(object, config->model, path);
  if (config->model == core::LatticeKind::kBaudet &&
      config->shape.kind != core::BodyShape::Kind::kBox) {
    Fail(path + "/model", "baudet fills boxes only (shape type box)");
  }
  config->lattice.spacing = NonNegative(object, "spacing", 0.0, path);
  config->target_nodes =
      static_cast<int>(param::Count(object, "target_nodes", 0.0, core::kMaxBodyNodes, path));
  if ((config->lattice.spacing > 0.0) == (config->target_nodes > 0)) {
    Fail(path + "/spacing", "give exactly one of spacing (m) and target_nodes");
  }
  config->antialias = Flag(object, "antialias", true, path);
  config->surface.free_face_bending = Flag(object, "free_face_bending", false, path);
  if (config->surface.free_face_bending && config->model != core::LatticeKind::kCubic) {
    Fail(path + "/free_face_bending", "applies to cubic models only");
  }
  config->surface.surface_dispersion = Number(object, "surface_dispersion", 1.0, path);
  if (!(config->surface.surface_dispersion > 0.0 && config->surface.surface_dispersion <= 1.0)) {
    Fail(path + "/surface_dispersion",
         "must lie in (0, 1] (the share of its bulk the outer node layer keeps; 1: off), got " +
             std::to_string(config->surface.surface_dispersion));
  }
  if (config->surface.surface_dispersion != 1.0 && config->model != core::LatticeKind::kCubic) {
    Fail(path + "/surface_dispersion", "applies to cubic models only");
  }
  config->surface.mass_scaling = ReadMassScaling(object, path);
  config->seed = static_cast<std::uint64_t>(param::Count(object, "seed", 1.0, kMaxSeed, path));
  // Read whatever the lattice, so that a bad value is refused wherever it is given.
  const bool self_calibrate = Flag(object, "self_calibrate", kSelfCalibrateDefault, path);
  if (Has(object, "self_calibrate") && self_calibrate &&
      config->model != core::LatticeKind::kRandom) {
    Fail(path + "/self_calibrate", "applies to random models only");
  }
  config->self_calibrate = self_calibrate && config->model == core::LatticeKind::kRandom;
}

// The dynamics keys: dampers, friction, restitution and the orientation barrier.
void ReadDynamicsKeys(XmlRpcValue& object, const std::string& path, ObjectConfig* config) {
  config->damping = NonNegative(object, "damping", 2e-4, path);
  config->friction = NonNegative(object, "friction", config->friction, path);
  config->restitution = Number(object, "restitution", config->restitution, path);
  if (config->restitution < 0.0 || config->restitution > 1.0) {
    Fail(path + "/restitution", "must lie in [0, 1]");
  }
  config->orientation_threshold =
      Number(object, "orientation_threshold", config->orientation_threshold, path);
  if (config->orientation_threshold != 0.0 &&
      !(config->orientation_threshold > 0.0 && config->orientation_threshold < 1.0)) {
    Fail(path + "/orientation_threshold",
         "must be 0 (off) or lie in (0, 1), a fraction of a cell corner's rest volume; 0.2 "
         "unfolds a block squeezed to 30 % of its height");
  }
  if (config->orientation_threshold > 0.0 && config->model == core::LatticeKind::kRandom) {
    Fail(path + "/orientation_threshold",
         "applies to lattices with cells (cubic, baudet); a random lattice has none");
  }
}

// The clamps and the visual mesh, both optional. A clamp's name is its wrench's collider name
// in ~contacts: unique within the object and none of `reserved`.
void ReadClampsAndVisual(XmlRpcValue& object, const std::set<std::string>& reserved,
                         const std::string& path, ObjectConfig* config) {
  if (Has(object, "clamps")) {
    XmlRpcValue& clamps = object["clamps"];
    if (clamps.getType() != XmlRpcValue::TypeArray) Fail(path + "/clamps", "expected a list");
    std::set<std::string> names;
    for (int c = 0; c < clamps.size(); ++c) {
      const std::string clamp_path = path + "/clamps[" + std::to_string(c) + "]";
      config->clamps.push_back(ReadClamp(clamps[c], reserved, clamp_path));
      if (!names.insert(config->clamps.back().name).second) {
        Fail(clamp_path + "/name", "duplicate clamp name '" + config->clamps.back().name + "'");
      }
    }
  }
  if (Has(object, "visual_mesh")) {
    config->visual_mesh_path =
        ResolveUri(Text(object, "visual_mesh", "", path), path + "/visual_mesh");
    RequireReadable(config->visual_mesh_path, path + "/visual_mesh");
    config->visual_scale = Positive(object, "visual_scale", 1.0, path);
  }
}

ObjectConfig ReadObject(XmlRpcValue& object, XmlRpcValue* materials, const WorldConfig& world,
                        const std::string& path) {
  KnownKeys(object, kObjectKeys, path);
  ObjectConfig config;
  const std::set<std::string> reserved = ReservedNames(world);
  config.name = param::Name(object, "name", reserved, path);
  config.shape = ReadShape(object, path);
  config.pose = ReadPose(object, world.max_distance, path);
  ReadLatticeKeys(object, path, &config);
  const NamedMaterial material = FindMaterial(object, materials, path);
  ReadMaterial(object, material, path, &config);
  ReadSpringLaw(object, material, path, &config.lattice);
  ReadDynamicsKeys(object, path, &config);
  ReadClampsAndVisual(object, reserved, path, &config);
  return config;
}

}  // namespace

// ~objects, each with a unique name; ~materials supplies the materials objects name.
std::vector<ObjectConfig> ReadObjects(XmlRpcValue& root, const WorldConfig& world) {
  XmlRpcValue materials;
  const bool has_materials =
      Get(root, "materials", &materials) && materials.getType() == XmlRpcValue::TypeStruct;
  XmlRpcValue objects;
  if (!Get(root, "objects", &objects) || objects.getType() != XmlRpcValue::TypeArray ||
      objects.size() == 0) {
    Fail("~objects", "missing: list at least one object (see config/default.yaml)");
  }
  std::vector<ObjectConfig> configs;
  std::set<std::string> names;
  for (int i = 0; i < objects.size(); ++i) {
    ObjectConfig object = ReadObject(objects[i], has_materials ? &materials : nullptr, world,
                                     "~objects[" + std::to_string(i) + "]");
    if (!names.insert(object.name).second) {
      Fail("~objects[" + std::to_string(i) + "]/name", "duplicate name '" + object.name + "'");
    }
    configs.push_back(std::move(object));
  }
  return configs;
}

}  // namespace msm_sim::ros_interface
