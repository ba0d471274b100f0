// msm_lab squeeze's options (core::RunSqueezeExperiment).
#include "lab_command_line.h"

namespace msm_sim::lab {

void AddSqueezeCommand(CLI::App* app, CommandLine* line) {
  GraspArguments& shape = line->arguments.grasp;
  SqueezeArguments& squeeze = line->arguments.squeeze;
  CLI::App* command = line->squeeze = app->add_subcommand(
      "squeeze",
      "an object on its own between two rigid flat plates that close on it along z, "
      "quasi-statically, until their total approach is --approach: per row the approach, the "
      "force on a plate and the contact patch's area and radius (no gravity)");
  command->add_option("--shape", shape.shape, "box | sphere | cylinder | ellipsoid | mesh")
      ->required()
      ->check(CLI::IsMember({"box", "sphere", "cylinder", "ellipsoid", "mesh"}));
  command->add_option("--radius", shape.radius, "sphere and cylinder radius (m)")
      ->check(Finite(false));
  command->add_option("--length", shape.length, "cylinder length (m), its axis along y")
      ->check(Finite(false));
  AddModelOptions(command, line, Body::kGraspObject);
  command->add_option("--approach", squeeze.approach, "both plates' travel together (m)")
      ->required()
      ->check(Finite(false));
  command->add_option("--speed", squeeze.speed, "each plate's closing speed (m/s)")
      ->capture_default_str()
      ->check(Finite(false));
  command
      ->add_option("--friction", squeeze.friction,
                   "Coulomb coefficient with the plates (0: frictionless)")
      ->capture_default_str()
      ->check(Finite(true));
  command->add_option("--damping", squeeze.damping, "spring dampers beta, c = beta k (s)")
      ->capture_default_str()
      ->check(Finite(true));
  command
      ->add_option("--orientation-threshold", squeeze.orientation_threshold,
                   "cubic lattices: cells squeezed below this fraction of their volume are "
                   "pushed back (0 off); a cell turned inside out stops the run either way")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.99));
  command->add_option("--samples", squeeze.samples, "rows of the profile")
      ->capture_default_str()
      ->check(CLI::Range(1, 10000));
  command
      ->add_option("--integrator", squeeze.integrator,
                   "explicit (position Verlet, stable substeps) | implicit (one substep a step)")
      ->capture_default_str()
      ->check(CLI::IsMember({"explicit", "implicit"}));
  command
      ->add_option("--time-step-safety", squeeze.time_step_safety,
                   "explicit integrator: the fraction of the stable step each substep takes, in "
                   "(0, 1]; smaller for power-law springs squeezed hard")
      ->capture_default_str()
      ->check(CLI::Range(1e-3, 1.0));
  command->add_flag("--json", line->arguments.json, "print one JSON object");
}

}  // namespace msm_sim::lab
