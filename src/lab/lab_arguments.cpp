#include "lab_arguments.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "lab_command_line.h"
#include "msm_sim/lattice/body_recipe.h"

namespace msm_sim::lab {
namespace {

constexpr const char* kCommands[] = {"compression", "deflection", "poisson-sweep", "build",
                                     "slide",       "realtime",   "indent",        "fit",
                                     "grip",        "grasp",      "material",      "squeeze"};

// The sphere commands' model options: --model defaults to cubic.
bool ModelOptional(Body body) {
  return body == Body::kBlock || body == Body::kDefaultBlock || body == Body::kFitBlock ||
         body == Body::kGraspObject;
}

// --size and/or --mesh with its --scale and --antialias; returns --size (nullptr for kMesh).
CLI::Option* AddBodyOptions(CLI::App* command, ModelArguments* model, std::vector<double>* size,
                            Body body) {
  CLI::Option* size_option = nullptr;
  if (body != Body::kMesh) {
    size_option = command->add_option("--size", *size, "body size LX LY LZ (m)")->expected(3);
    if (body == Body::kBox || body == Body::kBlock) {
      size_option->required();
    }
  }
  if (body != Body::kBoxOrMesh && body != Body::kMesh && body != Body::kGraspObject) {
    return size_option;
  }
  auto* mesh_option = command->add_option(
      "--mesh", model->mesh, "closed triangle mesh (STL, OBJ, PLY, OFF, DAE, glTF, ...)");
  if (size_option != nullptr) {
    mesh_option->excludes(size_option);
    size_option->excludes(mesh_option);
  } else {
    mesh_option->required();
  }
  command->add_option("--scale", model->scale, "mesh units to metres (0.001 for mm)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  command
      ->add_option_function<std::string>(
          "--antialias", [model](const std::string& v) { model->antialias = v == "on"; },
          "cubic in a mesh, or in a --size box with --rotate: cells weighted by the fraction "
          "inside the surface: on | off")
      ->check(CLI::IsMember({"on", "off"}));
  return size_option;
}

// --spacing, and --target-nodes where a mesh may be given.
void AddSpacingOptions(CLI::App* command, ModelArguments* model, Body body) {
  auto* spacing_option =
      command->add_option("--spacing", model->spacing,
                          "lattice spacing a (m); for --model random the characteristic spacing l");
  const bool optional = body == Body::kFitBlock || body == Body::kGraspObject;
  if ((body == Body::kBox || ModelOptional(body)) && !optional) spacing_option->required();
  if (body == Body::kBoxOrMesh || body == Body::kMesh || optional) {
    command
        ->add_option("--target-nodes", model->target_nodes,
                     "choose the spacing for about this many nodes (instead of --spacing)")
        ->check(CLI::PositiveNumber)
        ->excludes(spacing_option);
  }
}

// --youngs, --poisson (both required unless the command has defaults) and --density.
void AddMaterialOptions(CLI::App* command, ModelArguments* model, Body body) {
  if (body == Body::kFitBlock) {  // E is what fit finds
    command->add_option("--poisson", model->poisson,
                        "Poisson's ratio nu, in (-1, 0.5) (default 0.49, an elastomer)");
    command->add_option("--density", model->density, "density (kg/m^3)")->capture_default_str();
    return;
  }
  auto* youngs_option = command->add_option("--youngs", model->youngs, "Young's modulus E (Pa)");
  if (body != Body::kDefaultBox) {
    if (body != Body::kDefaultBlock) youngs_option->required();
    command->add_option("--poisson", model->poisson, "Poisson's ratio nu, in (-1, 0.5)")
        ->required();
  }
  auto* density_option = command->add_option("--density", model->density, "density (kg/m^3)");
  if (body != Body::kDefaultBlock) density_option->capture_default_str();
}

// A share in (0, 1]: CLI::Range includes 0 and PositiveNumber's message names a range up to
// the largest double.
CLI::Validator ShareInZeroToOne() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value) || !(value > 0.0 && value <= 1.0)) {
          return "must lie in (0, 1], got " + text;
        }
        return "";
      },
      "SHARE in (0, 1]");
}

// The options each lattice reads: construction and rotation (cubic), seed, distances and
// stiffness law (random), and the spring and dispersion laws of every lattice.
void AddLatticeOptions(CLI::App* command, ModelArguments* model, std::vector<double>* rotate) {
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
  command->add_flag("--self-calibrate", model->self_calibrate,
                    "random lattice: correct k and q by measuring a representative block");
  command->add_flag("--free-face-bending", model->free_face_bending,
                    "node-centred cubic box: stiffen the outer layers' springs (and soften the "
                    "interior's) to restore the free faces' bending stiffness");
  command
      ->add_option("--surface-dispersion", model->surface_dispersion,
                   "node-centred cubic: the share of its eMSM bulk the outer node layer keeps, "
                   "in (0, 1], the rest moved one layer in (a longer stable step near nu = 0.5)")
      ->capture_default_str()
      ->check(ShareInZeroToOne());
  command
      ->add_option("--mass-scaling", model->mass_scaling,
                   "node-centred cubic: the most mass added to cut cells so that they do not set "
                   "the explicit step, a fraction of the body's in [0, 0.1]; 0: off")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.1));
  command
      ->add_option("--spring", model->spring,
                   "spring tension law: linear | nonlinear | power (with --alpha and --beta)")
      ->capture_default_str()
      ->check(CLI::IsMember({"linear", "nonlinear", "power"}));
  command->add_option("--alpha", model->alpha,
                      "--spring power: the law's alpha (docs/physics.md 4.1; fit --tensile)");
  command->add_option("--beta", model->beta,
                      "--spring power: the law's beta >= 0 (docs/physics.md 4.1; fit --tensile)");
}

}  // namespace

// Options describing the model, in the order --help lists them.
void AddModelOptions(CLI::App* command, CommandLine* line, Body body) {
  ModelArguments* model = &line->arguments.model;
  auto* model_option =
      command
          ->add_option(
              "--model", model->model,
              "cubic | random | baudet (eMSM lattices, or Baudet's bricks with correction)")
          ->check(CLI::IsMember(core::LatticeKindNames()));
  model_option->required(!ModelOptional(body));
  if (ModelOptional(body)) model_option->capture_default_str();
  AddBodyOptions(command, model, &line->size, body);
  AddSpacingOptions(command, model, body);
  AddMaterialOptions(command, model, body);
  AddLatticeOptions(command, model, &line->rotate);
}

namespace {

ParseOutcome Failure(const std::string& message) {
  ParseOutcome outcome;
  outcome.message = message;
  outcome.exit_code = 2;
  return outcome;
}

// A first word that is no option and no command; CLI11 would take it for an extra argument.
bool IsUnknownCommand(const std::vector<std::string>& argv) {
  return argv.size() > 1 && !argv[1].empty() && argv[1][0] != '-' &&
         std::find(std::begin(kCommands), std::end(kCommands), argv[1]) == std::end(kCommands);
}

// What CLI11 cannot say: an option required only together with another, or only by one command.
std::string MissingBodyOption(const CommandLine& line) {
  const ModelArguments& model = line.arguments.model;
  const bool has_spacing = model.spacing != 0.0 || model.target_nodes != 0;
  if ((line.compression->parsed() || line.build->parsed()) && !has_spacing) {
    return "--spacing or --target-nodes is required";
  }
  if (line.material->parsed() && line.material->get_option("--shore-a")->count() == 0 &&
      line.material->get_option("--shore-00")->count() == 0) {
    return "material needs --shore-a S or --shore-00 S";
  }
  if (line.grasp->parsed()) return GraspShapeProblem(line, "grasp");
  if (line.squeeze->parsed()) return GraspShapeProblem(line, "squeeze");
  if (line.fit->parsed()) return FitOptionProblem(line);
  if (line.compression->parsed() && line.size.empty() && model.mesh.empty()) {
    return "compression needs --size LX LY LZ or --mesh FILE";
  }
  return "";
}

// poisson-sweep's defaults (see its help): the eMSM paper's blocks.
void ApplySweepDefaults(CommandLine* line) {
  ModelArguments& model = line->arguments.model;
  const bool cubic = model.model != "random";
  if (line->size.empty()) {
    line->size = cubic ? std::vector<double>{2, 1, 1} : std::vector<double>{3, 1, 1};
  }
  if (model.spacing == 0.0) model.spacing = cubic ? 1.0 / 12.0 : 0.1;
  if (model.youngs == 0.0) model.youngs = 1e5;
}

// realtime's defaults (see its help): the block.
void ApplyRealtimeDefaults(CommandLine* line) {
  ModelArguments& model = line->arguments.model;
  if (line->size.empty()) line->size = {0.1, 0.1, 0.05};
  if (line->realtime->get_option("--youngs")->count() == 0) model.youngs = 2e5;
  if (line->realtime->get_option("--density")->count() == 0) model.density = 1100.0;
}

// grip's defaults (see its help): a 4 cm cube of the material.
void ApplyGripDefaults(CommandLine* line) {
  ModelArguments& model = line->arguments.model;
  if (line->size.empty()) line->size = {0.04, 0.04, 0.04};
  if (line->grip->get_option("--youngs")->count() == 0) model.youngs = 2e5;
  if (line->grip->get_option("--density")->count() == 0) model.density = 1100.0;
}

// The parsed command, with the checked vectors copied into the arguments.
LabArguments ParsedArguments(CommandLine* line) {
  LabArguments& arguments = line->arguments;
  if (line->slide->parsed()) {
    arguments.command = LabCommand::kSlide;
    const std::vector<int>& nodes = line->slide_nodes;
    const std::vector<double>& size = line->slide_size;
    arguments.slide.nodes = Eigen::Vector3i(nodes[0], nodes[1], nodes[2]);
    arguments.slide.size = Eigen::Vector3d(size[0], size[1], size[2]);
    return arguments;
  }
  if (line->material->parsed()) {
    arguments.command = LabCommand::kMaterial;
    arguments.hardness.from_shore_00 = line->material->get_option("--shore-00")->count() > 0;
    arguments.hardness.has_poisson = line->material->get_option("--poisson")->count() > 0;
    return arguments;
  }
  if (line->compression->parsed()) {
    arguments.command = LabCommand::kCompression;
  } else if (line->build->parsed()) {
    arguments.command = LabCommand::kBuild;
  } else if (line->deflection->parsed()) {
    arguments.command = LabCommand::kDeflection;
  } else if (line->realtime->parsed()) {
    arguments.command = LabCommand::kRealtime;
    ApplyRealtimeDefaults(line);
  } else if (line->indent->parsed()) {
    arguments.command = LabCommand::kIndent;
  } else if (line->fit->parsed()) {
    arguments.command = LabCommand::kFit;
    ApplyFitDefaults(line);
  } else if (line->grip->parsed()) {
    arguments.command = LabCommand::kGrip;
    ApplyGripDefaults(line);
  } else if (line->grasp->parsed()) {
    arguments.command = LabCommand::kGrasp;
  } else if (line->squeeze->parsed()) {
    arguments.command = LabCommand::kSqueeze;
  } else {
    arguments.command = LabCommand::kPoissonSweep;
    ApplySweepDefaults(line);
  }
  const std::vector<double>& size = line->size;
  const std::vector<double>& rotate = line->rotate;
  if (!size.empty()) arguments.model.size = Eigen::Vector3d(size[0], size[1], size[2]);
  if (!rotate.empty()) {
    arguments.model.rotate = Eigen::Vector4d(rotate[0], rotate[1], rotate[2], rotate[3]);
  }
  const std::vector<int>& elements = line->reference_elements;
  if (!elements.empty()) {
    arguments.reference_elements = Eigen::Vector3i(elements[0], elements[1], elements[2]);
  }
  return arguments;
}

}  // namespace

ParseOutcome ParseLabArguments(const std::vector<std::string>& argv) {
  CLI::App app{"msm_lab: virtual material tests of calibrated mass-spring models (SI units)",
               "msm_lab"};
  app.require_subcommand(1);
  CommandLine line;
  AddStaticCommands(&app, &line);
  AddSphereCommands(&app, &line);
  AddGripCommand(&app, &line);
  AddGraspCommand(&app, &line);
  AddSqueezeCommand(&app, &line);

  if (IsUnknownCommand(argv)) {
    return Failure("unknown command '" + argv[1] +
                   "' (expected compression, deflection, poisson-sweep, build, slide, realtime, "
                   "indent, fit, grip, grasp, material or squeeze)");
  }
  // CLI11 wants argv without the program name, in reverse order.
  std::vector<std::string> reversed(argv.rbegin(), argv.rend());
  if (!reversed.empty()) reversed.pop_back();
  ParseOutcome outcome;
  try {
    app.parse(reversed);
  } catch (const CLI::CallForHelp&) {
    outcome.message = app.help();
    return outcome;
  } catch (const CLI::ParseError& error) {
    return Failure(error.what());
  }
  const std::string missing = MissingBodyOption(line);
  if (!missing.empty()) return Failure(missing);
  outcome.arguments = ParsedArguments(&line);
  return outcome;
}

}  // namespace msm_sim::lab
