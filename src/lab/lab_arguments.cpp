#include "lab_arguments.h"

#include <CLI/CLI.hpp>

namespace msm_sim::lab {
namespace {

void AddModelOptions(CLI::App* command, ModelArguments* model, std::vector<double>* size,
                     std::vector<double>* rotate) {
  command->add_option("--model", model->model, "cubic | random")
      ->required()
      ->check(CLI::IsMember({"cubic", "random"}));
  command->add_option("--size", *size, "body size LX LY LZ (m)")->expected(3)->required();
  command
      ->add_option("--spacing", model->spacing,
                   "lattice spacing a (m); for --model random the characteristic spacing l")
      ->required();
  command->add_option("--youngs", model->youngs, "Young's modulus E (Pa)")->required();
  command->add_option("--poisson", model->poisson, "Poisson's ratio nu")->required();
  command->add_option("--density", model->density, "density (kg/m^3)")->capture_default_str();
  command->add_option("--construction", model->construction, "cubic lattice: node | corner")
      ->capture_default_str()
      ->check(CLI::IsMember({"node", "corner"}));
  command->add_option("--rotate", *rotate, "cubic lattice rotation: axis AX AY AZ, angle DEG")
      ->expected(4);
  command->add_option("--seed", model->seed, "random lattice seed")->capture_default_str();
  command->add_option("--min-dist", model->min_dist, "random lattice minL as a multiple of l")
      ->capture_default_str();
  command->add_option("--max-dist", model->max_dist, "random lattice maxL as a multiple of l")
      ->capture_default_str();
  command
      ->add_option("--stiffness", model->stiffness,
                   "random lattice spring law: uniform | inverse-square")
      ->capture_default_str()
      ->check(CLI::IsMember({"uniform", "inverse-square"}));
}

}  // namespace

ParseOutcome ParseLabArguments(const std::vector<std::string>& argv) {
  CLI::App app{"msm_lab: virtual material tests of calibrated mass-spring models (SI units)",
               "msm_lab"};
  app.require_subcommand(1);
  LabArguments arguments;
  std::vector<double> size;
  std::vector<double> rotate;

  CLI::App* compression = app.add_subcommand(
      "compression", "uniaxial compression along x: measured E and nu (thesis 3.2.1)");
  AddModelOptions(compression, &arguments.model, &size, &rotate);
  compression->add_option("--strain", arguments.strain, "imposed compressive strain")
      ->capture_default_str();
  compression->add_flag("--json", arguments.json, "print one JSON object");

  CLI::App* deflection = app.add_subcommand(
      "deflection", "cantilever clamped at x = 0, force F in -z at x = L (thesis 3.2.6)");
  AddModelOptions(deflection, &arguments.model, &size, &rotate);
  deflection->add_option("--force", arguments.force, "total end force F (N)")->required();
  deflection->add_flag("--json", arguments.json, "print one JSON object");

  ParseOutcome outcome;
  if (argv.size() > 1 && !argv[1].empty() && argv[1][0] != '-' && argv[1] != "compression" &&
      argv[1] != "deflection") {
    outcome.message = "unknown command '" + argv[1] + "' (expected compression or deflection)";
    outcome.exit_code = 2;
    return outcome;
  }
  // CLI11 wants argv without the program name, in reverse order.
  std::vector<std::string> reversed(argv.rbegin(), argv.rend());
  if (!reversed.empty()) reversed.pop_back();
  try {
    app.parse(reversed);
  } catch (const CLI::CallForHelp&) {
    outcome.message = app.help();
    return outcome;
  } catch (const CLI::ParseError& error) {
    outcome.message = error.what();
    outcome.exit_code = 2;
    return outcome;
  }
  arguments.command = compression->parsed() ? LabCommand::kCompression : LabCommand::kDeflection;
  arguments.model.size = Eigen::Vector3d(size[0], size[1], size[2]);
  if (!rotate.empty()) {
    arguments.model.rotate = Eigen::Vector4d(rotate[0], rotate[1], rotate[2], rotate[3]);
  }
  outcome.arguments = arguments;
  return outcome;
}

}  // namespace msm_sim::lab
