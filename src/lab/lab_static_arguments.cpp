// msm_lab's static commands (compression, deflection, poisson-sweep), build, slide and material:
// their options (lab_command_line.h).
#include <string>
#include <vector>

#include "lab_command_line.h"

namespace msm_sim::lab {
namespace {

void AddExperimentCommands(CLI::App* app, CommandLine* line) {
  LabArguments& arguments = line->arguments;
  line->compression = app->add_subcommand(
      "compression", "uniaxial compression along x: measured E and nu (thesis 3.2.1)");
  AddModelOptions(line->compression, line, Body::kBoxOrMesh);
  line->compression->add_option("--strain", arguments.strain, "imposed compressive strain")
      ->capture_default_str();
  line->compression->add_flag("--json", arguments.json, "print one JSON object");

  line->deflection = app->add_subcommand(
      "deflection", "cantilever clamped at x = 0, force F in -z at x = L (thesis 3.2.6)");
  AddModelOptions(line->deflection, line, Body::kBox);
  line->deflection->add_option("--force", arguments.force, "total end force F (N)")->required();
  line->deflection
      ->add_option("--ends", arguments.ends,
                   "faces: clamp the face x = 0 and load the face x = L (node-centred cubic); "
                   "layers: the first and last node layers (default: faces where possible)")
      ->check(CLI::IsMember({"faces", "layers"}));
  auto* reference =
      line->deflection
          ->add_option("--reference", arguments.reference,
                       "also solve the box by finite elements: calculix (C3D8I; needs ccx)")
          ->check(CLI::IsMember({"calculix"}));
  line->deflection
      ->add_option("--reference-elements", line->reference_elements,
                   "the reference's mesh NX NY NZ (default 10 x 10 across, >= 40 along x)")
      ->expected(3)
      ->check(CLI::Range(1, 1000000))
      ->needs(reference);
  line->deflection->add_flag("--json", arguments.json, "print one JSON object");

  line->sweep = app->add_subcommand(
      "poisson-sweep",
      "compression at several target nu: measured against theoretical nu(Q) (eMSM figs. 7-8); "
      "defaults: E 1e5 Pa, cubic 2 x 1 x 1 m at a = 1/12 m, random 3 x 1 x 1 m at l = 0.1 m");
  AddModelOptions(line->sweep, line, Body::kDefaultBox);
  line->sweep->add_option("--targets", arguments.targets, "target Poisson's ratios")
      ->capture_default_str();
  line->sweep->add_option("--strain", arguments.strain, "imposed compressive strain")
      ->capture_default_str();
  line->sweep->add_option("--plot", arguments.plot,
                          "write a plot of nu against Q to this PNG file");
  line->sweep->add_flag("--json", arguments.json, "print one JSON object");
}

void AddBuildCommand(CLI::App* app, CommandLine* line) {
  LabArguments& arguments = line->arguments;
  line->build = app->add_subcommand(
      "build", "build a calibrated model from a closed mesh: size, mass; save it or export VTK");
  AddModelOptions(line->build, line, Body::kMesh);
  line->build->add_option("--out", arguments.out,
                          "save the model to this file (msm_sim model format)");
  line->build->add_option("--vtk", arguments.vtk, "write the model at rest to this .vtu file");
  line->build->add_flag("--json", arguments.json, "print one JSON object");
}

void AddSlideCommand(CLI::App* app, CommandLine* line) {
  SlideArguments& slide_arguments = line->arguments.slide;
  CLI::App* slide = line->slide = app->add_subcommand(
      "slide", "a box of NX x NY x NZ nodes slides on the ground from v0 along +x (thesis 6.4)");
  slide->add_option("--nodes", line->slide_nodes, "nodes along x, y, z (element-corner lattice)")
      ->expected(3)
      ->required()
      ->check(CLI::Range(2, 1000));
  slide->add_option("--size", line->slide_size, "box size LX LY LZ (m)")->expected(3)->required();
  slide->add_option("--mass", slide_arguments.mass, "total mass (kg)")->required();
  slide->add_option("--v0", slide_arguments.v0, "initial speed along +x (m/s)")->required();
  slide->add_option("--mu", slide_arguments.mu, "Coulomb friction with the ground")->required();
  slide->add_option("--youngs", slide_arguments.youngs, "Young's modulus E (Pa)")
      ->capture_default_str();
  slide->add_option("--poisson", slide_arguments.poisson, "Poisson's ratio nu")
      ->capture_default_str();
  slide->add_flag("--json", line->arguments.json, "print one JSON object");
}
void AddMaterialCommand(CLI::App* app, CommandLine* line) {
  HardnessArguments& hardness = line->arguments.hardness;
  CLI::App* material = line->material = app->add_subcommand(
      "material",
      "Young's modulus from a Shore hardness (Gent's relation; the type 00 sphere relation "
      "for soft readings), with its validity range (docs/materials.md)");
  auto* shore_a = material->add_option("--shore-a", hardness.shore_a, "Shore A hardness, 10 to 90");
  auto* shore_00 =
      material->add_option("--shore-00", hardness.shore_00, "Shore 00 hardness, 10 to 98");
  shore_a->excludes(shore_00);
  shore_00->excludes(shore_a);
  material->add_option("--poisson", hardness.poisson,
                       "Poisson's ratio nu, in (-1, 0.5): also print the shear modulus");
  material->add_flag("--json", line->arguments.json, "print one JSON object");
}

}  // namespace

void AddStaticCommands(CLI::App* app, CommandLine* line) {
  AddExperimentCommands(app, line);
  AddBuildCommand(app, line);
  AddSlideCommand(app, line);
  AddMaterialCommand(app, line);
}

}  // namespace msm_sim::lab
