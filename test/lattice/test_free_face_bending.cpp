// The free faces' bending correction of node-centred cubic boxes (src/lattice/free_face_bending.h,
// docs/physics.md §2.1 "Free faces in bending"). The cantilever against CalculiX is in
// test/experiments/test_cantilever_faces.cpp.
#include "lattice/free_face_bending.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "msm_sim/lattice/cubic_lattice_builder.h"

namespace msm_sim::core {
namespace {

using lattice::DiagonalIncrementRatio;
using lattice::FreeFaceBending;

Model Box(double poisson, const Eigen::Vector3i& cells, bool correct, double angle = 0.0) {
  CubicLatticeOptions options;
  options.lattice.spacing = 0.01;
  options.size = options.lattice.spacing * cells.cast<double>();
  options.surface.free_face_bending = correct;
  options.lattice.rotation_axis = Eigen::Vector3d(0.2, 0.9, -0.4);
  options.lattice.rotation_angle = angle;
  return BuildCubicLattice(Material::FromYoungsPoisson(1e5, poisson, 1000.0), options);
}

Eigen::Vector3d Direction(const Model& model, int s) {
  const auto& x = model.rest_positions();
  return (x.col(model.spring_node_b()[s]) - x.col(model.spring_node_a()[s])).normalized();
}

// The springs' share of C_1111 I_y in a slice one cell long: sum k L0^2 u_x^4 z_mid^2 over the
// springs that start (lower x end) in the middle layer of cells, z_mid the spring's midpoint
// height from the box's mid-plane. Under the bending strain eps_xx = kappa z a spring stores
// (1/2) k (L0 u_x^2 kappa z_mid)^2: this sum is twice that energy per kappa^2.
double SliceBendingSum(const Model& model, double slice_x, double spacing, double mid_z) {
  const auto& x = model.rest_positions();
  double sum = 0.0;
  for (int s = 0; s < model.num_springs(); ++s) {
    const Eigen::Vector3d a = x.col(model.spring_node_a()[s]);
    const Eigen::Vector3d b = x.col(model.spring_node_b()[s]);
    if (std::abs(std::min(a.x(), b.x()) - slice_x) > 0.25 * spacing) continue;
    const double ux = Direction(model, s).x();
    const double z = 0.5 * (a.z() + b.z()) - mid_z;
    sum += model.spring_stiffness()[s] * std::pow(model.spring_rest_length()[s], 2) *
           std::pow(ux, 4) * z * z;
  }
  return sum;
}

// The closed form of the deficit against the lattice itself: the midpoint sums of an uncorrected
// box n cells thick, over the continuum's C_1111 W H^3 / 12 per cell of length (C_1111 = 3 mu
// at nu = 1/4, where the springs are the whole stiffness).
TEST(FreeFaceBending, DeficitIsTheUncorrectedLatticesMidpointSum) {
  for (const int n : {4, 5, 8, 11}) {
    const Model model = Box(0.25, Eigen::Vector3i(9, n, n), false);
    const double a = 0.01, h = n * a;
    const double mu = model.material().shear_modulus();
    const double continuum = 3.0 * mu * h * h * h * h / 12.0 * a;
    const double lattice = SliceBendingSum(model, 4.5 * a, a, 0.5 * h);
    EXPECT_NEAR(lattice / continuum, 1.0 - FreeFaceBendingDeficit(n), 1e-12) << n << " across";
  }
}

// The layer modulus sensitivity at three points worked out by hand: at nu = 0 the dispersion
// cancels the direct springs' lateral coupling and the in-layer springs' 2 mu alpha over E = 2 mu
// give 1; at nu = 1/4 (no dispersion, C = mu [[3,1,1],[1,3,1],[1,1,3]]) 0.65; it tends to 1/2 as
// nu -> 1/2, which keeps alpha below 1/2 at 4 cells across.
TEST(FreeFaceBending, AddedLayerSpringsCarryNoLateralStressUnderUniaxialStress) {
  // The springs lying in a layer normal to y, per cell of a lattice with spacing a and kappa =
  // mu a: A springs along x and z (k L^2 = mu a^3), B springs (1, 0, +-1) (k L^2 = 2 mu a^3),
  // scaled by alpha_A and alpha_B. Their stress under the body's uniaxial-stress strain
  // diag(1, -nu, -nu) eps: C_ijkl eps_kl with C = sum alpha k L^2 u u u u / a^3.
  for (const double poisson : {-0.5, 0.0, 0.25, 0.45, 0.49}) {
    const double mu = 1.0, alpha_a = 0.3, alpha_b = alpha_a * DiagonalIncrementRatio(poisson);
    const Eigen::Vector3d strain(1.0, -poisson, -poisson);  // eps = 1
    Eigen::Vector3d stress = Eigen::Vector3d::Zero();
    const auto add = [&](const Eigen::Vector3d& d, double k_l2, double alpha) {
      const Eigen::Vector3d u = d.normalized();
      const double stretch = u.cwiseProduct(u).dot(strain);  // u . eps u
      stress += alpha * k_l2 * stretch * u.cwiseProduct(u);
    };
    add({1, 0, 0}, mu, alpha_a);
    add({0, 0, 1}, mu, alpha_a);
    add({1, 0, 1}, 2.0 * mu, alpha_b);
    add({1, 0, -1}, 2.0 * mu, alpha_b);
    EXPECT_NEAR(stress.z(), 0.0, 1e-14) << poisson;
    EXPECT_NEAR(stress.y(), 0.0, 1e-14) << poisson;
    const double youngs = 2.0 * mu * (1.0 + poisson);
    EXPECT_NEAR(stress.x(), 0.5 * alpha_a * youngs, 1e-14) << poisson;
  }
}

// The correction moves stiffness from the interior layers to the outer ones without changing
// what a homogeneous strain sees: the block's total stiffness tensor sum k L0^2 u (x) u (x) u (x) u
// is the uncorrected one's, and so is every spring's v k at both ends (the eMSM dispersion).
TEST(FreeFaceBending, KeepsTheStiffnessTensorAndTheDispersion) {
  for (const double poisson : {-0.5, 0.25, 0.49}) {
    const Model plain = Box(poisson, Eigen::Vector3i(12, 5, 4), false);
    const Model corrected = Box(poisson, Eigen::Vector3i(12, 5, 4), true);
    ASSERT_EQ(plain.num_springs(), corrected.num_springs());
    std::array<double, 81> tensor_plain{}, tensor_corrected{};
    double largest_change = 0.0;
    for (int s = 0; s < plain.num_springs(); ++s) {
      const Eigen::Vector3d u = Direction(plain, s);
      const double l2 = std::pow(plain.spring_rest_length()[s], 2);
      for (int i = 0; i < 81; ++i) {
        const double uuuu = u[i % 3] * u[(i / 3) % 3] * u[(i / 9) % 3] * u[i / 27];
        tensor_plain[i] += plain.spring_stiffness()[s] * l2 * uuuu;
        tensor_corrected[i] += corrected.spring_stiffness()[s] * l2 * uuuu;
      }
      const double kp = plain.spring_stiffness()[s], kc = corrected.spring_stiffness()[s];
      largest_change = std::max(largest_change, std::abs(kc / kp - 1.0));
      EXPECT_NEAR(corrected.dispersion_weight_a()[s] * kc, plain.dispersion_weight_a()[s] * kp,
                  1e-12 * kp);
      EXPECT_NEAR(corrected.dispersion_weight_b()[s] * kc, plain.dispersion_weight_b()[s] * kp,
                  1e-12 * kp);
    }
    for (int i = 0; i < 81; ++i) {
      EXPECT_NEAR(tensor_corrected[i], tensor_plain[i], 1e-12 * tensor_plain[0]) << i;
    }
    EXPECT_GT(largest_change, 0.1) << "the correction did nothing at nu " << poisson;
  }
}

// Where the stiffness goes: an A spring lying in an outer layer of one axis gains alpha_A, in an
// interior layer it loses 2 alpha_A / (n - 2), in layers of two axes it takes the product of
// both factors; B springs the same with alpha_B = alpha_A nu / (1 - nu). alpha_A puts back the
// deficit at the outer layers' modulus gain E alpha_A / 2: alpha_A S(n) / 2 = deficit n^3 / 12.
TEST(FreeFaceBending, FactorsByLayer) {
  std::vector<Eigen::Vector3i> cells;
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 6; ++j)
      for (int i = 0; i < 3; ++i) cells.emplace_back(i, j, k);
  const auto bending = FreeFaceBending::ForBox(cells, 0.25);
  ASSERT_TRUE(bending.has_value());
  const Eigen::Vector3d alpha = bending->alpha();
  EXPECT_EQ(alpha.x(), 0.0);  // 3 layers: not corrected
  // n = 4: z_k = +-1.5, +-0.5; S = 2 (2.25) - (2 / 2) 2 (0.25) = 4.
  EXPECT_NEAR(alpha.z(), FreeFaceBendingDeficit(4) * 64.0 / (6.0 * 4.0), 1e-12);  // 1/2
  // n = 6: z = +-2.5, +-1.5, +-0.5; S = 2 (6.25) - (2 / 4) 2 (2.25 + 0.25) = 10.
  EXPECT_NEAR(alpha.y(), FreeFaceBendingDeficit(6) * 216.0 / (6.0 * 10.0), 1e-12);
  const Eigen::Vector3d alpha_b = bending->alpha_b();
  EXPECT_NEAR(alpha_b.y(), alpha.y() / 3.0, 1e-15);  // nu / (1 - nu) at nu = 1/4
  EXPECT_NEAR(alpha_b.z(), alpha.z() / 3.0, 1e-15);
  const Eigen::Vector3i along_x(1, 0, 0);
  EXPECT_NEAR(bending->Factor({1, 0, 0}, along_x), (1.0 + alpha.y()) * (1.0 + alpha.z()), 1e-15);
  EXPECT_NEAR(bending->Factor({1, 2, 0}, along_x), (1.0 - alpha.y() / 2.0) * (1.0 + alpha.z()),
              1e-15);
  EXPECT_NEAR(bending->Factor({1, 2, 1}, along_x), (1.0 - alpha.y() / 2.0) * (1.0 - alpha.z()),
              1e-15);
  // A spring along z lies in layers of x (not corrected) and y only.
  EXPECT_NEAR(bending->Factor({1, 5, 0}, Eigen::Vector3i(0, 0, 1)), 1.0 + alpha.y(), 1e-15);
  // B springs lie in one layer and take alpha_B.
  EXPECT_NEAR(bending->Factor({1, 0, 0}, Eigen::Vector3i(1, 0, 1)), 1.0 + alpha_b.y(), 1e-15);
  EXPECT_NEAR(bending->Factor({1, 3, 1}, Eigen::Vector3i(1, 1, 0)), 1.0 - alpha_b.z(), 1e-15);
  EXPECT_NEAR(bending->Factor({1, 5, 0}, Eigen::Vector3i(1, 1, 1)), 1.0, 1e-15);
}

// Only boxes of whole cells: cells with a hole, or a rotated lattice, are left alone.
TEST(FreeFaceBending, OnlyForCellsThatFillABox) {
  std::vector<Eigen::Vector3i> cells;
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 5; ++i) cells.emplace_back(i, j, k);
  EXPECT_TRUE(FreeFaceBending::ForBox(cells, 0.3).has_value());
  cells.erase(cells.begin() + 62);
  EXPECT_FALSE(FreeFaceBending::ForBox(cells, 0.3).has_value());
  EXPECT_FALSE(FreeFaceBending::ForBox({}, 0.3).has_value());
  std::vector<Eigen::Vector3i> plate;  // 3 cells thick everywhere: nothing to correct
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) plate.emplace_back(i, j, k);
  EXPECT_FALSE(FreeFaceBending::ForBox(plate, 0.3).has_value());

  const Model rotated = Box(0.3, Eigen::Vector3i(8, 8, 8), true, 0.6);
  const Model rotated_plain = Box(0.3, Eigen::Vector3i(8, 8, 8), false, 0.6);
  EXPECT_EQ(rotated.spring_stiffness(), rotated_plain.spring_stiffness());
}

}  // namespace
}  // namespace msm_sim::core
