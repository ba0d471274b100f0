#pragma once

#include <algorithm>
#include <functional>
#include <mutex>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "mechanics/single_precision_kernels.h"
#include "mechanics/worker_pool.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core::internal {

/// The threads and shares of ForceEvaluator's spring passes: which work each thread takes and
/// how the threads are started. The shares are fixed by the model and max_threads alone, never
/// by which thread runs one, so the sums depend on the thread count only (docs/physics.md §9).
class SharePlan {
 public:
  /// Models with at least this many springs split the double loops over up to max_threads
  /// threads; smaller ones would lose more to waking the threads than they gain.
  static constexpr int kParallelSprings = 50'000;
  /// Models with at least this many nodes split the single loops into exactly max_threads node
  /// shares, which write disjoint memory (SingleShare).
  static constexpr int kParallelSingleNodes = 1'000;

  SharePlan(int num_nodes, int num_springs, int max_threads);

  /// Clamps to [1, WorkerPool::kMaxShares] and returns to equal node shares.
  void set_max_threads(int max_threads);
  int max_threads() const { return max_threads_; }

  /// The number of node shares of the single loops (1 below kParallelSingleNodes).
  int NodeShareCount() const;
  /// Share t of `count` node shares: Cut's where it cut that many, else equal shares; their
  /// bounds are multiples of SinglePrecisionSprings::kAlignment (where the runs' loads start).
  SingleShare NodeShare(int t, int count) const;
  /// The NodeShareCount() node shares in node order.
  std::vector<SingleShare> NodeShares() const;
  /// Cuts the node shares at equal work (ForceEvaluator::CutNodeShares); true if they moved.
  bool Cut(const std::vector<NodeIndex>& busy, double busy_work);

  /// Runs task(t) for t = 0 .. shares - 1, on the shared worker pool when there are several
  /// and it is free, else all on the caller (the same shares either way).
  static void Run(int shares, const std::function<void(int)>& task);
  /// WorkerPool::RunInTwoParts on the shared pool; its fallback is every first part, then every
  /// second part, on the caller.
  static void RunInTwoParts(int shares, const std::function<void(int)>& first,
                            const std::function<void(int)>& second,
                            const std::function<int(int)>& last_read);

  /// Runs body(begin, end, scatter_target) over `count` work items (springs or runs) of the
  /// double loops: in fixed contiguous per-thread shares for large models, each thread scattering
  /// into its own copy of `target`, added in share order afterwards.
  template <typename Body>
  void ForSpringShares(int count, double* target, Eigen::Index target_size, Body&& body);

 private:
  int num_nodes_;
  int num_springs_;
  int max_threads_;
  std::vector<int> bounds_;               // the node shares' cut (empty: equal shares)
  std::vector<Eigen::VectorXd> scratch_;  // per extra thread: its scatter buffer
};

template <typename Body>
void SharePlan::ForSpringShares(int count, double* target, Eigen::Index target_size, Body&& body) {
  // The pool's thread starts only when a model may use it: a one-thread world starts none.
  const bool parallel = num_springs_ >= kParallelSprings && max_threads_ > 1;
  WorkerPool* pool = parallel ? &WorkerPool::Shared() : nullptr;
  const int threads = parallel ? std::min(max_threads_, pool->workers() + 1) : 1;
  if (threads <= 1) {
    body(0, count, target);
    return;
  }
  // The springs and runs are ordered by node, so contiguous shares touch mostly different nodes.
  scratch_.resize(threads - 1);
  for (auto& buffer : scratch_) buffer.setZero(target_size);
  const std::function<void(int)> share = [&](int t) {
    const int begin = static_cast<int>(static_cast<long long>(count) * t / threads);
    const int end = static_cast<int>(static_cast<long long>(count) * (t + 1) / threads);
    body(begin, end, t == 0 ? target : scratch_[t - 1].data());
  };
  std::unique_lock<std::mutex> lock(pool->busy(), std::try_to_lock);
  if (lock.owns_lock()) {
    pool->Run(threads, share);
  } else {  // another evaluator (another World's thread) has the pool: the same shares, here
    for (int t = 0; t < threads; ++t) share(t);
  }
  Eigen::Map<Eigen::VectorXd> sum(target, target_size);
  for (const auto& buffer : scratch_) sum += buffer;
}

}  // namespace msm_sim::core::internal
