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
/// Why not OpenMP's fork-join: its barrier spins before it sleeps, and with two threads on a
/// machine whose other core is busy (a robot stack, a build) the spinning thread held the only
/// free core while the thread it waited for could not run: an 8,125-node step ran at 0.30 of
/// one thread's speed (0.22 with a pause-based spin here). A waiting thread here yields instead,
/// so the scheduler runs the awaited thread on that core at once (0.77), and after
/// kSpinIterations yields (about a millisecond) sleeps on a condition variable. Idle, yielding
/// costs nothing: the yield returns at once.
class WorkerPool {
 public:
  /// Starts `workers` threads (0 is allowed: Run then runs share 0 only, on the caller).
  explicit WorkerPool(int workers);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int workers() const { return static_cast<int>(threads_.size()); }

  /// Runs task(s) for s = 0 .. shares - 1, share 0 on the calling thread, share s on worker
  /// s - 1 while there are workers and on the caller beyond, and returns when all have
  /// finished. Preconditions: shares >= 1; task does not throw; one Run at a time (callers
  /// serialise through `busy()`).
  void Run(int shares, const std::function<void(int)>& task);

  /// Held by the caller of Run for its duration; a caller that cannot take it (another thread
  /// is running a task) runs its shares itself.
  std::mutex& busy() { return busy_; }

  /// The process-wide pool: one worker per hardware thread beyond the first, started on first
  /// use.
  static WorkerPool& Shared();

 private:
  static constexpr int kSpinIterations = 2'000;

  void WorkerLoop(int index);
  bool HasWork(int index, std::uint64_t seen) const;
  void WaitForWork(int index, std::uint64_t seen);
  void WaitUntilDone();

  // Worker w runs share w + 1 of task_ whenever tickets_[w] moves past the value it last saw:
  // only the workers a Run needs are woken, and the task is written before their tickets, so
  // no worker reads it while the next Run writes it.
  std::unique_ptr<std::atomic<std::uint64_t>[]> tickets_;
  std::vector<std::thread> threads_;
  std::mutex busy_;
  const std::function<void(int)>* task_ = nullptr;
  std::uint64_t runs_ = 0;
  std::atomic<int> pending_{0};
  std::atomic<bool> stop_{false};
  std::mutex wake_mutex_;
  std::condition_variable wake_;
  std::mutex done_mutex_;
  std::condition_variable done_;
};

}  // namespace msm_sim::core
