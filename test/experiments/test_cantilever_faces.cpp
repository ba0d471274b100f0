// Issue "Fidelity against FEM", must-show 1: the node-centred cubic eMSM cantilever clamped and
// loaded at its faces (CantileverEnds::kFaces on a lattice with face anchors at x = 0) against
// CalculiX on the same box: 0.2 x 0.05 x 0.05 m, E = 120 kPa, 0.05 N in -z on the face x = L,
// C3D8I 40 x 10 x 10 with the face x = 0 clamped. Nothing is hard-coded: both sides are solved
// here. Needs calculix-ccx (scripts/install_dependencies.sh).
//
// What holds (docs/physics.md §2.1 "Face anchors" and "Free faces in bending"): the anchors make
// the first layer a bulk layer. Without the free faces' bending correction the lattice's bending
// stiffness is low by (2/3)/n^2 + (1/3)(10/n^2 - 12/n^3) (n cells across; its outermost springs
// sit half a cell inside the free faces), +20..+24 % at 4 across and +6 % at 8. With it
// (NodeCentredSurfaceOptions::free_face_bending, off by default in the library, on here unless a
// Case says otherwise) the end face is within 3 % of CalculiX at 4, 8 and 16 across, except nu = 0
// at 4 across: +3.4 %.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "msm_sim/experiments/calculix_reference.h"
#include "msm_sim/experiments/cantilever_experiment.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/mechanics/force_evaluator.h"
#include "msm_sim/model/model_file.h"

namespace msm_sim::core {
namespace {

constexpr double kLength = 0.2, kSide = 0.05, kYoungs = 120e3, kForce = 0.05;

// The finite-element reference, solved once per nu (about a second each).
const CalculixCantileverResult& Reference(double poisson) {
  static std::map<double, CalculixCantileverResult> solved;
  auto found = solved.find(poisson);
  if (found != solved.end()) return found->second;
  CalculixCantilever box;
  box.length = kLength;
  box.width = kSide;
  box.height = kSide;
  box.youngs = kYoungs;
  box.poisson = poisson;
  box.force = kForce;
  box.timeout_seconds = 120.0;
  return solved.emplace(poisson, RunCalculixCantilever(box)).first->second;
}

Model AnchoredBar(double poisson, int cells_across, bool free_face_bending,
                  double surface_dispersion = 1.0) {
  CubicLatticeOptions options;
  options.surface.free_face_bending = free_face_bending;
  options.surface.surface_dispersion = surface_dispersion;
  options.size = Eigen::Vector3d(kLength, kSide, kSide);
  options.lattice.spacing = kSide / cells_across;
  options.surface.anchored_planes = {AnchoredPlane{}};  // the face x = 0
  return BuildCubicLattice(Material::FromYoungsPoisson(kYoungs, poisson, 1000.0), options);
}

// The lattice profile interpolated linearly at x (extrapolated past its last sample).
double ProfileAt(const std::vector<DeflectionSample>& profile, double x) {
  std::size_t i = 1;
  while (i + 1 < profile.size() && profile[i].x < x) ++i;
  const DeflectionSample& lo = profile[i - 1];
  const DeflectionSample& hi = profile[i];
  return lo.deflection + (hi.deflection - lo.deflection) * (x - lo.x) / (hi.x - lo.x);
}

struct Case {
  double poisson;
  int cells_across;
  bool free_face_bending = true;
  double surface_dispersion = 1.0;  // NodeCentredSurfaceOptions::surface_dispersion
};

struct Comparison {
  double end_error = 0.0;      // end_face_deflection / CalculiX - 1
  double profile_error = 0.0;  // largest |lattice - CalculiX| over the stations / CalculiX end
  double profile_x = 0.0;      // m, where
};

Comparison CompareWithCalculix(const Case& c) {
  const Model model =
      AnchoredBar(c.poisson, c.cells_across, c.free_face_bending, c.surface_dispersion);
  CantileverExperimentOptions options;
  options.body_size = Eigen::Vector3d(kLength, kSide, kSide);
  options.total_force = kForce;
  options.ends = CantileverEnds::kFaces;
  const CantileverExperimentResult lattice = RunCantileverExperiment(model, options);
  EXPECT_TRUE(lattice.solver.converged) << lattice.solver.message;
  EXPECT_DOUBLE_EQ(lattice.beam_length, kLength);
  const int n = c.cells_across;  // one anchor per edge spring, one per pair of diagonals
  EXPECT_EQ(lattice.clamped_nodes, n * n + 2 * n * (n + 1));
  const CalculixCantileverResult& fem = Reference(c.poisson);
  Comparison result;
  result.end_error = lattice.end_face_deflection / fem.end_face_deflection - 1.0;
  for (const CalculixProfileSample& station : fem.profile) {
    const double error =
        (ProfileAt(lattice.profile, station.x) - station.deflection) / fem.end_face_deflection;
    if (std::abs(error) > std::abs(result.profile_error)) {
      result.profile_error = error;
      result.profile_x = station.x;
    }
  }
  std::printf(
      "  nu %.2f, %2d across%s%s: end face %.5f mm, CalculiX %.5f mm (%+.2f %%); old-style tip "
      "%.5f mm; profile worst %+.2f %% of the end's at x = %.4f m\n",
      c.poisson, n, c.free_face_bending ? "" : " (uncorrected)",
      c.surface_dispersion < 1.0 ? " (softer outer layer)" : "", 1e3 * lattice.end_face_deflection,
      1e3 * fem.end_face_deflection, 100.0 * result.end_error, 1e3 * lattice.tip_deflection,
      100.0 * result.profile_error, result.profile_x);
  return result;
}

class CantileverFaces : public ::testing::TestWithParam<double> {};

// 16 cells across (16,384 lattice nodes; nu = 0.49 is left out: 79 s).
TEST_P(CantileverFaces, WithinThreePercentOfCalculixAtSixteenCellsAcross) {
  const Comparison fine = CompareWithCalculix({GetParam(), 16});
  EXPECT_LT(std::abs(fine.end_error), 0.03);
  EXPECT_LT(std::abs(fine.profile_error), 0.03) << "at x = " << fine.profile_x;
}

INSTANTIATE_TEST_SUITE_P(IssueBox, CantileverFaces, ::testing::Values(0.0, 0.25, 0.4));

class CantileverFacesCoarse : public ::testing::TestWithParam<double> {};

// The issue's must-show at 4 and 8 cells across (measured: 4 across -1.1 / +0.9 / +0.0 / -1.9 %,
// 8 across +0.1 / +0.8 / +0.8 / +0.6 % at nu 0 / 0.25 / 0.4 / 0.49; before the correction +21..24 %
// and +6 %). The profile's worst station is the end's own, or within 0.3 % of it.
TEST_P(CantileverFacesCoarse, WithinThreePercentOfCalculixAtFourAndEightCellsAcross) {
  for (const int n : {4, 8}) {
    const Comparison c = CompareWithCalculix({GetParam(), n});
    EXPECT_LT(std::abs(c.end_error), 0.03) << n << " across";
    EXPECT_LT(std::abs(c.profile_error), 0.03) << n << " across, at x = " << c.profile_x;
  }
}

// Without the correction the lattice is softer than CalculiX by what the deficit predicts,
// 1 / (1 - deficit) - 1 (+23.1 % at 4 across, +5.8 % at 8), within 3 points (measured +20.3 to
// +24.0 % and +5.8 to +6.5 %): the deficit, not the clamp or the load, is what was missing.
TEST_P(CantileverFacesCoarse, WithoutTheCorrectionTheErrorIsTheBendingDeficit) {
  for (const int n : {4, 8}) {
    const Comparison c = CompareWithCalculix({GetParam(), n, false});
    const double deficit = FreeFaceBendingDeficit(n);
    EXPECT_NEAR(c.end_error, 1.0 / (1.0 - deficit) - 1.0, 0.03) << n << " across";
  }
}

INSTANTIATE_TEST_SUITE_P(IssueBox, CantileverFacesCoarse, ::testing::Values(0.0, 0.25, 0.4, 0.49));

// The softer outer layer (NodeCentredSurfaceOptions::surface_dispersion = 0.5, docs/physics.md §7)
// where it is recommended, nu = 0.49: bending stresses peak in the outer layer, whose bulk it
// halves, yet 8 cells across still bend within 3 % of CalculiX (measured +1.2 %, +0.6 % without).
TEST(CantileverFacesSofterOuterLayer, WithinThreePercentOfCalculixAtEightCellsAcrossAtNu049) {
  for (const double share : {0.5, 0.25}) {
    const Comparison c = CompareWithCalculix({0.49, 8, true, share});
    EXPECT_LT(std::abs(c.end_error), 0.03) << "share " << share;
    EXPECT_LT(std::abs(c.profile_error), 0.03) << "share " << share << ", at x = " << c.profile_x;
  }
}

// The derivation behind the anchors (docs/physics.md §2.1 "Face anchors"): with the anchors moved
// by the same uniform strain as the lattice, a node of the first layer at least two cells from
// the free faces feels exactly the force, direct and dispersed, of the node with the same y and z
// in the middle of the bar (nearer, its neighbours carry the free faces' mirrored half-springs);
// at the free end x = L, whose mirrored half-springs restore only the stiffness tensor, it does
// not.
TEST(FaceAnchors, FirstLayerFeelsWhatTheMiddleFeelsUnderUniformStrain) {
  const Model model = AnchoredBar(0.4, 8, true);
  Eigen::Matrix3d strain;
  strain << 0.010, 0.002, -0.003, 0.002, -0.004, 0.001, -0.003, 0.001, 0.006;
  const Eigen::Matrix3Xd& rest = model.rest_positions();
  const Eigen::Matrix3Xd positions = rest + strain * rest;
  Eigen::Matrix3Xd forces = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
  ForceEvaluator(model).AccumulateForces(positions, &forces);
  const double a = kSide / 8, scale = model.material().youngs_modulus() * a * a * 0.01;
  // Nodes by x, y, z in half cells (odd numbers: cell centres).
  std::map<std::tuple<long, long, long>, int> at;
  for (int i = 0; i < model.num_nodes(); ++i) {
    at[{std::lround(rest(0, i) / (0.5 * a)), std::lround(rest(1, i) / (0.5 * a)),
        std::lround(rest(2, i) / (0.5 * a))}] = i;
  }
  const long first = 1, middle = std::lround(kLength / a) + 1;
  const long last = std::lround(2 * kLength / a) - 1;
  int compared = 0, unlike_at_free_end = 0;
  for (long y = 5; y <= 11; y += 2) {
    for (long z = 5; z <= 11; z += 2) {
      const Eigen::Vector3d f_middle = forces.col(at.at({middle, y, z}));
      const Eigen::Vector3d f_first = forces.col(at.at({first, y, z}));
      const Eigen::Vector3d f_last = forces.col(at.at({last, y, z}));
      EXPECT_LT((f_first - f_middle).norm(), 1e-9 * scale) << "y " << y << " z " << z;
      if ((f_last - f_middle).norm() > 1e-3 * scale) ++unlike_at_free_end;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 16);
  EXPECT_EQ(unlike_at_free_end, 16);
}

// (Without the free faces' bending correction, which divides the node end's weight by the
// spring's stiffness factor.)
TEST(FaceAnchors, AnchorsLieOnTheirPlaneAndDisperseNothing) {
  const Model model = AnchoredBar(0.4, 4, false);
  const std::vector<NodeIndex> anchors = AnchorNodes(model, AnchoredPlane{});
  // One per edge spring, one per pair of face-diagonal springs meeting on the face.
  EXPECT_EQ(static_cast<int>(anchors.size()), 16 + 2 * 4 * 5);
  std::vector<bool> is_anchor(model.num_nodes(), false);
  for (NodeIndex i : anchors) is_anchor[i] = true;
  int anchor_springs = 0;
  for (int s = 0; s < model.num_springs(); ++s) {
    const int na = model.spring_node_a()[s], nb = model.spring_node_b()[s];
    if (!is_anchor[na] && !is_anchor[nb]) continue;
    ++anchor_springs;
    EXPECT_EQ(is_anchor[na] ? model.dispersion_weight_a()[s] : model.dispersion_weight_b()[s], 0.0);
    EXPECT_EQ(is_anchor[na] ? model.dispersion_weight_b()[s] : model.dispersion_weight_a()[s], 2.0);
  }
  EXPECT_EQ(anchor_springs, 16 * 5);  // every first-layer node: 1 edge + 4 face-diagonal springs
}

// Model files accept the anchors' zero dispersion weights (format version 1, weights >= 0).
TEST(FaceAnchors, AnchoredModelRoundTripsThroughAModelFile) {
  const Model model = AnchoredBar(0.4, 4, true);
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("msm_anchored_" + std::to_string(::getpid()) + ".msm"))
                               .string();
  SaveModel(model, path);
  const Model loaded = LoadModel(path);
  std::filesystem::remove(path);
  EXPECT_EQ(loaded.num_nodes(), model.num_nodes());
  EXPECT_EQ(loaded.dispersion_weight_a(), model.dispersion_weight_a());
  EXPECT_EQ(loaded.dispersion_weight_b(), model.dispersion_weight_b());
  EXPECT_EQ(AnchorNodes(loaded, AnchoredPlane{}), AnchorNodes(model, AnchoredPlane{}));
}

}  // namespace
}  // namespace msm_sim::core
