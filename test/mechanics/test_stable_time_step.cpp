// The explicit step against the spectral radius of position Verlet's one-step map, formed
// densely from K and the dampers' C on small blocks.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/mechanics/force_evaluator.h"
#include "msm_sim/mechanics/stable_time_step.h"
#include "msm_sim/model/model_builder.h"

namespace msm_sim::core {
namespace {

// Dense K at rest (through ApplyStiffness, column by column).
Eigen::MatrixXd DenseStiffness(const Model& model) {
  ForceEvaluator evaluator(model);
  evaluator.Linearize(model.rest_positions());
  const int n = 3 * model.num_nodes();
  Eigen::MatrixXd k(n, n);
  for (int column = 0; column < n; ++column) {
    Eigen::Matrix3Xd unit = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
    unit(column % 3, column / 3) = 1.0;
    Eigen::Matrix3Xd product;
    evaluator.ApplyStiffness(unit, &product);
    k.col(column) = Eigen::Map<const Eigen::VectorXd>(product.data(), n);
  }
  return k;
}

// Dense C = beta sum k (e_b - e_a)(e_b - e_a)^T (x) u u^T: each spring's damper beta k (v_b -
// v_a).u along u, written out here independently of the library.
Eigen::MatrixXd DenseDampers(const Model& model, double beta) {
  const int n = 3 * model.num_nodes();
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(n, n);
  for (int s = 0; s < model.num_springs(); ++s) {
    const int a = model.spring_node_a()[s], b = model.spring_node_b()[s];
    const Eigen::Vector3d u =
        (model.rest_positions().col(b) - model.rest_positions().col(a)).normalized();
    const Eigen::Matrix3d block = beta * model.spring_stiffness()[s] * u * u.transpose();
    c.block<3, 3>(3 * a, 3 * a) += block;
    c.block<3, 3>(3 * b, 3 * b) += block;
    c.block<3, 3>(3 * a, 3 * b) -= block;
    c.block<3, 3>(3 * b, 3 * a) -= block;
  }
  return c;
}

// Spectral radius of the map (x, v) -> (x', v') of one substep: drift h/2, kick with the forces
// -K x - C v at the drifted positions and the start velocities, drift h/2 (World::Substep), for
// the nodes not `held`. Holding some removes the rigid-body modes: their eigenvalue 1 is
// defective (x grows linearly at constant v) and rounding would put it a little above 1.
double SpectralRadiusHolding(const Model& model, const Eigen::MatrixXd& full_k,
                             const Eigen::MatrixXd& full_c, double h,
                             const std::vector<bool>& held) {
  std::vector<int> free;
  for (int dof = 0; dof < full_k.rows(); ++dof) {
    if (!held[dof / 3]) free.push_back(dof);
  }
  const int n = static_cast<int>(free.size());
  Eigen::MatrixXd k(n, n), c(n, n);
  Eigen::VectorXd inverse_mass(n);
  for (int i = 0; i < n; ++i) {
    inverse_mass[i] = 1.0 / model.masses()[free[i] / 3];
    for (int j = 0; j < n; ++j) {
      k(i, j) = full_k(free[i], free[j]);
      c(i, j) = full_c(free[i], free[j]);
    }
  }
  const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXd drift = Eigen::MatrixXd::Identity(2 * n, 2 * n);
  drift.topRightCorner(n, n) = 0.5 * h * identity;
  Eigen::MatrixXd kick = Eigen::MatrixXd::Identity(2 * n, 2 * n);
  kick.bottomLeftCorner(n, n) = -h * inverse_mass.asDiagonal() * k;
  kick.bottomRightCorner(n, n) = identity - h * inverse_mass.asDiagonal() * c;
  const Eigen::MatrixXd map = drift * kick * drift;
  return Eigen::EigenSolver<Eigen::MatrixXd>(map, false).eigenvalues().cwiseAbs().maxCoeff();
}

// The same with the bottom layer's nodes held (or none).
double SpectralRadius(const Model& model, const Eigen::MatrixXd& full_k,
                      const Eigen::MatrixXd& full_c, double h, bool hold_bottom = true) {
  const double bottom = model.rest_positions().row(2).minCoeff();
  std::vector<bool> held(model.num_nodes(), false);
  for (int i = 0; i < model.num_nodes(); ++i) {
    held[i] = hold_bottom && model.rest_positions()(2, i) <= bottom + 1e-9;
  }
  return SpectralRadiusHolding(model, full_k, full_c, h, held);
}

// M^-1/2 A M^-1/2 for a dense 3N x 3N matrix A of the whole block, symmetrised.
Eigen::MatrixXd MassScaledDense(const Model& model, const Eigen::MatrixXd& a) {
  Eigen::VectorXd inverse_sqrt_mass(a.rows());
  for (int dof = 0; dof < a.rows(); ++dof) {
    inverse_sqrt_mass[dof] = 1.0 / std::sqrt(model.masses()[dof / 3]);
  }
  const Eigen::MatrixXd symmetric = 0.5 * (a + a.transpose());
  return inverse_sqrt_mass.asDiagonal() * symmetric * inverse_sqrt_mass.asDiagonal();
}

double LargestEigenvalue(const Eigen::MatrixXd& symmetric) {
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(symmetric, Eigen::EigenvaluesOnly)
      .eigenvalues()
      .maxCoeff();
}

Model SmallBlock(double poisson) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d(0.2, 0.15, 0.1);
  lattice_options.lattice.spacing = 0.05;  // 5 x 4 x 3 nodes
  return BuildCubicLattice(Material::FromYoungsPoisson(1e5, poisson, 1000.0), lattice_options);
}

class StableTimeStepDampers : public ::testing::TestWithParam<double> {};

TEST_P(StableTimeStepDampers, TheStepIsStableWithStrongDampers) {
  const double poisson = GetParam();
  const Model model = SmallBlock(poisson);
  const Eigen::MatrixXd k = DenseStiffness(model);
  StableTimeStepOptions options;
  options.safety = 1.0;
  const double undamped = StableTimeStep(model, options);
  // Dampers of ratio zeta = 2 at the highest frequency: the damped limit is far below 2 / omega.
  options.damping_beta = 4.0 * undamped / 2.0;
  const double h = StableTimeStep(model, options);
  const Eigen::MatrixXd c = DenseDampers(model, options.damping_beta);
  // At the limit itself the highest mode sits on the unit circle (a repeated eigenvalue -1,
  // which rounding of the dense eigensolver moves by ~1e-8); just inside it, strictly stable.
  const double radius = SpectralRadius(model, k, c, h);
  EXPECT_LE(radius, 1.0 + 1e-7) << "nu " << poisson << " radius - 1 = " << radius - 1.0;
  EXPECT_LE(SpectralRadius(model, k, c, 0.98 * h), 1.0 + 1e-12) << "nu " << poisson;
  // The limit Rayleigh damping beta K would give, which the dampers beat where the dispersion
  // stiffens K but not C.
  const double omega = 2.0 / undamped;
  const double zeta = 0.5 * options.damping_beta * omega;
  const double rayleigh = (2.0 / omega) * (std::sqrt(1.0 + zeta * zeta) - zeta);
  // The step is the sharp limit of the quadratic forms: at it the largest eigenvalue of
  // M^-1/2 ((h^2 / 4) K + (h / 2) C) M^-1/2 is 1 (stable while at most 1, the header's
  // condition), which the sum of K's and C's largest (the sufficient bound) overstates.
  EXPECT_NEAR(LargestEigenvalue(MassScaledDense(model, 0.25 * h * h * k + 0.5 * h * c)), 1.0, 1e-4)
      << "nu " << poisson;
  const double a = 0.25 * LargestEigenvalue(MassScaledDense(model, k));
  const double b = 0.5 * LargestEigenvalue(MassScaledDense(model, c));
  const double sufficient = 2.0 / (b + std::sqrt(b * b + 4.0 * a));
  std::printf("  nu %.2f: damped step %.4g s, the sufficient bound %.4g s (x%.3f)\n", poisson, h,
              sufficient, h / sufficient);
  if (poisson == 0.25) {
    EXPECT_NEAR(h / sufficient, 1.0, 1e-4);  // C = beta K: the two bounds coincide
    // Plain MSM: C = beta K exactly, the bound is sharp: a little longer is unstable (for the
    // free block, whose highest mode the step is computed for).
    EXPECT_NEAR(h / rayleigh, 1.0, 0.01);
    EXPECT_GT(SpectralRadius(model, k, c, 1.05 * h, false), 1.0 + 1e-3);
  } else {
    EXPECT_GT(h, 1.5 * rayleigh) << "nu " << poisson;
    EXPECT_GT(h, 1.005 * sufficient) << "nu " << poisson;  // K's top modes are C's soft ones
  }
}

INSTANTIATE_TEST_SUITE_P(PlainAndDispersed, StableTimeStepDampers,
                         ::testing::Values(0.25, 0.45, 0.49));

// Fixed nodes do not limit the step: a block whose base face is anchored (anchors of a token
// 1e-6 of a cell's mass, AnchoredPlane) has, counting the anchors, a step a thousand times too
// short; with them fixed, the step of the free nodes, which the Verlet map with the anchors held
// confirms: stable just inside it, unstable a little beyond.
TEST(StableTimeStep, FixedNodesAreLeftOut) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d(0.2, 0.15, 0.1);
  lattice_options.lattice.spacing = 0.05;
  lattice_options.surface.anchored_planes = {
      AnchoredPlane{Eigen::Vector3d::Zero(), -Eigen::Vector3d::UnitZ()}};
  const Model model =
      BuildCubicLattice(Material::FromYoungsPoisson(1e5, 0.45, 1000.0), lattice_options);
  const std::vector<NodeIndex> anchors =
      AnchorNodes(model, lattice_options.surface.anchored_planes[0]);
  ASSERT_EQ(anchors.size(), 4u * 3u + 4u * 4u + 3u * 5u);  // A springs; diagonals per pair
  StableTimeStepOptions options;
  options.safety = 1.0;
  const double counting_anchors = StableTimeStep(model, options);
  options.fixed_nodes = anchors;
  const double h = StableTimeStep(model, options);
  EXPECT_GT(h, 300.0 * counting_anchors);
  std::vector<bool> held(model.num_nodes(), false);
  for (const NodeIndex anchor : anchors) held[anchor] = true;
  const Eigen::MatrixXd k = DenseStiffness(model);
  const Eigen::MatrixXd c = DenseDampers(model, 0.0);
  EXPECT_LE(SpectralRadiusHolding(model, k, c, 0.98 * h, held), 1.0 + 1e-9);
  EXPECT_GT(SpectralRadiusHolding(model, k, c, 1.05 * h, held), 1.0 + 1e-3);

  // Every node fixed: nothing moves, nothing limits the step. A node the model does not have is
  // refused.
  options.fixed_nodes.resize(model.num_nodes());
  for (int i = 0; i < model.num_nodes(); ++i) options.fixed_nodes[i] = i;
  EXPECT_EQ(StableTimeStep(model, options), std::numeric_limits<double>::infinity());
  options.fixed_nodes = {model.num_nodes()};
  EXPECT_THROW(StableTimeStep(model, options), std::invalid_argument);
}

// What sets the explicit step near nu = 1/2 (docs/physics.md section 7, "the surface layer"): on
// a node-centred block the highest mode lives in the outer node layer, whose one-sided
// dispersion stars respond to the shortest waves as interior stars do not. With that layer held,
// the undamped step of the interior is 1.66 times longer at nu = 0.49 (1.64 on the realtime
// block, 10 x 10 x 5 cm); at nu = 1/4 (no dispersion) the layer costs little (1.04).
TEST(StableTimeStep, AtNuNearOneHalfTheSurfaceLayerSetsTheStep) {
  const Eigen::Vector3d size(0.06, 0.06, 0.03);
  const double spacing = 0.005;  // 12 x 12 x 6 nodes, 544 of them in the outer layer
  for (const double poisson : {0.25, 0.49}) {
    CubicLatticeOptions lattice_options;
    lattice_options.size = size;
    lattice_options.lattice.spacing = spacing;
    const Model model =
        BuildCubicLattice(Material::FromYoungsPoisson(2e5, poisson, 1100.0), lattice_options);
    StableTimeStepOptions options;
    options.safety = 1.0;
    const double whole = StableTimeStep(model, options);
    for (int i = 0; i < model.num_nodes(); ++i) {
      const Eigen::Array3d x = model.rest_positions().col(i).array();
      if ((x < spacing).any() || (x > size.array() - spacing).any()) {
        options.fixed_nodes.push_back(i);
      }
    }
    ASSERT_EQ(options.fixed_nodes.size(), 12u * 12u * 6u - 10u * 10u * 4u);
    const double interior = StableTimeStep(model, options);
    std::printf("  nu %.2f: step %.1f us, with the outer layer held %.1f us (x%.2f)\n", poisson,
                1e6 * whole, 1e6 * interior, interior / whole);
    if (poisson == 0.25) {
      EXPECT_LT(interior / whole, 1.1);
    } else {
      EXPECT_GT(interior / whole, 1.4);
    }
  }
}

// The remedy of docs/physics.md §7 "A softer outer layer": the outer layer keeping half its eMSM
// bulk (the rest moved one layer in) lengthens the step at nu = 0.49, short of what holding the
// layer gives, since the layer beneath now carries more bulk.
TEST(StableTimeStep, ASofterOuterLayerLengthensTheStepAtNuNearOneHalf) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d(0.06, 0.06, 0.03);
  lattice_options.lattice.spacing = 0.005;
  const Material rubber = Material::FromYoungsPoisson(2e5, 0.49, 1100.0);
  StableTimeStepOptions options;
  options.safety = 1.0;
  const double plain = StableTimeStep(BuildCubicLattice(rubber, lattice_options), options);
  lattice_options.surface.surface_dispersion = 0.5;
  const double softer = StableTimeStep(BuildCubicLattice(rubber, lattice_options), options);
  lattice_options.surface.surface_dispersion = 0.25;
  const double quarter = StableTimeStep(BuildCubicLattice(rubber, lattice_options), options);
  std::printf(
      "  nu 0.49: step %.1f us, with the outer layer at half its bulk %.1f us (x%.2f), at a "
      "quarter %.1f us (x%.2f)\n",
      1e6 * plain, 1e6 * softer, softer / plain, 1e6 * quarter, quarter / plain);
  EXPECT_GT(softer / plain, 1.25);
  // A smaller share gains less and less: the layer beneath, carrying more bulk, takes over.
  EXPECT_GT(quarter / softer, 1.02);
  EXPECT_LT(quarter / plain, 1.66);  // the held layer's gain (the test above)
}

// One spring (k = 100 N/m, L0 = 1 m) between unit masses: omega_max^2 = 2 k times the law's
// stiffening, so the square of the step's ratio to the linear law's is that stiffening.
double TwoMassStep(SpringLaw law, const PowerSpringLaw& power,
                   const StableTimeStepOptions& options) {
  ModelBuilder builder(Material::FromYoungsPoisson(1e4, 0.25, 1000.0));
  builder.AddNode({0, 0, 0}, 1.0);
  builder.AddNode({1, 0, 0}, 1.0);
  builder.AddSpring(0, 1, 100.0);
  builder.SetSpringLaw(law, power);
  return StableTimeStep(builder.Build(1.0, 1.0), options);
}

TEST(StableTimeStep, PowerLawStepHoldsForItsTangentFromMinCompressionToMaxStretch) {
  StableTimeStepOptions options;
  options.min_compression = 0.7;
  options.max_stretch = 2.0;
  const double linear = TwoMassStep(SpringLaw::kLinear, {}, options);
  ASSERT_TRUE(std::isfinite(linear));
  EXPECT_NEAR(TwoMassStep(SpringLaw::kPower, {1.0, 0.0}, options), linear, 1e-12 * linear);
  const double carrier = TwoMassStep(SpringLaw::kNonlinear, {}, options);
  EXPECT_NEAR(TwoMassStep(SpringLaw::kPower, {-1.0, 0.0}, options), carrier, 1e-12 * carrier);
  const double c = options.min_compression, stretch = options.max_stretch;
  const double far = std::max(1.0 - c, stretch - 1.0);
  for (const PowerSpringLaw law : {PowerSpringLaw{-4.54, 0.116}, PowerSpringLaw{-2.5, 0.0},
                                   PowerSpringLaw{0.5, 0.3}, PowerSpringLaw{2.0, 0.5}}) {
    SCOPED_TRACE(law.alpha);
    const double ratio = linear / TwoMassStep(SpringLaw::kPower, law, options);
    const double stiffening = ratio * ratio;
    // The largest tangent over k on [c, S], sampled.
    double largest = 0.0;
    for (int i = 0; i <= 1000; ++i) {
      largest = std::max(largest, law.TangentStiffness(1.0, 1.0, c + (stretch - c) * i / 1000.0));
    }
    EXPECT_GE(stiffening, largest * (1.0 - 1e-9));                       // never too long a step
    EXPECT_LE(stiffening, largest + 3.0 * law.beta * far * far + 1e-9);  // nor needlessly short
    // Exact where both terms peak at the same end (beta = 0, or alpha >= 1 with S - 1 > 1 - c).
    if (law.beta == 0.0 || law.alpha >= 1.0) {
      EXPECT_NEAR(stiffening, largest, 1e-9 * largest);
    }
  }
  options.max_stretch = 0.9;
  EXPECT_THROW(TwoMassStep(SpringLaw::kPower, {-2.0, 0.1}, options), std::invalid_argument);
}

}  // namespace
}  // namespace msm_sim::core
