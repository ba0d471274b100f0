// msm_lab grip's options (core::RunGripExperiment).
#include "lab_command_line.h"

namespace msm_sim::lab {

void AddGripCommand(CLI::App* app, CommandLine* line) {
  GripArguments& grip = line->arguments.grip;
  CLI::App* command = line->grip = app->add_subcommand(
      "grip",
      "a block squeezed between two rigid jaws and lifted, with mu set from the jaws' measured "
      "normal force so that 2 mu F_n = ratio m g: slip and whether it is held; defaults: "
      "0.04 x 0.04 x 0.04 m, E 2e5 Pa, density 1100 kg/m^3");
  AddModelOptions(command, line, Body::kDefaultBlock);
  command->add_option("--ratio", grip.ratio, "2 mu F_n / (m g) the friction is chosen for")
      ->capture_default_str()
      ->check(Finite(false));
  command->add_option("--squeeze", grip.squeeze, "each jaw's travel into the block (m)")
      ->capture_default_str()
      ->check(Finite(false));
  command->add_option("--damping", grip.damping, "spring dampers beta, c = beta k (s)")
      ->capture_default_str()
      ->check(Finite(true));
  command->add_option("--lift-time", grip.lift_time, "how long the jaws rise (s)")
      ->capture_default_str()
      ->check(Finite(false));
  command
      ->add_option("--integrator", grip.integrator,
                   "explicit (position Verlet, stable substeps) | implicit (one substep a step)")
      ->capture_default_str()
      ->check(CLI::IsMember({"explicit", "implicit"}));
  command->add_flag("--json", line->arguments.json, "print one JSON object");
}

}  // namespace msm_sim::lab
