// The single-precision spring loops (SpringPrecision::kSingle) against the double per-spring
// loops, which the rest of the suite checks against theory; their schedule; the evaluator's
// stiffness products in single precision.
#include <cstdint>
#include <cstdio>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <utility>

#include <gtest/gtest.h>

#include "mechanics/single_precision_kernels.h"
#include "msm_sim/geometry/mesh_primitives.h"
#include "msm_sim/lattice/body_recipe.h"
#include "msm_sim/mechanics/force_evaluator.h"
#include "msm_sim/model/model_builder.h"
#include "perturbed_positions.h"
#include "single_precision_checks.h"

namespace msm_sim::core {
namespace {

class SinglePrecisionKernels : public ::testing::TestWithParam<std::pair<double, double>> {};

TEST_P(SinglePrecisionKernels, MatchTheDoublePerSpringLoops) {
  const auto [poisson, beta] = GetParam();
  const Model model = Block(poisson);
  // Away from the world's origin: the loops work relative to node 0.
  const Eigen::Matrix3Xd x =
      (Perturbed(model.rest_positions(), 5e-4, 1).colwise() + Eigen::Vector3d(3.0, -2.0, 1.0))
          .eval();
  const Eigen::Matrix3Xd v = Perturbed(Eigen::Matrix3Xd::Zero(3, model.num_nodes()), 0.1, 2);
  const Eigen::Matrix3Xd single = Forces(model, SpringPrecision::kSingle, x, v, beta);
  ExpectClose(model, single, Forces(model, SpringPrecision::kDouble, x, v, beta));
  // Each slot adds and subtracts the same force: momentum is conserved to the sums' rounding.
  const Eigen::Vector3d net = (single.array() - 1.0).matrix().rowwise().sum();
  EXPECT_LE(net.cwiseAbs().maxCoeff(), SingleBound(model));
}

// The same on a block large enough for the schedule's blocks (SinglePrecisionSprings::Blocks;
// the block above has too many phantoms for them, and takes the runs), on one thread and on
// two node shares, whose first writes b ends past its last node to its overflow, in place, split
// or whole, and whose second runs its split's tail apart.
TEST_P(SinglePrecisionKernels, BlocksMatchTheDoublePerSpringLoops) {
  const auto [poisson, beta] = GetParam();
  const Model model = Block(poisson, 0.0035);
  ASSERT_FALSE(SinglePrecisionSprings::Schedule(model)->blocks.offsets.empty());
  ASSERT_TRUE(SinglePrecisionSprings::Schedule(Block(poisson))->blocks.offsets.empty());
  const Eigen::Matrix3Xd x =
      (Perturbed(model.rest_positions(), 2e-4, 1).colwise() + Eigen::Vector3d(3.0, -2.0, 1.0))
          .eval();
  const Eigen::Matrix3Xd v = Perturbed(Eigen::Matrix3Xd::Zero(3, model.num_nodes()), 0.1, 2);
  const Eigen::Matrix3Xd reference = Forces(model, SpringPrecision::kDouble, x, v, beta);
  for (const int threads : {1, 2}) {
    SCOPED_TRACE(threads);
    ExpectClose(model, Forces(model, SpringPrecision::kSingle, x, v, beta, threads), reference);
  }
}

// Plain MSM (nu = 1/4) and eMSM (nu = 0.45, 0.49, -0.5), without and with dampers.
INSTANTIATE_TEST_SUITE_P(PlainAndDispersed, SinglePrecisionKernels,
                         ::testing::Values(std::make_pair(0.25, 0.0), std::make_pair(0.25, 1e-3),
                                           std::make_pair(0.45, 0.0), std::make_pair(0.45, 1e-3),
                                           std::make_pair(0.49, 1e-3), std::make_pair(-0.5, 1e-3)));

TEST(SinglePrecisionSchedule, PhantomsJoinABoxsRowsAndCarryNothing) {
  const Model model = Block(0.45);
  const auto springs = SinglePrecisionSprings::Schedule(model);
  EXPECT_EQ(springs->num_slots(), model.num_springs() + springs->num_phantoms);
  EXPECT_GT(springs->num_phantoms, 0);
  // 10 x 6 x 5 nodes, 9 offsets: rows of 10 joined across their ends into long runs.
  EXPECT_LT(springs->runs.size(), 40u);
  int phantoms = 0;
  for (int slot = 0; slot < springs->num_slots(); ++slot) {
    if (springs->stiffness[slot] == 0.0f) {
      ++phantoms;
      EXPECT_EQ(springs->outflow_a[slot], 0.0f);
      EXPECT_EQ(springs->outflow_b[slot], 0.0f);
    }
  }
  EXPECT_EQ(phantoms, springs->num_phantoms);
  for (const SingleRun& run : springs->runs) {
    EXPECT_GE(run.count, 1);
    EXPECT_LE(run.count, SinglePrecisionSprings::kMaxRunLength);
    EXPECT_LT(run.a0 + run.offset + run.count - 1, model.num_nodes());
  }
}

// The blocks hold every spring of the model once, with its data, and group offsets that differ
// by a multiple of kAlignment or by at least kGroupSeparation.
TEST(SinglePrecisionSchedule, BlocksHoldEverySpringOnceInSeparatedGroups) {
  const Model model = Block(0.45, 0.0035);
  const auto springs = SinglePrecisionSprings::Schedule(model);
  const SinglePrecisionSprings::Blocks& blocks = springs->blocks;
  ASSERT_EQ(blocks.offsets.size(), 9u);
  ASSERT_EQ(blocks.count, (model.num_nodes() + 7) / 8);
  ASSERT_EQ(blocks.slots.size(), 4u * 8 * 9 * blocks.count);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(blocks.slots.data()) % kCacheLineBytes, 0u);
  int begin = 0;
  int found = 0;
  double k_sum = 0.0, rest_sum = 0.0;
  for (const int end : blocks.group_ends) {
    for (int i = begin; i < end; ++i) {
      for (int j = begin; j < i; ++j) {
        const int apart = blocks.offsets[i] - blocks.offsets[j];
        EXPECT_TRUE(apart % 8 == 0 || apart >= SinglePrecisionSprings::kGroupSeparation)
            << blocks.offsets[j] << " and " << blocks.offsets[i];
      }
    }
    const std::size_t size = end - begin;
    for (int k = 0; k < blocks.count; ++k) {
      for (std::size_t o = 0; o < size; ++o) {
        const float* slot = blocks.slots.data() +
                            32 * (static_cast<std::size_t>(begin) * blocks.count + k * size + o);
        for (int lane = 0; lane < 8; ++lane) {
          if (slot[8 + lane] == 0.0f) continue;  // no spring
          ++found;
          k_sum += slot[lane];
          rest_sum += slot[8 + lane];
          // Its b end is a node of the model.
          EXPECT_LT(8 * k + lane + blocks.offsets[begin + o], model.num_nodes());
        }
      }
    }
    begin = end;
  }
  EXPECT_EQ(begin, 9);
  EXPECT_EQ(found, model.num_springs());
  const auto sum = [](const std::vector<double>& values) {
    return std::accumulate(values.begin(), values.end(), 0.0);
  };
  EXPECT_NEAR(k_sum, sum(model.spring_stiffness()), 1e-6 * k_sum);
  EXPECT_NEAR(rest_sum, sum(model.spring_rest_length()), 1e-6 * rest_sum);
}

// A lattice that suits the blocks but has more nodes than kMaxBlockNodes keeps the runs alone
// (its node arrays far outgrow a core's L2, where the blocks measured slower than the runs).
TEST(SinglePrecisionSchedule, LargeModelsKeepTheRunsAlone) {
  const Model model = Block(0.45, 0.0018);
  ASSERT_GT(model.num_nodes(), SinglePrecisionSprings::kMaxBlockNodes);
  const auto springs = SinglePrecisionSprings::Schedule(model);
  EXPECT_TRUE(springs->blocks.offsets.empty());
  EXPECT_TRUE(springs->blocks.slots.empty());
  EXPECT_EQ(springs->PaddedNodes(), model.num_nodes());
  EXPECT_EQ(springs->num_slots() - springs->num_phantoms, model.num_springs());
}

// Every run starts at a node and a slot that are multiples of kAlignment, in slot arrays that
// start a cache line: its loads at the a ends and slots never straddle two lines.
TEST(SinglePrecisionSchedule, RunsStartAtAlignedNodesAndSlots) {
  const Model model = Block(0.45);
  const auto springs = SinglePrecisionSprings::Schedule(model);
  constexpr int kAlign = SinglePrecisionSprings::kAlignment;
  for (const SingleRun& run : springs->runs) {
    EXPECT_EQ(run.a0 % kAlign, 0) << run.a0;
    EXPECT_EQ(run.first % kAlign, 0) << run.first;
  }
  for (const auto* slots :
       {&springs->rest, &springs->stiffness, &springs->outflow_a, &springs->outflow_b}) {
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(slots->data()) % kCacheLineBytes, 0u);
  }
  // Fewer than kAlignment unused slots lie between two runs.
  for (std::size_t r = 1; r < springs->runs.size(); ++r) {
    const SingleRun& run = springs->runs[r];
    EXPECT_LT(run.first - (springs->runs[r - 1].first + springs->runs[r - 1].count), kAlign);
  }
}

TEST(SinglePrecisionSchedule, ReversedSpringsKeepTheirEndWeights) {
  // Springs from the higher index to the lower with unequal end weights, and a gap whose
  // phantom joins two coinciding nodes (zero length: no NaN, no force).
  ModelBuilder builder(Material::FromYoungsPoisson(1e4, 0.45, 1000.0));
  for (int i = 0; i < 24; ++i) {
    const int along = i < 12 ? i : i - 1;  // nodes 11 and 12 coincide
    builder.AddNode(Eigen::Vector3d(0.01 * along, 0.0, 0.0), 0.1);
  }
  for (int i = 0; i < 23; ++i) {
    if (i == 11) continue;
    const SpringIndex s = builder.AddSpring(i + 1, i, 100.0 + i);
    builder.SetDispersionWeight(s, i + 1, 1.5);
    builder.SetDispersionWeight(s, i, 0.5);
  }
  builder.SetDispersionFraction(2.0);
  const Model model = builder.Build(1e-6, 0.01);
  const Eigen::Matrix3Xd x = Perturbed(model.rest_positions(), 1e-3, 3);
  Eigen::Matrix3Xd coinciding = x;  // the phantom between nodes 11 and 12 has zero length
  coinciding.col(12) = coinciding.col(11);
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
  for (const Eigen::Matrix3Xd* positions :
       {&x, static_cast<const Eigen::Matrix3Xd*>(&coinciding)}) {
    ExpectClose(model, Forces(model, SpringPrecision::kSingle, *positions, v, 1e-3),
                Forces(model, SpringPrecision::kDouble, *positions, v, 1e-3));
  }
}

// The largest difference single precision may make to a stiffness product: every term is
// rounded to float (2^-24 relative) and a node sums a few dozen of them, so 2e-6 of the
// product's largest entry bounds it with room (measured 1.2-1.9e-7, printed below). A kernel error
// shows far above it: a wrong end, weight or coefficient changes entries by their own size.
double ProductDifference(const Eigen::Matrix3Xd& single, const Eigen::Matrix3Xd& exact) {
  return (single - exact).cwiseAbs().maxCoeff() / exact.cwiseAbs().maxCoeff();
}

TEST(SinglePrecisionEvaluator, RecordsNoTensionsAndLinearizesInDouble) {
  const Model model = Block(0.45);
  const Eigen::Matrix3Xd x = Perturbed(model.rest_positions(), 5e-4, 4);
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
  const Eigen::Matrix3Xd probe = Perturbed(Eigen::Matrix3Xd::Zero(3, model.num_nodes()), 1.0, 5);
  ForceEvaluator single(model);
  single.set_precision(SpringPrecision::kSingle);
  EXPECT_EQ(single.precision(), SpringPrecision::kSingle);
  Forces(&single, x, v, 0.0);
  EXPECT_THROW(single.total_tensions(), std::logic_error);
  // The linearisation is the double one; the product rounds it and runs in float.
  ForceEvaluator exact(model);
  Eigen::Matrix3Xd products[2];
  ForceEvaluator* evaluators[2] = {&single, &exact};
  for (int e = 0; e < 2; ++e) {
    evaluators[e]->Linearize(x);
    evaluators[e]->ApplyStiffness(probe, &products[e]);
  }
  EXPECT_LE(ProductDifference(products[0], products[1]), 2e-6);
  EXPECT_NE(products[0], products[1]);  // the float product, not the double one
  EXPECT_EQ(single.StiffnessDiagonal(), exact.StiffnessDiagonal());
  EXPECT_EQ(single.precision(), SpringPrecision::kSingle);
  EXPECT_NO_THROW(single.total_tensions());  // Linearize evaluated in double
  ExpectClose(model, Forces(&single, x, v, 0.0), Forces(&exact, x, v, 0.0));
  single.set_precision(SpringPrecision::kDouble);
  EXPECT_EQ(Forces(&single, x, v, 0.0), Forces(&exact, x, v, 0.0));
  single.ApplyStiffness(probe, &products[0]);
  EXPECT_EQ(products[0], products[1]);
}

// The single-precision stiffness product against the double per-spring one, which the
// stiffness tests check against finite differences of the forces: plain MSM and eMSM up to
// nu = 0.49 (the dispersed part), deformed, exact and compression-dropping geometric terms, and
// a precision set after the linearisation.
TEST(SinglePrecisionEvaluator, StiffnessProductsMatchTheDoubleOnes) {
  for (const double poisson : {0.25, 0.45, 0.49}) {
    const Model model = Block(poisson);
    const Eigen::Matrix3Xd x =
        (Perturbed(model.rest_positions(), 5e-4, 6).colwise() + Eigen::Vector3d(3.0, -2.0, 1.0))
            .eval();
    const Eigen::Matrix3Xd probe = Perturbed(Eigen::Matrix3Xd::Zero(3, model.num_nodes()), 1.0, 7);
    for (const GeometricStiffness geometric :
         {GeometricStiffness::kExact, GeometricStiffness::kDropCompression}) {
      ForceEvaluator exact(model, SpringKernels::kPerSpring);
      exact.Linearize(x, geometric);
      Eigen::Matrix3Xd reference;
      exact.ApplyStiffness(probe, &reference);
      ForceEvaluator single(model);
      single.set_precision(SpringPrecision::kSingle);
      single.Linearize(x, geometric);
      ForceEvaluator late(model);  // linearised in double, then switched
      late.Linearize(x, geometric);
      late.set_precision(SpringPrecision::kSingle);
      Eigen::Matrix3Xd product, late_product;
      single.ApplyStiffness(probe, &product);
      late.ApplyStiffness(probe, &late_product);
      const double difference = ProductDifference(product, reference);
      std::printf("  nu %.2f, geometric %d: single against double %.2g of the largest entry\n",
                  poisson, static_cast<int>(geometric), difference);
      EXPECT_LE(difference, 2e-6) << poisson;
      EXPECT_EQ(late_product, product) << poisson;
    }
  }
}

// A curved object's float schedule bridges the gaps between its rows with phantoms, and the
// stiffness product walks those slots: a sphere in a node-centred lattice gives the double
// product too.
TEST(SinglePrecisionEvaluator, StiffnessProductOfACurvedObjectMatchesTheDoubleOne) {
  BodyRecipe recipe(Material::FromYoungsPoisson(259e3, 0.49, 1070.0));
  recipe.solid = std::make_shared<const SolidMesh>(MakeIcosphereMesh(0.012, 3));
  recipe.lattice.spacing = 0.002;
  const Model model = BuildModel(recipe);
  ASSERT_GT(SinglePrecisionSprings::Schedule(model)->num_phantoms, 0);
  const Eigen::Matrix3Xd x = Perturbed(model.rest_positions(), 1e-4, 10);
  const Eigen::Matrix3Xd probe = Perturbed(Eigen::Matrix3Xd::Zero(3, model.num_nodes()), 1.0, 11);
  ForceEvaluator exact(model, SpringKernels::kPerSpring);
  exact.Linearize(x, GeometricStiffness::kDropCompression);
  Eigen::Matrix3Xd reference, product;
  exact.ApplyStiffness(probe, &reference);
  ForceEvaluator single(model);
  single.set_precision(SpringPrecision::kSingle);
  single.Linearize(x, GeometricStiffness::kDropCompression);
  single.ApplyStiffness(probe, &product);
  EXPECT_LE(ProductDifference(product, reference), 2e-6);
}

// On two threads (a model of 1,000 nodes or more) each share sums its part of the runs and the
// shares are added in order: the same bound against double, and the same product every time.
TEST(SinglePrecisionEvaluator, StiffnessProductsOnTwoThreadsAgreeAndRepeat) {
  const Model model = Block(0.49, 0.005);
  ASSERT_GE(model.num_nodes(), 1000);
  const Eigen::Matrix3Xd x = Perturbed(model.rest_positions(), 2e-4, 8);
  const Eigen::Matrix3Xd probe = Perturbed(Eigen::Matrix3Xd::Zero(3, model.num_nodes()), 1.0, 9);
  ForceEvaluator exact(model);
  exact.Linearize(x);
  Eigen::Matrix3Xd reference, product, again;
  exact.ApplyStiffness(probe, &reference);
  ForceEvaluator single(model, SpringKernels::kAuto, 2);
  single.set_precision(SpringPrecision::kSingle);
  single.Linearize(x);
  single.ApplyStiffness(probe, &product);
  single.ApplyStiffness(probe, &again);
  EXPECT_LE(ProductDifference(product, reference), 2e-6);
  EXPECT_EQ(product, again);
}

TEST(SinglePrecisionEvaluator, SetForcesEqualsAddingOntoZero) {
  // SetForces overwrites whatever *forces held, on every path: the single and double run loops,
  // and the per-spring loops.
  const Model model = Block(0.45);
  const Eigen::Matrix3Xd x = Perturbed(model.rest_positions(), 5e-4, 20);
  const Eigen::Matrix3Xd v = Perturbed(Eigen::Matrix3Xd::Zero(3, model.num_nodes()), 0.1, 21);
  for (const auto precision : {SpringPrecision::kSingle, SpringPrecision::kDouble}) {
    for (const auto kernels : {SpringKernels::kAuto, SpringKernels::kPerSpring}) {
      ForceEvaluator set(model, kernels), added(model, kernels);
      set.set_precision(precision);
      added.set_precision(precision);
      for (int evaluation = 0; evaluation < 2; ++evaluation) {
        Eigen::Matrix3Xd overwritten = Eigen::Matrix3Xd::Constant(3, 4, 7.0);  // wrong size too
        set.SetForces(x, v, 1e-3, &overwritten);
        Eigen::Matrix3Xd sum = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
        added.AccumulateForces(x, v, 1e-3, &sum);
        EXPECT_EQ(overwritten, sum)
            << static_cast<int>(precision) << " " << static_cast<int>(kernels) << " " << evaluation;
      }
    }
  }
}

}  // namespace
}  // namespace msm_sim::core
