#include <cmath>
#include <string>

#include "lab_command_line.h"

namespace msm_sim::lab {
namespace {

// --sphere-radius and --damping of the sphere commands (realtime, indent).
void AddSphereOptions(CLI::App* command, ContactArguments* contact) {
  command->add_option("--sphere-radius", contact->sphere_radius, "rigid sphere's radius (m)")
      ->capture_default_str()
      ->check(Finite(false));
  command->add_option("--damping", contact->damping, "spring dampers beta, c = beta k (s)")
      ->capture_default_str()
      ->check(Finite(true));
  command
      ->add_option("--integrator", contact->integrator,
                   "explicit (position Verlet, stable substeps) | implicit (one substep a step)")
      ->capture_default_str()
      ->check(CLI::IsMember({"explicit", "implicit"}));
  command
      ->add_option("--precision", contact->precision,
                   "the spring loops' arithmetic: single | double (cubic lattices; "
                   "docs/physics.md section 9)")
      ->capture_default_str()
      ->check(CLI::IsMember({"double", "single"}));
}

void AddFitCommand(CLI::App* app, CommandLine* line) {
  FitArguments& fit = line->arguments.fit;
  CLI::App* command = line->fit = app->add_subcommand(
      "fit",
      "--indent: the Young's modulus for which indent on the same block reproduces a measured "
      "curve of a spherical probe (1-D search from Hertz's estimate); defaults: cubic, a spacing "
      "with 4 nodes across the largest contact radius sqrt(R depth), nu 0.49. --tensile: E and "
      "the spring law (docs/physics.md 4.1) from a uniaxial tensile curve");
  command->add_option("--indent", fit.curve, "CSV of depth_m,force_N rows, depth past contact")
      ->check(CLI::ExistingFile);
  AddModelOptions(command, line, Body::kFitBlock);
  AddSphereOptions(command, &line->arguments.contact);
  command->add_option("--speed", line->arguments.contact.speed, "the simulated probe's speed (m/s)")
      ->capture_default_str()
      ->check(Finite(false));
  auto* fit_poisson = command->add_flag(
      "--fit-poisson", fit.fit_poisson,
      "fit nu too, from a second curve (--indent2) on a block of another thickness (--size2): "
      "E from the first curve at each trial nu, nu where both are reproduced");
  fit_poisson->excludes(command->get_option("--poisson"));
  auto* second = command
                     ->add_option("--indent2", fit.second_curve,
                                  "--fit-poisson: the second CSV, on the --size2 block")
                     ->check(CLI::ExistingFile);
  auto* second_size =
      command
          ->add_option("--size2", line->second_size, "--fit-poisson: the second block LX LY LZ (m)")
          ->expected(3);
  fit_poisson->needs(second)->needs(second_size);
  second->needs(fit_poisson);
  second_size->needs(fit_poisson);
  command->add_option("--yaml", fit.yaml, "write the fitted material as a materials.yaml entry");
  command->add_option("--name", fit.name, "the material's name in that entry")
      ->capture_default_str();
  AddTensileOptions(command, line);
  command->add_flag("--json", line->arguments.json, "print one JSON object");
}

}  // namespace

// A finite number > 0 (or >= 0): CLI11's PositiveNumber would print its range up to DBL_MAX.
CLI::Validator Finite(bool zero_allowed) {
  const char* requirement = zero_allowed ? "must be finite and >= 0" : "must be finite and > 0";
  return CLI::Validator(
      [zero_allowed, requirement](std::string& text) -> std::string {
        double value = 0.0;
        const bool number = CLI::detail::lexical_cast(text, value) && std::isfinite(value);
        return number && (value > 0.0 || (zero_allowed && value == 0.0)) ? "" : requirement;
      },
      zero_allowed ? "NONNEGATIVE" : "POSITIVE");
}

void AddSphereCommands(CLI::App* app, CommandLine* line) {
  ContactArguments& contact = line->arguments.contact;
  CLI::App* realtime = line->realtime = app->add_subcommand(
      "realtime",
      "wall time per simulated second of the dynamics (explicit integrator: 1 ms steps in stable "
      "substeps): a block on the ground, a rigid sphere pressing into the middle of its top at "
      "1 cm/s; defaults: 0.1 x 0.1 x 0.05 m, E 2e5 Pa, density 1100 kg/m^3");
  AddModelOptions(realtime, line, Body::kDefaultBlock);
  AddSphereOptions(realtime, &contact);
  realtime->add_option("--seconds", contact.seconds, "simulated time (s)")
      ->capture_default_str()
      ->check(Finite(false));
  realtime
      ->add_option("--threads", contact.threads,
                   "threads of the spring loops and per-node stages (node shares of blocks of "
                   "1,000 nodes or more)")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  realtime
      ->add_option("--time-step-safety", contact.time_step_safety,
                   "explicit integrator: the fraction of the stable step each substep takes, in "
                   "(0, 1]")
      ->capture_default_str()
      ->check(CLI::Range(1e-3, 1.0));
  realtime->add_flag("--json", line->arguments.json, "print one JSON object");

  CLI::App* indent = line->indent = app->add_subcommand(
      "indent",
      "a rigid sphere pressed into the middle of the top of a block clamped at its base, force "
      "against Hertz's (explicit integrator, 1 ms steps, no gravity)");
  AddModelOptions(indent, line, Body::kBlock);
  AddSphereOptions(indent, &contact);
  indent->get_option("--sphere-radius")->required();
  indent->add_option("--depth", contact.depth, "indentation past first contact (m)")
      ->required()
      ->check(Finite(false));
  indent->add_option("--speed", contact.speed, "the sphere's speed, down (m/s)")
      ->capture_default_str()
      ->check(Finite(false));
  indent
      ->add_option("--friction", contact.friction,
                   "Coulomb coefficient between the sphere and the block (0: frictionless, as "
                   "Hertz's contact)")
      ->capture_default_str()
      ->check(Finite(true));
  indent
      ->add_option("--start-depth", contact.start_depth,
                   "also start the sphere this far past first contact, inside the block, and "
                   "hold it there 0.2 s: penetration recovery (m)")
      ->capture_default_str()
      ->check(Finite(true));
  indent->add_option("--plot", line->arguments.plot,
                     "write a plot of the force and Hertz's against depth to this PNG file");
  indent->add_flag("--json", line->arguments.json, "print one JSON object");
  AddFitCommand(app, line);
}

}  // namespace msm_sim::lab
