#include "lab_arguments.h"

#include <CLI/CLI.hpp>

namespace msm_sim::lab {
namespace {

constexpr const char* kCommands[] = {"compression", "deflection", "poisson-sweep", "build",
                                     "slide"};

// Which body a command accepts and which options it insists on.
enum class Body {
  kBox,         // --size, required
  kBoxOrMesh,   // --size or --mesh, one of them required
  kMesh,        // --mesh, required
  kDefaultBox,  // --size optional (poisson-sweep has defaults)
};

// Options describing the model.
void AddModelOptions(CLI::App* command, ModelArguments* model, std::vector<double>* size,
                     std::vector<double>* rotate, Body body) {
  const bool required = body != Body::kDefaultBox;
  command
      ->add_option("--model", model->model,
                   "cubic | random | baudet (eMSM lattices, or Baudet's bricks with correction)")
      ->required()
      ->check(CLI::IsMember({"cubic", "random", "baudet"}));
  CLI::Option* size_option = nullptr;
  if (body != Body::kMesh) {
    size_option = command->add_option("--size", *size, "body size LX LY LZ (m)")->expected(3);
  }
  if (body == Body::kBoxOrMesh || body == Body::kMesh) {
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
            "mesh + cubic: cells weighted by the fraction inside the surface: on | off")
        ->check(CLI::IsMember({"on", "off"}));
  }
  auto* spacing_option =
      command->add_option("--spacing", model->spacing,
                          "lattice spacing a (m); for --model random the characteristic spacing l");
  if (body == Body::kBoxOrMesh || body == Body::kMesh) {
    command
        ->add_option("--target-nodes", model->target_nodes,
                     "choose the spacing for about this many nodes (instead of --spacing)")
        ->check(CLI::PositiveNumber)
        ->excludes(spacing_option);
  }
  auto* youngs_option = command->add_option("--youngs", model->youngs, "Young's modulus E (Pa)");
  if (required) {
    if (body == Body::kBox) size_option->required();
    if (body == Body::kBox) spacing_option->required();
    youngs_option->required();
    command->add_option("--poisson", model->poisson, "Poisson's ratio nu, in (-1, 0.5)")
        ->required();
  }
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
  command->add_option("--spring", model->spring, "spring tension law: linear | nonlinear")
      ->capture_default_str()
      ->check(CLI::IsMember({"linear", "nonlinear"}));
  command
      ->add_option("--dispersion", model->dispersion,
                   "eMSM dispersion: two-pass (exact) | one-pass (lagged accumulators)")
      ->capture_default_str()
      ->check(CLI::IsMember({"two-pass", "one-pass"}));
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
  AddModelOptions(compression, &arguments.model, &size, &rotate, Body::kBoxOrMesh);
  compression->add_option("--strain", arguments.strain, "imposed compressive strain")
      ->capture_default_str();
  compression->add_flag("--json", arguments.json, "print one JSON object");

  CLI::App* deflection = app.add_subcommand(
      "deflection", "cantilever clamped at x = 0, force F in -z at x = L (thesis 3.2.6)");
  AddModelOptions(deflection, &arguments.model, &size, &rotate, Body::kBox);
  deflection->add_option("--force", arguments.force, "total end force F (N)")->required();
  deflection->add_flag("--json", arguments.json, "print one JSON object");

  CLI::App* sweep = app.add_subcommand(
      "poisson-sweep",
      "compression at several target nu: measured against theoretical nu(Q) (eMSM figs. 7-8); "
      "defaults: E 1e5 Pa, cubic 2 x 1 x 1 m at a = 1/12 m, random 3 x 1 x 1 m at l = 0.1 m");
  AddModelOptions(sweep, &arguments.model, &size, &rotate, Body::kDefaultBox);
  sweep->add_option("--targets", arguments.targets, "target Poisson's ratios")
      ->capture_default_str();
  sweep->add_option("--strain", arguments.strain, "imposed compressive strain")
      ->capture_default_str();
  sweep->add_option("--plot", arguments.plot, "write a plot of nu against Q to this PNG file");
  sweep->add_flag("--json", arguments.json, "print one JSON object");

  CLI::App* build = app.add_subcommand(
      "build", "build a calibrated model from a closed mesh: size, mass; save it or export VTK");
  AddModelOptions(build, &arguments.model, &size, &rotate, Body::kMesh);
  build->add_option("--out", arguments.out, "save the model to this file (msm_sim model format)");
  build->add_option("--vtk", arguments.vtk, "write the model at rest to this .vtu file");
  build->add_flag("--json", arguments.json, "print one JSON object");

  CLI::App* slide = app.add_subcommand(
      "slide", "a box of NX x NY x NZ nodes slides on the ground from v0 along +x (thesis 6.4)");
  std::vector<int> slide_nodes;
  std::vector<double> slide_size;
  slide->add_option("--nodes", slide_nodes, "nodes along x, y, z (element-corner lattice)")
      ->expected(3)
      ->required()
      ->check(CLI::Range(2, 1000));
  slide->add_option("--size", slide_size, "box size LX LY LZ (m)")->expected(3)->required();
  slide->add_option("--mass", arguments.slide.mass, "total mass (kg)")->required();
  slide->add_option("--v0", arguments.slide.v0, "initial speed along +x (m/s)")->required();
  slide->add_option("--mu", arguments.slide.mu, "Coulomb friction with the ground")->required();
  slide->add_option("--youngs", arguments.slide.youngs, "Young's modulus E (Pa)")
      ->capture_default_str();
  slide->add_option("--poisson", arguments.slide.poisson, "Poisson's ratio nu")
      ->capture_default_str();
  slide->add_flag("--json", arguments.json, "print one JSON object");

  ParseOutcome outcome;
  if (argv.size() > 1 && !argv[1].empty() && argv[1][0] != '-' &&
      std::find(std::begin(kCommands), std::end(kCommands), argv[1]) == std::end(kCommands)) {
    outcome.message = "unknown command '" + argv[1] +
                      "' (expected compression, deflection, poisson-sweep, build or slide)";
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
  const bool has_spacing = arguments.model.spacing != 0.0 || arguments.model.target_nodes != 0;
  if ((compression->parsed() || build->parsed()) && !has_spacing) {
    outcome.message = "--spacing or --target-nodes is required";
    outcome.exit_code = 2;
    return outcome;
  }
  if (compression->parsed() && size.empty() && arguments.model.mesh.empty()) {
    outcome.message = "compression needs --size LX LY LZ or --mesh FILE";
    outcome.exit_code = 2;
    return outcome;
  }
  if (slide->parsed()) {
    arguments.command = LabCommand::kSlide;
    arguments.slide.nodes = Eigen::Vector3i(slide_nodes[0], slide_nodes[1], slide_nodes[2]);
    arguments.slide.size = Eigen::Vector3d(slide_size[0], slide_size[1], slide_size[2]);
    outcome.arguments = arguments;
    return outcome;
  }
  if (compression->parsed()) {
    arguments.command = LabCommand::kCompression;
  } else if (build->parsed()) {
    arguments.command = LabCommand::kBuild;
  } else if (deflection->parsed()) {
    arguments.command = LabCommand::kDeflection;
  } else {
    arguments.command = LabCommand::kPoissonSweep;
    const bool cubic = arguments.model.model != "random";
    if (size.empty()) size = cubic ? std::vector<double>{2, 1, 1} : std::vector<double>{3, 1, 1};
    if (arguments.model.spacing == 0.0) arguments.model.spacing = cubic ? 1.0 / 12.0 : 0.1;
    if (arguments.model.youngs == 0.0) arguments.model.youngs = 1e5;
  }
  if (!size.empty()) arguments.model.size = Eigen::Vector3d(size[0], size[1], size[2]);
  if (!rotate.empty()) {
    arguments.model.rotate = Eigen::Vector4d(rotate[0], rotate[1], rotate[2], rotate[3]);
  }
  outcome.arguments = arguments;
  return outcome;
}

}  // namespace msm_sim::lab
