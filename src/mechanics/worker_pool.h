#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace msm_sim::core {

/// Threads that run the shares of one task beside the caller: the spring passes' parallel
/// loop. A share is a fixed index range chosen by the caller, so results do not depend on which
/// thread runs it.
///
/// Shares are claimed, not assigned: the caller runs share 0, then claims whatever share no
/// worker has started, so a worker that the scheduler keeps off its core (another process busy
/// on it) delays nothing but the share it already holds.
///
/// Why not OpenMP's fork-join: its barrier spins before it sleeps, and on a machine whose other
/// core is busy (a robot stack, a build) the spinning thread holds the only free core while the
/// thread it waits for cannot run. A waiting thread here yields instead, so the scheduler runs
/// the awaited thread on that core at once, and after kSpinIterations yields sleeps on a
/// condition variable (docs/design/threads-default.md has the measurements).
class WorkerPool {
 public:
  /// Starts `workers` threads (0 is allowed: Run then runs share 0 only, on the caller).
  explicit WorkerPool(int workers);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int workers() const { return static_cast<int>(threads_.size()); }

  /// Runs task(s) once for each s = 0 .. shares - 1, share 0 on the calling thread and each
  /// other share on whichever thread claims it first (the woken workers, or the caller once
  /// its own share is done), and returns when all have finished. Preconditions:
  /// 1 <= shares <= kMaxShares; task does not throw; one Run at a time (callers serialise
  /// through `busy()`).
  void Run(int shares, const std::function<void(int)>& task);
  static constexpr int kMaxShares = 4095;

  /// Runs first(s), then second(s), for each s = 0 .. shares - 1, where second(s) reads what
  /// first(s') wrote for the shares s' = s + 1 .. last_read(s) (a spring loop reading the nodes
  /// just past its share, which the next shares move): second(s) waits for those first parts
  /// only, not for every share as a second Run would. A share whose first part it needs and
  /// that no thread has claimed yet, it runs itself, so a worker kept off its core delays the
  /// others no more than in Run. Without workers, or with one share: every first part, then
  /// every second part. Preconditions as for Run; s < last_read(s) < shares, or
  /// last_read(s) <= s for none; first(s) waits for nothing.
  void RunInTwoParts(int shares, const std::function<void(int)>& first,
                     const std::function<void(int)>& second,
                     const std::function<int(int)>& last_read);

  /// Held by the caller of Run for its duration; a caller that cannot take it (another thread
  /// is running a task) runs its shares itself.
  std::mutex& busy() { return busy_; }

  /// The process-wide pool: one worker per hardware thread beyond the first, started on first
  /// use.
  static WorkerPool& Shared();

 private:
  static constexpr int kSpinIterations = 2'000;
  static constexpr int kClaimAfter = 100;

  void WorkerLoop(int index);
  /// Claims the next unstarted share of run `run` into *share; false once none is left or
  /// another run has begun.
  bool Claim(std::uint64_t run, int* share);
  /// Claims share `share` of run `run` if it is the next unclaimed one, and runs it here.
  bool RunIfUnclaimed(std::uint64_t run, int share);
  /// Runs task_(share) and counts it as done.
  void RunShare(int share);
  /// Runs the shares of run `run` this thread claims, counting each as done.
  void RunClaimedShares(std::uint64_t run);
  bool HasWork(int index, std::uint64_t seen) const;
  void WaitForWork(int index, std::uint64_t seen);
  void WaitUntilDone();

  // Worker w looks for shares of run tickets_[w] whenever that moves past the value it last
  // saw: only the workers a Run needs are woken.
  std::unique_ptr<std::atomic<std::uint64_t>[]> tickets_;
  // The run number (high 40 bits), its share count (12 bits) and its next unclaimed share (low
  // 12 bits), in one word: a claim is one compare-and-swap, and a worker that wakes for a run
  // that has ended finds another run number and claims nothing. task_ is written before the
  // word, and no claim of the run succeeds once its last share is done, so a thread that
  // claimed a share reads the run's task.
  std::atomic<std::uint64_t> claims_{0};
  std::vector<std::thread> threads_;
  std::mutex busy_;
  const std::function<void(int)>* task_ = nullptr;
  std::uint64_t runs_ = 0;
  std::atomic<int> pending_{0};
  std::atomic<bool> stop_{false};
  // RunInTwoParts: the run whose first part share s has finished (one cache line each, as
  // different threads write them).
  struct alignas(64) FirstPartDone {
    std::atomic<std::uint64_t> run{0};
  };
  std::unique_ptr<FirstPartDone[]> first_done_;
  std::mutex wake_mutex_;
  std::condition_variable wake_;
  std::mutex done_mutex_;
  std::condition_variable done_;
};

}  // namespace msm_sim::core
