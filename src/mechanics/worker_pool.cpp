#include "mechanics/worker_pool.h"

#include <algorithm>

namespace msm_sim::core {
namespace {

// A waiting thread yields rather than pauses: on an idle machine yield returns at once (a spin),
// and when the thread it waits for is runnable on the same core (the other core busy with
// another process) the scheduler runs that thread now, instead of after this one's time slice.
inline void LetOthersRun() { std::this_thread::yield(); }

}  // namespace

WorkerPool::WorkerPool(int workers)
    : tickets_(std::make_unique<std::atomic<std::uint64_t>[]>(std::max(workers, 0))),
      first_done_(std::make_unique<FirstPartDone[]>(kMaxShares)) {
  threads_.reserve(static_cast<std::size_t>(std::max(workers, 0)));
  for (int w = 0; w < workers; ++w) {
    tickets_[w].store(0, std::memory_order_relaxed);
    threads_.emplace_back([this, w] { WorkerLoop(w); });
  }
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(wake_mutex_);
    stop_.store(true, std::memory_order_release);
  }
  wake_.notify_all();
  for (std::thread& thread : threads_) thread.join();
}

WorkerPool& WorkerPool::Shared() {
  static WorkerPool pool(std::max(1, static_cast<int>(std::thread::hardware_concurrency())) - 1);
  return pool;
}

namespace {

constexpr int kShareBits = 12;
constexpr std::uint64_t kShareMask = (std::uint64_t{1} << kShareBits) - 1;

std::uint64_t ClaimWord(std::uint64_t run, int shares, int next) {
  return (run << (2 * kShareBits)) | (static_cast<std::uint64_t>(shares) << kShareBits) |
         static_cast<std::uint64_t>(next);
}

}  // namespace

void WorkerPool::Run(int shares, const std::function<void(int)>& task) {
  if (workers() == 0 || shares <= 1) {
    for (int share = 0; share < shares; ++share) task(share);
    return;
  }
  task_ = &task;
  pending_.store(shares - 1, std::memory_order_relaxed);
  ++runs_;
  claims_.store(ClaimWord(runs_, shares, 1), std::memory_order_release);
  {
    // The tickets move under the mutex a worker checks them under before it sleeps, so it
    // cannot miss the notification.
    std::lock_guard<std::mutex> lock(wake_mutex_);
    const int woken = std::min(shares - 1, workers());
    for (int w = 0; w < woken; ++w) tickets_[w].store(runs_, std::memory_order_release);
  }
  wake_.notify_all();
  task(0);
  RunClaimedShares(runs_);  // the shares no worker has started
  WaitUntilDone();
}

bool WorkerPool::Claim(std::uint64_t run, int* share) {
  std::uint64_t word = claims_.load(std::memory_order_acquire);
  for (;;) {
    const int shares = static_cast<int>((word >> kShareBits) & kShareMask);
    const int next = static_cast<int>(word & kShareMask);
    if ((word >> (2 * kShareBits)) != run || next >= shares) return false;
    if (claims_.compare_exchange_weak(word, word + 1, std::memory_order_acq_rel,
                                      std::memory_order_acquire)) {
      *share = next;
      return true;
    }
  }
}

void WorkerPool::RunShare(int share) {
  (*task_)(share);
  if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
    std::lock_guard<std::mutex> lock(done_mutex_);
    done_.notify_one();
  }
}

void WorkerPool::RunClaimedShares(std::uint64_t run) {
  int share = 0;
  while (Claim(run, &share)) RunShare(share);
}

bool WorkerPool::RunIfUnclaimed(std::uint64_t run, int share) {
  std::uint64_t word = claims_.load(std::memory_order_acquire);
  if (word != ClaimWord(run, static_cast<int>((word >> kShareBits) & kShareMask), share)) {
    return false;  // another run, or `share` claimed already (claims go in share order)
  }
  if (!claims_.compare_exchange_strong(word, word + 1, std::memory_order_acq_rel,
                                       std::memory_order_acquire)) {
    return false;  // a worker claimed it just now
  }
  RunShare(share);
  return true;
}

void WorkerPool::RunInTwoParts(int shares, const std::function<void(int)>& first,
                               const std::function<void(int)>& second,
                               const std::function<int(int)>& last_read) {
  if (workers() == 0 || shares <= 1) {
    for (int share = 0; share < shares; ++share) first(share);
    for (int share = 0; share < shares; ++share) second(share);
    return;
  }
  const std::uint64_t run = runs_ + 1;  // the number Run gives this run
  const std::function<void(int)> task = [&](int share) {
    first(share);
    first_done_[share].run.store(run, std::memory_order_release);
    // Every claimed share finishes its first part without waiting (a precondition), so these
    // waits end: on a share no thread has claimed, by running it here, but only after a grace
    // of kClaimAfter yields, in which a worker that is waking up claims it (run here at once,
    // a share's nodes went to the caller's core whenever its worker was a microsecond late).
    for (int later = share + 1; later <= last_read(share); ++later) {
      for (int i = 0; first_done_[later].run.load(std::memory_order_acquire) != run; ++i) {
        if (i < kClaimAfter || !RunIfUnclaimed(run, later)) LetOthersRun();
      }
    }
    second(share);
  };
  Run(shares, task);
}

void WorkerPool::WorkerLoop(int index) {
  std::uint64_t seen = 0;
  for (;;) {
    WaitForWork(index, seen);
    if (stop_.load(std::memory_order_acquire)) return;
    seen = tickets_[index].load(std::memory_order_acquire);
    RunClaimedShares(seen);
  }
}

bool WorkerPool::HasWork(int index, std::uint64_t seen) const {
  return tickets_[index].load(std::memory_order_acquire) != seen ||
         stop_.load(std::memory_order_acquire);
}

void WorkerPool::WaitForWork(int index, std::uint64_t seen) {
  for (int i = 0; i < kSpinIterations; ++i) {
    if (HasWork(index, seen)) return;
    LetOthersRun();
  }
  std::unique_lock<std::mutex> lock(wake_mutex_);
  wake_.wait(lock, [&] { return HasWork(index, seen); });
}

void WorkerPool::WaitUntilDone() {
  for (int i = 0; i < kSpinIterations; ++i) {
    if (pending_.load(std::memory_order_acquire) == 0) return;
    LetOthersRun();
  }
  std::unique_lock<std::mutex> lock(done_mutex_);
  done_.wait(lock, [&] { return pending_.load(std::memory_order_acquire) == 0; });
}

}  // namespace msm_sim::core
