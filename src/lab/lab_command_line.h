#pragma once
// The pieces of msm_lab's command-line parser that its files share: lab_arguments.cpp (the
// parser and the model options), lab_static_arguments.cpp (the static commands, slide and
// material), lab_sphere_arguments.cpp (the commands that press a rigid sphere into a block) and
// lab_fit_arguments.cpp (fit's --tensile). Private to the lab library.

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "lab_arguments.h"

namespace msm_sim::lab {

// Which body a command accepts and which options it insists on.
enum class Body {
  kBox,           // --size, required
  kBoxOrMesh,     // --size or --mesh, one of them required
  kMesh,          // --mesh, required
  kDefaultBox,    // --size optional (poisson-sweep has defaults)
  kBlock,         // --size required, --model optional (cubic): indent
  kDefaultBlock,  // --size, --model, --youngs, --density optional (defaults): realtime, grip
  kFitBlock,      // --size (required with --indent); --model, --spacing, --poisson optional,
                  // no --youngs: fit
  kGraspObject,   // --size or --mesh or neither (the shape's own options), --model optional
};

// What CLI11 fills in besides LabArguments: vectors it checks the length of, copied into the
// arguments' Eigen vectors once parsed, and the commands, to ask which one was parsed.
struct CommandLine {
  LabArguments arguments;
  std::vector<double> size;
  std::vector<double> second_size;  // fit --size2
  std::vector<double> rotate;
  std::vector<int> slide_nodes;
  std::vector<int> reference_elements;  // deflection --reference-elements
  std::vector<double> slide_size;
  CLI::App* compression = nullptr;
  CLI::App* deflection = nullptr;
  CLI::App* sweep = nullptr;
  CLI::App* build = nullptr;
  CLI::App* slide = nullptr;
  CLI::App* realtime = nullptr;
  CLI::App* indent = nullptr;
  CLI::App* fit = nullptr;
  CLI::App* grip = nullptr;
  CLI::App* grasp = nullptr;
  CLI::App* material = nullptr;
  CLI::App* squeeze = nullptr;
};

/// Options describing the model, in the order --help lists them.
void AddModelOptions(CLI::App* command, CommandLine* line, Body body);

/// A finite number > 0 (or >= 0): CLI11's PositiveNumber would print its range up to DBL_MAX.
CLI::Validator Finite(bool zero_allowed);

/// The realtime, indent and fit commands.
void AddSphereCommands(CLI::App* app, CommandLine* line);

/// fit's --tensile and its options, after the --indent ones (lab_fit_arguments.cpp).
void AddTensileOptions(CLI::App* fit, CommandLine* line);

/// fit: one of --indent and --tensile, each with its own options; the reason when not, else "".
std::string FitOptionProblem(const CommandLine& line);

/// fit's defaults (see its help): nu 0.49. With neither --spacing nor --target-nodes, RunFit
/// chooses a spacing that resolves the contact (lab_fit_command.cpp).
void ApplyFitDefaults(CommandLine* line);

/// The compression, deflection, poisson-sweep, build, slide and material commands
/// (lab_static_arguments.cpp).
void AddStaticCommands(CLI::App* app, CommandLine* line);

/// The grip command (lab_grip_arguments.cpp).
void AddGripCommand(CLI::App* app, CommandLine* line);

/// The grasp command (lab_grasp_arguments.cpp).
void AddGraspCommand(CLI::App* app, CommandLine* line);

/// The squeeze command (lab_squeeze_arguments.cpp).
void AddSqueezeCommand(CLI::App* app, CommandLine* line);

/// grasp and squeeze (`command`): the shape's own options (--size, --radius, --length, --mesh)
/// agree with --shape; the reason when they do not, empty otherwise.
std::string GraspShapeProblem(const CommandLine& line, const std::string& command);

}  // namespace msm_sim::lab
