// The single-precision spring loops on node shares: nodes rounded ahead, a first pass taken
// ahead, shares cut at busy nodes, unstored forces, and two or four threads against one.
#include <algorithm>
#include <atomic>
#include <numeric>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "mechanics/node_shares.h"
#include "mechanics/single_precision_kernels.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/mechanics/force_evaluator.h"
#include "perturbed_positions.h"
#include "single_precision_checks.h"

namespace msm_sim::core {
namespace {

// Nodes rounded ahead (internal::NodeShares::Round, in two ranges) and NodeStages::rounded give
// the forces of the loops' own rounding relative to the same origin, to the bit, on one and two
// threads, without calling `before`; with another origin the rounding, and so the forces, differ.
TEST(SinglePrecisionEvaluator, NodesRoundedAheadGiveTheForcesOfTheLoopsOwnRounding) {
  const Model model = Block(0.45, 0.0035);
  ASSERT_GE(model.num_nodes(), 1'000);
  const Eigen::Matrix3Xd x = Perturbed(model.rest_positions(), 2.5e-4, 12);
  const Eigen::Matrix3Xd v = Perturbed(Eigen::Matrix3Xd::Zero(3, model.num_nodes()), 0.1, 13);
  const double origin[3] = {0.013, -0.002, 0.007};
  const int n = model.num_nodes();
  for (const int threads : {1, 2}) {
    ForceEvaluator own(model, SpringKernels::kAuto, threads);
    ForceEvaluator ahead(model, SpringKernels::kAuto, threads);
    own.set_precision(SpringPrecision::kSingle);
    ahead.set_precision(SpringPrecision::kSingle);
    ASSERT_TRUE(internal::NodeShares::Rounds(ahead));
    std::atomic<int> befores{0};
    internal::NodeStages stages;
    stages.before = [&](int, int, int) { ++befores; };
    stages.after = [](int, int, int) {};
    stages.origin = origin;
    Eigen::Matrix3Xd expected, first, rounded;
    internal::NodeShares::SetForces(&own, x, v, 1e-3, &expected, stages);
    EXPECT_GT(befores.load(), 0);
    ahead.SetForces(x, v, 1e-3, &first);  // sizes the node arrays (node 0 as origin)
    EXPECT_NE(first, expected) << "the origin changes the rounding";
    internal::NodeShares::Round(&ahead, x, &v, 0, n / 3, origin);
    internal::NodeShares::Round(&ahead, x, &v, n / 3, n, origin);
    befores = 0;
    stages.rounded = true;
    internal::NodeShares::SetForces(&ahead, x, v, 1e-3, &rounded, stages);
    EXPECT_EQ(befores.load(), 0) << threads;
    EXPECT_EQ(rounded, expected) << threads;
  }
}

// Sums the two halves of after_unstored's forces `f` of nodes [begin, end) into *forces.
void SumUnstored(int begin, int end, const float* f, long stride, Eigen::Matrix3Xd* forces) {
  for (int i = begin; i < end; ++i) {
    for (int d = 0; d < 3; ++d) {
      (*forces)(d, i) =
          static_cast<double>(f[d * stride + i]) + static_cast<double>(f[(3 + d) * stride + i]);
    }
  }
}

// A slab three nodes thick (nu = 0.45) whose four node shares are each shorter than a layer.
Model ThinSlab() {
  CubicLatticeOptions slab;
  slab.size = Eigen::Vector3d(0.4, 0.4, 0.02);
  slab.lattice.spacing = 0.01;
  return BuildCubicLattice(Material::FromYoungsPoisson(1e5, 0.45, 1000.0), slab);
}

// Positions and velocities of one evaluation and of the next, and positions of a later one.
struct Motion {
  Eigen::Matrix3Xd x, v, next_x, next_v, later_x;
};

// The perturbed motion of `model` (seeds 30 to 34): the next positions 0.1 mm on from x.
Motion PerturbedMotion(const Model& model) {
  const int n = model.num_nodes();
  Motion m;
  m.x = Perturbed(model.rest_positions(), 2.5e-4, 30);
  m.v = Perturbed(Eigen::Matrix3Xd::Zero(3, n), 0.1, 31);
  m.next_x = m.x + Perturbed(Eigen::Matrix3Xd::Zero(3, n), 1e-4, 32);
  m.next_v = Perturbed(Eigen::Matrix3Xd::Zero(3, n), 0.1, 33);
  m.later_x = Perturbed(model.rest_positions(), 2.5e-4, 34);
  return m;
}

// Stages that do nothing, rounding relative to `origin`.
internal::NodeStages PlainStages(const double origin[3]) {
  internal::NodeStages plain;
  plain.before = [](int, int, int) {};
  plain.after = [](int, int, int) {};
  plain.origin = origin;
  return plain;
}

// Forces from scratch at each state of a Motion, and at the next with other dampers.
struct ExpectedForces {
  Eigen::Matrix3Xd now, next, later, other_dampers;
};

// Evaluates ExpectedForces with `own`, in that order.
ExpectedForces FromScratch(ForceEvaluator& own, const Motion& m,
                           const internal::NodeStages& plain) {
  ExpectedForces e;
  internal::NodeShares::SetForces(&own, m.x, m.v, 1e-3, &e.now, plain);
  internal::NodeShares::SetForces(&own, m.next_x, m.next_v, 1e-3, &e.next, plain);
  internal::NodeShares::SetForces(&own, m.later_x, m.v, 1e-3, &e.later, plain);
  internal::NodeShares::SetForces(&own, m.next_x, m.next_v, 2e-3, &e.other_dampers, plain);
  return e;
}

// The numbers of nodes of the first and of the last of `threads` node shares.
std::pair<int, int> FirstAndLastShare(ForceEvaluator& evaluator, int threads) {
  int first = 0, last = 0;
  internal::NodeShares::ForEach(&evaluator, [&](int share, int begin, int end) {
    if (share == 0) first = end - begin;
    if (share == threads - 1) last = end - begin;
  });
  return {first, last};
}

// `plain` rounding m's next state ahead into *ahead, summing into *now, counting rounded nodes.
internal::NodeStages RoundingAhead(const internal::NodeStages& plain, ForceEvaluator* ahead,
                                   const Motion* m, Eigen::Matrix3Xd* now,
                                   std::atomic<int>* rounded_nodes) {
  internal::NodeStages first = plain;
  const double* origin = plain.origin;
  first.after_unstored = [=](int, int begin, int end, const float* f, long stride) {
    SumUnstored(begin, end, f, stride, now);
    internal::NodeShares::Round(ahead, m->next_x, &m->next_v, begin, end, origin);
    *rounded_nodes += end - begin;
  };
  first.rounds_ahead = true;
  return first;
}

// NodeStages::rounds_ahead: the `after` stages round the nodes where the next evaluation will
// find them, and the loops take that evaluation's first pass ahead, each share once the shares
// its springs reach have rounded theirs (and, on shares cut unequal, the last share's part of
// the passes after it, or of the plain pass). The next evaluation (NodeStages::rounded) gives
// the forces of one at those positions from scratch, to the bit, on one and two threads and on
// four shares shorter than a layer (whose springs reach two shares on); this one's forces are
// not disturbed, and an evaluation without `rounded`, or with other dampers, after it does not
// take what was taken ahead.
TEST(SinglePrecisionEvaluator, AFirstPassTakenAheadGivesTheNextEvaluationsForces) {
  const Model block = Block(0.45, 0.0035);
  const Model plain = Block(0.25, 0.0035);  // no dispersion: the plain pass
  ASSERT_EQ(plain.dispersion_fraction(), 0.0);
  const Model thin = ThinSlab();
  ASSERT_LT(thin.num_nodes() / 4, 40 * 40);  // a share is shorter than a layer
  const double origin[3] = {0.013, -0.002, 0.007};
  // Shares cut with the first 400 nodes busy (NodeShares::Cut): the last share is then longer than
  // the first and takes its extra nodes' dispersion and second pass ahead too.
  std::vector<NodeIndex> busy(400);
  std::iota(busy.begin(), busy.end(), 0);
  struct Case {
    const Model* model;
    int threads;
    bool cut;
  };
  for (const Case& c : {Case{&block, 1, false}, Case{&block, 2, false}, Case{&block, 2, true},
                        Case{&plain, 2, true}, Case{&thin, 4, false}, Case{&thin, 4, true}}) {
    const Model* model = c.model;
    const int threads = c.threads;
    ASSERT_GE(model->num_nodes(), 1'000);
    const int n = model->num_nodes();
    const Motion m = PerturbedMotion(*model);
    ForceEvaluator own(*model, SpringKernels::kAuto, threads);
    ForceEvaluator ahead(*model, SpringKernels::kAuto, threads);
    own.set_precision(SpringPrecision::kSingle);
    ahead.set_precision(SpringPrecision::kSingle);
    if (c.cut) {
      internal::NodeShares::Cut(&own, busy, 2.0);
      internal::NodeShares::Cut(&ahead, busy, 2.0);
      const auto [first, last] = FirstAndLastShare(ahead, threads);
      ASSERT_GT(last, first + 100) << threads;
    }
    const internal::NodeStages plain = PlainStages(origin);
    const ExpectedForces expected = FromScratch(own, m, plain);

    Eigen::Matrix3Xd now(3, n), unused, next, later;
    std::atomic<int> rounded_nodes{0};
    const internal::NodeStages first = RoundingAhead(plain, &ahead, &m, &now, &rounded_nodes);
    internal::NodeShares::SetForces(&ahead, m.x, m.v, 1e-3, &unused, first);
    ASSERT_EQ(rounded_nodes.load(), n);
    EXPECT_EQ(now, expected.now) << threads;
    internal::NodeStages second = plain;
    second.rounded = true;
    internal::NodeShares::SetForces(&ahead, m.next_x, m.next_v, 1e-3, &next, second);
    EXPECT_EQ(next, expected.next) << threads;
    EXPECT_NE(next, expected.now) << "the nodes moved";
    internal::NodeShares::SetForces(&ahead, m.later_x, m.v, 1e-3, &later, plain);
    EXPECT_EQ(later, expected.later) << threads;
    // The part taken ahead had this evaluation's dampers: with others next, it is taken again.
    internal::NodeShares::SetForces(&ahead, m.x, m.v, 1e-3, &unused, first);
    Eigen::Matrix3Xd other_dampers;
    internal::NodeShares::SetForces(&ahead, m.next_x, m.next_v, 2e-3, &other_dampers, second);
    EXPECT_EQ(other_dampers, expected.other_dampers) << threads;
  }
}

// NodeShares::Cut: shares of equal work, a busy node counting 1 + busy_work; without busy nodes
// the equal shares of before. Every share keeps a node however the work falls.
TEST(SinglePrecisionEvaluator, CutNodeSharesGivesSharesOfEqualWork) {
  const Model model = Block(0.45, 0.0035);
  const int n = model.num_nodes();
  ASSERT_GE(n, 1'000);
  ForceEvaluator evaluator(model, SpringKernels::kAuto, 3);
  evaluator.set_precision(SpringPrecision::kSingle);
  // The shares run on their own threads at once: each records its bounds in its own slot.
  const auto bounds = [&] {
    const int shares = internal::NodeShares::Count(evaluator);
    std::vector<int> begins(shares, -1), ends(shares, -1);
    internal::NodeShares::ForEach(&evaluator, [&](int share, int begin, int end) {
      begins[share] = begin;
      ends[share] = end;
    });
    for (int share = 0; share < shares; ++share) {
      EXPECT_EQ(begins[share], share == 0 ? 0 : ends[share - 1]) << share;
      EXPECT_LT(begins[share], ends[share]) << share;
    }
    return ends;
  };
  const std::vector<int> equal = bounds();
  // Inner bounds rounded down to where the runs' aligned loads start.
  const int align = SinglePrecisionSprings::kAlignment;
  EXPECT_EQ(equal, (std::vector<int>{n / 3 / align * align, 2 * n / 3 / align * align, n}));
  std::vector<NodeIndex> busy(300);
  std::iota(busy.begin(), busy.end(), 100);  // nodes 100 .. 399
  internal::NodeShares::Cut(&evaluator, busy, 2.0);
  const std::vector<int> cut = bounds();
  const double total = n + 2.0 * 300;
  const auto work_before = [&](int node) { return node + 2.0 * std::clamp(node - 100, 0, 300); };
  for (int t = 0; t < 2; ++t) {
    EXPECT_EQ(cut[t] % align, 0) << t;
    // Within one aligned step of nodes, busy ones, of the work's third.
    EXPECT_LE(work_before(cut[t]), total * (t + 1) / 3 + 1.0) << t;
    EXPECT_GT(work_before(cut[t] + align), total * (t + 1) / 3) << t;
  }
  EXPECT_EQ(cut[2], n);
  internal::NodeShares::Cut(&evaluator, {}, 2.0);
  EXPECT_EQ(bounds(), equal);
  std::vector<NodeIndex> all(n);
  std::iota(all.begin(), all.end(), 0);
  internal::NodeShares::Cut(&evaluator, std::vector<NodeIndex>(all.begin(), all.begin() + 2), 1e9);
  const std::vector<int> lopsided = bounds();  // the EXPECT_LTs above: no share left empty
  EXPECT_EQ(lopsided[0], SinglePrecisionSprings::kAlignment);
}

// NodeStages::after_unstored gets the forces SetForces would have stored, to the bit, for every
// node once (on one and two threads); `after` is not called and *forces is left as it was.
TEST(SinglePrecisionEvaluator, UnstoredForcesSumToTheStoredOnes) {
  const Model model = Block(0.45, 0.0035);
  ASSERT_GE(model.num_nodes(), 1'000);
  const Eigen::Matrix3Xd x = Perturbed(model.rest_positions(), 2.5e-4, 10);
  const Eigen::Matrix3Xd v = Perturbed(Eigen::Matrix3Xd::Zero(3, model.num_nodes()), 0.1, 11);
  for (const int threads : {1, 2}) {
    ForceEvaluator stored(model, SpringKernels::kAuto, threads);
    ForceEvaluator unstored(model, SpringKernels::kAuto, threads);
    stored.set_precision(SpringPrecision::kSingle);
    unstored.set_precision(SpringPrecision::kSingle);
    Eigen::Matrix3Xd expected;
    stored.SetForces(x, v, 1e-3, &expected);
    Eigen::Matrix3Xd summed = Eigen::Matrix3Xd::Constant(3, model.num_nodes(), 7.0);
    Eigen::Matrix3Xd untouched = Eigen::Matrix3Xd::Constant(3, model.num_nodes(), 7.0);
    std::atomic<int> afters{0}, sums{0};
    internal::NodeStages stages;
    stages.before = [](int, int, int) {};
    stages.after = [&](int, int, int) { ++afters; };
    stages.after_unstored = [&](int, int begin, int end, const float* f, long stride) {
      for (int i = begin; i < end; ++i) {
        for (int d = 0; d < 3; ++d) {
          summed(d, i) =
              static_cast<double>(f[d * stride + i]) + static_cast<double>(f[(3 + d) * stride + i]);
        }
      }
      sums += end - begin;
    };
    internal::NodeShares::SetForces(&unstored, x, v, 1e-3, &untouched, stages);
    EXPECT_EQ(sums.load(), model.num_nodes()) << threads;
    EXPECT_EQ(afters.load(), 0) << threads;
    EXPECT_EQ(summed, expected) << threads;
    EXPECT_TRUE((untouched.array() == 7.0).all()) << threads;
  }
}

TEST(SinglePrecisionEvaluator, TwoThreadsAgreeAndRepeat) {
  // Above the evaluator's threshold for threads (1,000 nodes).
  const Model model = Block(0.45, 0.0035);
  ASSERT_GE(model.num_nodes(), 1'000);
  const Eigen::Matrix3Xd x = Perturbed(model.rest_positions(), 2.5e-4, 6);
  const Eigen::Matrix3Xd v = Perturbed(Eigen::Matrix3Xd::Zero(3, model.num_nodes()), 0.1, 7);
  const Eigen::Matrix3Xd two = Forces(model, SpringPrecision::kSingle, x, v, 1e-3, 2);
  EXPECT_EQ(two, Forces(model, SpringPrecision::kSingle, x, v, 1e-3, 2));
  ExpectClose(model, two, Forces(model, SpringPrecision::kDouble, x, v, 1e-3));
}

// A slab three nodes thick in four node shares: each share is shorter than a layer, so a share's
// b ends overflow past the next share into the one after it, and the overflows of two earlier
// shares meet on the same nodes (SingleShare). Four shares run on a machine of any size (the
// pool's caller runs those beyond its workers).
TEST(SinglePrecisionEvaluator, SharesShorterThanTheLongestOffsetAgree) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(0.4, 0.4, 0.02);
  options.lattice.spacing = 0.01;
  for (const double poisson : {0.25, 0.45}) {
    const Model model =
        BuildCubicLattice(Material::FromYoungsPoisson(1e5, poisson, 1000.0), options);
    const int layer = 40 * 40;
    ASSERT_GE(model.num_nodes(), 1'000);
    ASSERT_LT(model.num_nodes() / 4, layer);
    const Eigen::Matrix3Xd x = Perturbed(model.rest_positions(), 5e-4, 8);
    const Eigen::Matrix3Xd v = Perturbed(Eigen::Matrix3Xd::Zero(3, model.num_nodes()), 0.1, 9);
    const Eigen::Matrix3Xd four = Forces(model, SpringPrecision::kSingle, x, v, 1e-3, 4);
    EXPECT_EQ(four, Forces(model, SpringPrecision::kSingle, x, v, 1e-3, 4));
    ExpectClose(model, four, Forces(model, SpringPrecision::kDouble, x, v, 1e-3));
  }
}

}  // namespace
}  // namespace msm_sim::core
