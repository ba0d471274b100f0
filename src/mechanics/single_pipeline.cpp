// The single-precision evaluation's stages: on each node share, the caller's `before` stage and
// the rounding, the eMSM first pass, the dispersion, the force pass, then the caller's `after`
// stage; and what one evaluation takes ahead of the next (NodeStages::rounds_ahead).

#include "mechanics/single_pipeline.h"

#include <algorithm>
#include <functional>
#include <vector>

namespace msm_sim::core::internal {

namespace {

// Adds the overflows of the shares before `share` (each `length` floats from its end node, at
// `stride` apart in `overflows`) into `shared` (per node) over the share's own nodes: after
// this, shared holds every b end's sum for them.
void GatherOverflows(const float* overflows, long stride, long length,
                     const std::vector<SingleShare>& shares, int share, float* shared) {
  const SingleShare& own = shares[share];
  for (int earlier = 0; earlier < share; ++earlier) {
    const long from = shares[earlier].end;
    const long lo = std::max<long>(own.begin, from);
    const long hi = std::min<long>(own.end, from + length);
    const float* overflow = overflows + stride * earlier;
    for (long i = lo; i < hi; ++i) shared[i] += overflow[i - from];
  }
}

// The point the loops round positions relative to: the stages' origin, else node 0 where it is
// before the stages move it (a float then resolves 6e-8 of the body's size, not of its distance
// from the world's origin).
void RoundingOrigin(const SingleInputs& in, double origin[3]) {
  const double* given = in.stages != nullptr ? in.stages->origin : nullptr;
  for (int d = 0; d < 3; ++d) origin[d] = given != nullptr ? given[d] : (*in.positions)(d, 0);
}

}  // namespace

/// One evaluation of SinglePasses: the shares, the arrays and what is taken ahead, fixed at its
/// start; each stage a method on one share.
class SingleEvaluation {
 public:
  SingleEvaluation(SinglePasses* passes, const SharePlan& plan, const SingleInputs& in,
                   const SingleOutputs& out);
  void Run();

 private:
  float* Overflow(int t, int block) {
    return passes_.overflows_.data() + 4 * overflow_stride_ * t + overflow_stride_ * block;
  }
  MutableSingleNodeArrays OverflowForces(int t) {
    return {Overflow(t, 0), Overflow(t, 1), Overflow(t, 2)};
  }
  int LastRead(int t) const;
  void Round(int t);
  void Barrier();
  void Clear(int t, float* nodes, int blocks, int first, int last);
  void ClearSums(int t, float* a_ends, int blocks, int first, int last);
  void ApplyForces(int t);
  int AheadFrom(int t) const;
  int Split() const;
  void SpringForces(int t, const SingleShare& part);
  void TailForces(int t);
  void ForcePass(int t);
  void FirstPass(int t);
  void Disperse(int begin, int end);
  void GatherAndDisperse(int t);
  void NextPasses(int t, bool early);

  SinglePasses& passes_;
  const SingleInputs& in_;
  const SingleOutputs& out_;
  const SinglePrecisionSprings& springs_;
  const int n_;
  const long stride_;  // between blocks of n
  const int count_;
  const std::vector<SingleShare> shares_;
  double origin_[3];
  float *x_, *v_, *f_;
  SingleNodeArrays x_arrays_, v_arrays_;
  const SingleNodeArrays* velocities_;
  SingleEndForces end_forces_;
  float beta_;
  bool dispersion_, rounded_, inflowed_, ahead_;
  bool barrier_added_ = false;  // the barrier added forces in this evaluation
  int early_from_;
  long length_;           // the longest overflow: the schedule's largest offset
  long overflow_stride_;  // blocks start a cache line
  float *j_a_ = nullptr, *j_b_ = nullptr;
  int last_, split_;
};

SingleEvaluation::SingleEvaluation(SinglePasses* passes, const SharePlan& plan,
                                   const SingleInputs& in, const SingleOutputs& out)
    : passes_(*passes),
      in_(in),
      out_(out),
      springs_(*in.springs),
      n_(in.model->num_nodes()),
      stride_(SingleStride(*in.springs)),
      count_(plan.NodeShareCount()),
      shares_(plan.NodeShares()) {
  passes_.nodes_.resize(12 * stride_);
  x_ = passes_.nodes_.data();
  v_ = x_ + 3 * stride_;
  f_ = x_ + 6 * stride_;
  RoundingOrigin(in, origin_);
  x_arrays_ = {x_, x_ + stride_, x_ + 2 * stride_};
  v_arrays_ = {v_, v_ + stride_, v_ + 2 * stride_};
  velocities_ = in.velocities != nullptr ? &v_arrays_ : nullptr;
  end_forces_ = {{f_, f_ + stride_, f_ + 2 * stride_},
                 {f_ + 3 * stride_, f_ + 4 * stride_, f_ + 5 * stride_}};
  beta_ = static_cast<float>(in.beta);
  dispersion_ = in.model->dispersion_fraction() != 0.0;
  rounded_ = in.stages != nullptr && in.stages->rounded;
  // What the last evaluation took ahead of this one, on these nodes (rounded since): the first
  // pass of the eMSM, and the last share's part of the passes after it from node early_from on,
  // which had that evaluation's dampers (only the caller knows whether its beta stays).
  const SinglePasses::TakenAhead taken = passes_.ahead_;
  const bool taken_ahead = rounded_ && taken.taken;
  inflowed_ = taken_ahead && dispersion_;
  const bool same_dampers = taken.beta == (in.velocities != nullptr ? beta_ : 0.0f);
  early_from_ = taken_ahead && same_dampers ? taken.early_from : -1;
  passes_.ahead_ = SinglePasses::TakenAhead{};
  ahead_ = in.stages != nullptr && in.stages->rounds_ahead;
  length_ = springs_.max_offset;
  overflow_stride_ = WholeCacheLinesOfFloats(length_);
  passes_.overflows_.resize(4 * overflow_stride_ * count_);
  if (dispersion_) {
    passes_.accumulators_.resize(2 * stride_);
    passes_.dispersion_.resize(stride_);  // g, read where the blocks' phantoms reach
  }
  j_a_ = passes_.accumulators_.data();
  j_b_ = j_a_ + stride_;
  last_ = count_ - 1;
  split_ = Split();
}

// The last share whose nodes share t's spring loops read (b = a + d, d <= max_offset): its
// second parts wait for those shares' first parts only (SharePlan::RunInTwoParts).
int SingleEvaluation::LastRead(int t) const {
  const long reach = std::min<long>(shares_[t].end + length_, n_) - 1;
  int last = t;
  while (last + 1 < count_ && shares_[last + 1].begin <= reach) ++last;
  return last;
}

void SingleEvaluation::Round(int t) {
  if (rounded_) return;
  const SingleShare& share = shares_[t];
  if (in_.stages != nullptr) in_.stages->before(t, share.begin, share.end);
  passes_.Round(springs_, in_.positions->data(), in_.velocities, share.begin, share.end, origin_);
}

// Zeroes share t's nodes in `blocks` consecutive node blocks from `nodes`, and its overflows
// `first` .. `last`.
void SingleEvaluation::Clear(int t, float* nodes, int blocks, int first, int last) {
  const SingleShare& share = shares_[t];
  for (int b = 0; b < blocks; ++b) {
    std::fill(nodes + b * stride_ + share.begin, nodes + b * stride_ + share.end, 0.0f);
  }
  std::fill(Overflow(t, first), Overflow(t, last) + length_, 0.0f);
}

// Zeroes what share t's passes add to: both ends' forces or accumulators, or where the loops
// take the share by blocks only the b ends' (they store the a ends'), and the overflows.
void SingleEvaluation::ClearSums(int t, float* a_ends, int blocks, int first, int last) {
  if (SingleLoopsByBlocks(springs_, shares_[t])) {
    Clear(t, a_ends + (blocks / 2) * stride_, blocks / 2, first, last);
  } else {
    Clear(t, a_ends, blocks, first, last);
  }
}

// The barrier's forces at the positions every share's `before` stage has left, in double
// (docs/physics.md §4), into barrier_forces, zero unless the last evaluation's barrier added some.
void SingleEvaluation::Barrier() {
  Eigen::Matrix3Xd& forces = *out_.barrier_forces;
  if (passes_.barrier_added_ || forces.cols() != n_) forces.setZero(3, n_);
  barrier_added_ =
      in_.barrier->AccumulateForces(*in_.positions, &forces, out_.barrier_reference) > 0;
  passes_.barrier_added_ = barrier_added_;
}

// The b ends' overflows gathered, then the forces handed to the caller's `after_unstored`, or
// stored or added (with the barrier's, where it added any) before its `after`.
void SingleEvaluation::ApplyForces(int t) {
  for (int d = 0; d < 3; ++d) {
    GatherOverflows(Overflow(0, d), 4 * overflow_stride_, length_, shares_, t,
                    f_ + (3 + d) * stride_);
  }
  const SingleShare& share = shares_[t];
  const NodeStages* stages = in_.stages;
  if (stages != nullptr && stages->after_unstored && !barrier_added_) {
    stages->after_unstored(t, share.begin, share.end, f_, stride_);
    return;
  }
  double* forces = out_.forces->data();
  if (in_.overwrite) {
    StoreSingleEndForces(f_, stride_, share.begin, share.end, forces);
  } else {
    AddSingleEndForces(f_, stride_, share.begin, share.end, forces);
  }
  if (barrier_added_) {
    out_.forces->middleCols(share.begin, share.end - share.begin) +=
        out_.barrier_forces->middleCols(share.begin, share.end - share.begin);
  }
  if (stages != nullptr) stages->after(t, share.begin, share.end);
}

// The last share's nodes [early_from, n), whose plain or eMSM second pass (and dispersion) the
// last evaluation took ahead.
int SingleEvaluation::AheadFrom(int t) const {
  return t == last_ && early_from_ >= 0 ? early_from_ : shares_[t].end;
}

// The last share's split (count > 1): the later evaluation's passes after the first may take
// its nodes from the split on ahead (NodeStages::rounds_ahead: the last share, which does not
// wait for the first's contacts, takes its nodes beyond the first share's count, which the cut
// gave it for those contacts, and beyond the earlier shares' overflows, whose J it has
// complete). So that they sum alike whether taken ahead or not, the last share's passes after
// the first always run them apart: first the split's tail, its b ends in place, then the nodes
// before it, whose b ends from the split on go to the share's overflow (unused otherwise), added
// after. (A node's b-end sum then takes the tail's slots, then the rest's, in either case.)
int SingleEvaluation::Split() const {
  const int extra =
      (shares_[last_].end - shares_[last_].begin) - (shares_[0].end - shares_[0].begin);
  constexpr int kAlign = SinglePrecisionSprings::kAlignment;  // where its loops start
  const int unaligned = std::max(shares_[last_].begin + static_cast<int>(length_), n_ - extra);
  return count_ > 1 ? std::min((unaligned + kAlign - 1) / kAlign * kAlign, n_) : n_;
}

// The forces of the slots in `part` of share t: the plain pass, or the eMSM second pass.
void SingleEvaluation::SpringForces(int t, const SingleShare& part) {
  if (dispersion_) {
    SingleOutflowRuns(springs_, part, x_arrays_, velocities_, beta_, passes_.dispersion_.data(),
                      end_forces_, OverflowForces(t));
  } else {
    SinglePlainRuns(springs_, part, x_arrays_, velocities_, beta_, end_forces_, OverflowForces(t));
  }
}

void SingleEvaluation::TailForces(int t) {
  ClearSums(t, f_, 6, 0, 2);
  SpringForces(t, SingleShare{split_, n_, n_});
}

void SingleEvaluation::ForcePass(int t) {
  if (t != last_ || split_ == n_) {
    ClearSums(t, f_, 6, 0, 2);
    SpringForces(t, shares_[t]);
    return;
  }
  if (early_from_ != split_) TailForces(t);  // else taken ahead, its blocks cleared then
  std::fill(Overflow(t, 0), Overflow(t, 2) + length_, 0.0f);
  SpringForces(t, SingleShare{shares_[t].begin, split_, split_});
  const long reach = std::min<long>(length_, n_ - split_);
  for (int d = 0; d < 3; ++d) {
    float* to = f_ + (3 + d) * stride_ + split_;
    const float* from = Overflow(t, d);
    for (long i = 0; i < reach; ++i) to[i] += from[i];
  }
}

// The plain pass, or the eMSM first pass (J's accumulators).
void SingleEvaluation::FirstPass(int t) {
  if (!dispersion_) {
    ForcePass(t);
    return;
  }
  ClearSums(t, j_a_, 2, 3, 3);
  SingleInflowRuns(springs_, shares_[t], x_arrays_, j_a_, j_b_, Overflow(t, 3));
}

void SingleEvaluation::Disperse(int begin, int end) {
  SingleDispersion(j_a_, in_.model->dispersion_fraction(), in_.inverse_star_weight, stride_, begin,
                   end, passes_.dispersion_.data());
}

void SingleEvaluation::GatherAndDisperse(int t) {
  GatherOverflows(Overflow(0, 3), 4 * overflow_stride_, length_, shares_, t, j_b_);
  Disperse(shares_[t].begin, AheadFrom(t));
}

// Ahead: the next evaluation's eMSM first pass on the nodes share t's `after` stage and the later
// shares' have rounded; the last share also takes the passes after it for its split's tail.
void SingleEvaluation::NextPasses(int t, bool early) {
  if (dispersion_) FirstPass(t);
  if (!early || t != last_) return;
  if (dispersion_) Disperse(split_, n_);
  TailForces(t);
}

void SingleEvaluation::Run() {
  const std::function<int(int)> last_read = [this](int t) { return LastRead(t); };
  const auto first_pass = [this](int t) { FirstPass(t); };
  if (in_.barrier != nullptr) {
    // Once every share's `before` stage has moved its nodes (or the last evaluation's `after`
    // stages, which took this one's first pass ahead); added per share.
    if (!rounded_) SharePlan::Run(count_, [this](int t) { Round(t); });
    Barrier();
    if (!inflowed_) SharePlan::Run(count_, first_pass);
  } else if (!inflowed_) {
    SharePlan::RunInTwoParts(
        count_, [this](int t) { Round(t); }, first_pass, last_read);
  }
  if (dispersion_) {
    SharePlan::RunInTwoParts(
        count_, [this](int t) { GatherAndDisperse(t); }, [this](int t) { ForcePass(t); },
        last_read);
  }
  // Each share's `after` stage (kick, contacts, drift), then what the next evaluation takes
  // ahead: the first share's contacts and the last share's tail are then done at the same time.
  const bool early = ahead_ && split_ < n_;
  const auto apply_forces = [this](int t) { ApplyForces(t); };
  if (ahead_ && (dispersion_ || early)) {
    SharePlan::RunInTwoParts(
        count_, apply_forces, [this, early](int t) { NextPasses(t, early); }, last_read);
    passes_.ahead_ = {true, early ? split_ : -1, velocities_ != nullptr ? beta_ : 0.0f};
  } else {
    SharePlan::Run(count_, apply_forces);
  }
}

void SinglePasses::Evaluate(const SharePlan& plan, const SingleInputs& in,
                            const SingleOutputs& out) {
  SingleEvaluation(this, plan, in, out).Run();
}

void SinglePasses::Round(const SinglePrecisionSprings& springs, const double* positions,
                         const double* velocities, int begin, int end, const double origin[3]) {
  const long stride = SingleStride(springs);
  float* x = nodes_.data();
  ToSingleNodeArrays(positions, stride, begin, end, origin, x);
  if (velocities != nullptr) {
    const double zero[3] = {0.0, 0.0, 0.0};
    ToSingleNodeArrays(velocities, stride, begin, end, zero, x + 3 * stride);
  }
}

}  // namespace msm_sim::core::internal
