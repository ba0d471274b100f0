#pragma once
// A finite-element reference for the cantilever experiment: the same box solved by CalculiX
// (Debian's calculix-ccx, the `ccx` program) with C3D8I hexahedra, so that the lattice models'
// deflections can be compared with a converged continuum solution rather than Euler-Bernoulli
// alone (which ignores shear and the clamp's constraint of the Poisson contraction).

#include <string>
#include <vector>

namespace msm_sim::core {

/// The box [0, length] x [0, width] x [0, height], clamped on the face x = 0 (every degree of
/// freedom of that face's nodes fixed) and loaded in -z on the face x = length, meshed with a
/// regular grid of C3D8I (incompatible-mode) hexahedra. Linear elasticity, small strains.
struct CalculixCantilever {
  double length = 0.2;    ///< m, along x; finite and > 0
  double width = 0.05;    ///< m, along y; finite and > 0
  double height = 0.05;   ///< m, along z; finite and > 0
  double youngs = 0.0;    ///< Pa; finite and > 0
  double poisson = 0.25;  ///< in (-1, 0.5)
  /// N, the total load in -z on the end face, finite. It is spread as consistent nodal loads:
  /// each element face carries force * (its area / the face's area), shared equally by its four
  /// corner nodes (exact for a uniform traction on bilinear faces).
  double force = 0.0;
  int elements_x = 40;  ///< >= 1
  int elements_y = 10;  ///< >= 1
  int elements_z = 10;  ///< >= 1; at most kMaxCalculixElements elements in all
  /// The CalculiX program: a name looked up in PATH, or a path (a relative one is taken from the
  /// current directory).
  std::string executable = "ccx";
  /// s; > 0: ccx is killed and the run fails after this long. <= 0: no limit.
  double timeout_seconds = 0.0;
};

/// Elements above which a deck is refused: CalculiX factors the stiffness matrix directly, and its
/// time and memory grow faster than the element count (docs/design/free-face-bending.md), so a
/// mistyped count would take the machine rather than fail.
constexpr long kMaxCalculixElements = 50000;

struct CalculixProfileSample {
  double x = 0.0;           ///< m, from the clamped face
  double deflection = 0.0;  ///< m, mean -u_z of the nodes at this x (positive down)
};

struct CalculixCantileverResult {
  double end_face_deflection = 0.0;  ///< m, mean -u_z of the nodes of the face x = length
  /// One sample per node station along x, elements_x + 1 of them, from x = 0 (exactly 0) to
  /// x = length (end_face_deflection).
  std::vector<CalculixProfileSample> profile;
  double seconds = 0.0;  ///< wall-clock time of the ccx run
};

/// The CalculiX input deck (.inp) of the cantilever: nodes, C3D8I elements (CalculiX's node
/// order: the face z = z0 counter-clockwise seen from +z, then the face z = z1), the clamp, the
/// material, one linear static step with *CLOAD and a *NODE PRINT of U for every node (set NALL).
/// Node (i, j, k) of the grid has the number 1 + i + (nx + 1) (j + (ny + 1) k).
/// Throws std::invalid_argument for a box outside the preconditions above.
std::string CalculixCantileverDeck(const CalculixCantilever& box);

/// Writes the deck into a fresh directory under std::filesystem::temp_directory_path(), runs
/// `ccx -i cantilever` there (no shell; its output goes to a file), reads the displacements back
/// from the .dat file and removes the directory. Throws std::invalid_argument for a box outside
/// the preconditions, std::runtime_error when ccx cannot be started ("... install calculix-ccx
/// (scripts/install_dependencies.sh)"), fails (its last output line), times out or writes no
/// displacements; every message is one line.
CalculixCantileverResult RunCalculixCantilever(const CalculixCantilever& box);

}  // namespace msm_sim::core
