#include "mechanics/share_plan.h"

#include <algorithm>
#include <mutex>
#include <utility>

namespace msm_sim::core::internal {

namespace {

constexpr int kAlign = SinglePrecisionSprings::kAlignment;

// Node i rounded down to the runs' alignment, where a share's loops start.
int AlignDown(long long i) { return static_cast<int>(i - i % kAlign); }

// Share t's first node of `count` equal shares of n nodes: a multiple of the runs' alignment
// (a share's loops start there), 0 for the first, n after the last.
int EqualShareBound(long long n, int t, int count) {
  return t == count ? static_cast<int>(n) : AlignDown(n * t / count);
}

// The bounds of `count` (> 1) shares of n nodes at equal work, node i counting 1 plus
// busy_work where it is in `busy` (sorted): share t ends at the first node at which the work
// before it reaches t / count of the whole, rounded down to the runs' alignment, every share
// keeping some nodes.
std::vector<int> EqualWorkBounds(int n, int count, const std::vector<NodeIndex>& busy,
                                 double busy_work) {
  const double total = n + busy_work * static_cast<double>(busy.size());
  std::vector<int> bounds(count + 1, n);
  bounds[0] = 0;
  std::size_t next_busy = 0;
  double work = 0.0;
  int t = 1;
  for (int i = 0; i < n && t < count; ++i) {
    while (t < count && work >= total * t / count) {
      bounds[t] = std::max(AlignDown(i), bounds[t - 1] + kAlign);
      ++t;
    }
    const bool is_busy = next_busy < busy.size() && busy[next_busy] == i;
    if (is_busy) ++next_busy;
    work += 1.0 + (is_busy ? busy_work : 0.0);
  }
  for (int u = count - 1; u >= 1; --u) {
    bounds[u] = std::min(bounds[u], AlignDown(bounds[u + 1] - 1));
  }
  return bounds;
}

}  // namespace

SharePlan::SharePlan(int num_nodes, int num_springs, int max_threads)
    : num_nodes_(num_nodes),
      num_springs_(num_springs),
      max_threads_(std::clamp(max_threads, 1, WorkerPool::kMaxShares)) {}

void SharePlan::set_max_threads(int max_threads) {
  max_threads_ = std::clamp(max_threads, 1, WorkerPool::kMaxShares);
  bounds_.clear();
}

int SharePlan::NodeShareCount() const {
  return num_nodes_ >= kParallelSingleNodes ? max_threads_ : 1;
}

SingleShare SharePlan::NodeShare(int t, int count) const {
  if (static_cast<int>(bounds_.size()) == count + 1) return {bounds_[t], bounds_[t + 1]};
  const long long n = num_nodes_;
  return {EqualShareBound(n, t, count), EqualShareBound(n, t + 1, count)};
}

std::vector<SingleShare> SharePlan::NodeShares() const {
  const int count = NodeShareCount();
  std::vector<SingleShare> shares(count);
  for (int t = 0; t < count; ++t) shares[t] = NodeShare(t, count);
  return shares;
}

bool SharePlan::Cut(const std::vector<NodeIndex>& busy, double busy_work) {
  const int count = NodeShareCount();
  std::vector<int> bounds;
  if (count > 1 && !busy.empty() && busy_work > 0.0) {
    bounds = EqualWorkBounds(num_nodes_, count, busy, busy_work);
  }
  if (bounds == bounds_) return false;
  bounds_ = std::move(bounds);
  return true;
}

void SharePlan::Run(int shares, const std::function<void(int)>& task) {
  if (shares <= 1) {
    task(0);
    return;
  }
  WorkerPool& pool = WorkerPool::Shared();
  std::unique_lock<std::mutex> lock(pool.busy(), std::try_to_lock);
  if (lock.owns_lock()) {
    pool.Run(shares, task);
  } else {  // another evaluator (another World's thread) has the pool: the same shares, here
    for (int t = 0; t < shares; ++t) task(t);
  }
}

void SharePlan::RunInTwoParts(int shares, const std::function<void(int)>& first,
                              const std::function<void(int)>& second,
                              const std::function<int(int)>& last_read) {
  if (shares > 1) {
    WorkerPool& pool = WorkerPool::Shared();
    std::unique_lock<std::mutex> lock(pool.busy(), std::try_to_lock);
    if (lock.owns_lock()) {
      pool.RunInTwoParts(shares, first, second, last_read);
      return;
    }
  }
  for (int t = 0; t < shares; ++t) first(t);
  for (int t = 0; t < shares; ++t) second(t);
}

}  // namespace msm_sim::core::internal
