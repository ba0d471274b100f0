// msm_lab grasp's options (core::RunGraspExperiment).
#include "lab_command_line.h"

namespace msm_sim::lab {

void AddGraspCommand(CLI::App* app, CommandLine* line) {
  GraspArguments& grasp = line->arguments.grasp;
  CLI::App* command = line->grasp = app->add_subcommand(
      "grasp",
      "an object resting on the ground, squeezed across its narrower horizontal extent by two "
      "rigid "
      "2 x 2 cm pads under force control "
      "until 2 mu F_n = Q m g, held 0.5 s, lifted and held 1 s: rise, slip and whether it is "
      "held");
  command->add_option("--shape", grasp.shape, "box | sphere | cylinder | ellipsoid | mesh")
      ->required()
      ->check(CLI::IsMember({"box", "sphere", "cylinder", "ellipsoid", "mesh"}));
  command->add_option("--radius", grasp.radius, "sphere and cylinder radius (m)")
      ->check(Finite(false));
  command->add_option("--length", grasp.length, "cylinder length (m), its axis along y")
      ->check(Finite(false));
  AddModelOptions(command, line, Body::kGraspObject);
  command->add_option("--friction", grasp.friction, "Coulomb coefficient with the pads, ground")
      ->capture_default_str()
      ->check(Finite(false));
  command->add_option("--force-ratio", grasp.force_ratio, "Q = 2 mu F_n / (m g)")
      ->capture_default_str()
      ->check(Finite(false));
  command->add_option("--lift", grasp.lift, "how high the pads lift (m)")
      ->capture_default_str()
      ->check(Finite(true));
  command->add_option("--lift-time", grasp.lift_time, "how long the lift takes (s)")
      ->capture_default_str()
      ->check(Finite(false));
  command->add_option("--damping", grasp.damping, "spring dampers beta, c = beta k (s)")
      ->capture_default_str()
      ->check(Finite(true));
  command
      ->add_option("--orientation-threshold", grasp.orientation_threshold,
                   "cubic lattices: cells squeezed below this fraction of their volume are "
                   "pushed back (0 off; keeps hard squeezes from folding the lattice)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.99));
  command
      ->add_option("--integrator", grasp.integrator,
                   "implicit (one substep a step; faster on grasp objects) | explicit (position "
                   "Verlet, stable substeps)")
      ->capture_default_str()
      ->check(CLI::IsMember({"explicit", "implicit"}));
  command->add_flag("--json", line->arguments.json, "print one JSON object");
}

std::string GraspShapeProblem(const CommandLine& line, const std::string& command) {
  const GraspArguments& grasp = line.arguments.grasp;
  const bool size = !line.size.empty(), mesh = !line.arguments.model.mesh.empty();
  const bool radius = grasp.radius > 0.0, length = grasp.length > 0.0;
  const std::string& shape = grasp.shape;
  if ((shape == "box" || shape == "ellipsoid") && !(size && !radius && !length)) {
    return command + " --shape " + shape + " needs --size LX LY LZ (and no --radius, --length)";
  }
  if (shape == "sphere" && !(radius && !size && !mesh && !length)) {
    return "grasp --shape sphere needs --radius R (and no --size, --mesh, --length)";
  }
  if (shape == "cylinder" && !(radius && length && !size && !mesh)) {
    return "grasp --shape cylinder needs --radius R and --length L (and no --size, --mesh)";
  }
  if (shape == "mesh" && !(mesh && !radius && !length)) {
    return "grasp --shape mesh needs --mesh FILE (and no --radius, --length)";
  }
  if (line.arguments.model.spacing == 0.0 && line.arguments.model.target_nodes == 0) {
    return command + " needs --spacing A or --target-nodes N";
  }
  return "";
}

}  // namespace msm_sim::lab
