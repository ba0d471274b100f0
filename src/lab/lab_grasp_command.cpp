#include "lab_grasp_command.h"

#include <cmath>
#include <iomanip>
#include <memory>
#include <utility>

#include "lab_model.h"
#include "lab_report.h"
#include "msm_sim/experiments/grasp_experiment.h"
#include "msm_sim/geometry/mesh_primitives.h"
#include "msm_sim/model/model_statistics.h"

namespace msm_sim::lab {
namespace {

// Primitives as fine as a 2 mm lattice can see on a 5 cm object.
constexpr int kSphereSubdivisions = 4;
constexpr int kCylinderSegments = 96;

LabBody BodyOfSolid(core::SolidMesh solid) {
  LabBody body;
  body.min = solid.min_corner();
  body.max = solid.max_corner();
  body.volume = solid.volume();
  body.solid = std::make_shared<const core::SolidMesh>(std::move(solid));
  return body;
}

}  // namespace

LabBody GraspBody(const LabArguments& arguments) {
  const GraspArguments& grasp = arguments.grasp;
  if (grasp.shape == "box" || grasp.shape == "mesh") return LoadLabBody(arguments.model, false);
  if (grasp.shape == "sphere") {
    return BodyOfSolid(core::SolidMesh(core::MakeIcosphereMesh(grasp.radius, kSphereSubdivisions)));
  }
  if (grasp.shape == "ellipsoid") {
    core::TriangleMesh mesh = core::MakeIcosphereMesh(0.5, kSphereSubdivisions);
    mesh.vertices = arguments.model.size.asDiagonal() * mesh.vertices;
    return BodyOfSolid(core::SolidMesh(mesh));
  }
  // A cylinder lying on the ground, its axis along y: across the pads, which close along x.
  core::TriangleMesh mesh = core::MakeCylinderMesh(grasp.radius, grasp.length, kCylinderSegments);
  // A quarter turn about x, exactly: (x, y, z) -> (x, -z, y).
  const Eigen::Matrix3Xd along_z = mesh.vertices;
  mesh.vertices.row(1) = -along_z.row(2);
  mesh.vertices.row(2) = along_z.row(1);
  return BodyOfSolid(core::SolidMesh(mesh));
}

namespace {

core::GraspExperimentOptions GraspOptions(const LabArguments& arguments) {
  const GraspArguments& grasp = arguments.grasp;
  core::GraspExperimentOptions options;
  options.friction = grasp.friction;
  options.force_ratio = grasp.force_ratio;
  options.lift = grasp.lift;
  options.lift_time = grasp.lift_time;
  options.damping_beta = grasp.damping;
  options.orientation_threshold = grasp.orientation_threshold;
  options.integrator = IntegratorNamed(grasp.integrator);
  return options;
}

void PrintGrasp(const LabArguments& arguments, const core::Model& model,
                const core::GraspExperimentResult& r, std::ostream& out) {
  const GraspArguments& grasp = arguments.grasp;
  out << "grasp: " << grasp.shape << " between two rigid pads, mu " << grasp.friction
      << ", 2 mu F_n = " << grasp.force_ratio << " m g, lift " << 1e3 * grasp.lift << " mm over "
      << grasp.lift_time << " s\n";
  PrintModelTable(arguments.model, core::ComputeModelStatistics(model), out);
  out << std::setprecision(4) << "integrator       " << grasp.integrator << "\n"
      << "mass             " << 1e3 * r.mass << " g\n"
      << "squeeze per pad  " << r.squeeze_force << " N (target " << r.target_force << " N)\n"
      << "rise             " << 1e3 * r.rise << " mm\n"
      << "slip             " << 1e3 * r.slip << " mm\n"
      << "max node speed   " << r.max_node_speed << " m/s\n"
      << "energy max       " << r.energy_max << " J\n"
      << "real-time factor " << r.real_time_factor << "\n"
      << "verdict          " << (r.held ? "held" : "not held") << "\n";
}

}  // namespace

int RunGrasp(const LabArguments& arguments, std::ostream& out) {
  const GraspArguments& grasp = arguments.grasp;
  const core::GraspExperimentOptions options = GraspOptions(arguments);
  const auto model =
      std::make_shared<const core::Model>(BuildLabModel(arguments.model, GraspBody(arguments)));
  const core::GraspExperimentResult r = core::RunGraspExperiment(model, options);
  if (!arguments.json) {
    PrintGrasp(arguments, *model, r, out);
    return 0;
  }
  const Json json{{"shape", grasp.shape},
                  {"friction", grasp.friction},
                  {"force_ratio", grasp.force_ratio},
                  {"integrator", grasp.integrator},
                  {"nodes", r.nodes},
                  {"added_mass", model->added_mass()},
                  {"squeeze_force", r.squeeze_force},
                  {"rise", r.rise},
                  {"slip", r.slip},
                  {"held", r.held},
                  {"max_node_speed", r.max_node_speed},
                  {"energy_max", r.energy_max},
                  {"real_time_factor", r.real_time_factor}};
  out << json.dump() << "\n";
  return 0;
}

}  // namespace msm_sim::lab
