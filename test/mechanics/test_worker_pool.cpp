#include "mechanics/worker_pool.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace msm_sim::core {
namespace {

// Every share of every run is executed exactly once, and Run returns only after all have
// finished (the counts are read right after each Run). Share 0 runs on the caller; the others
// on whichever thread claims them, workers as a rule: a share that takes a while leaves them
// time to.
TEST(WorkerPool, RunsEveryShareOnceAndWaitsForAll) {
  WorkerPool pool(3);
  ASSERT_EQ(pool.workers(), 3);
  std::vector<std::atomic<int>> counts(4);
  int on_workers = 0;
  for (int run = 0; run < 2000; ++run) {
    const int shares = 1 + run % 4;
    for (auto& count : counts) count.store(0);
    std::vector<std::thread::id> ids(4);
    pool.Run(shares, [&](int share) {
      ids[share] = std::this_thread::get_id();
      counts[share].fetch_add(1);
      if (share == 0) std::this_thread::sleep_for(std::chrono::microseconds(50));
    });
    for (int s = 0; s < 4; ++s) ASSERT_EQ(counts[s].load(), s < shares ? 1 : 0) << run;
    EXPECT_EQ(ids[0], std::this_thread::get_id());  // share 0 runs on the caller
    for (int s = 1; s < shares; ++s) on_workers += ids[s] != ids[0];
  }
  // The workers take some of the shares beyond the first; on a busy machine fewer, as the
  // caller claims the shares of a worker not yet awake.
  EXPECT_GT(on_workers, 0);
}

// A worker that has not started yet (here: asleep, its wake-up takes tens of microseconds)
// leaves its share to the caller, who runs it rather than waiting: shares are claimed, not
// assigned. With assigned shares the caller ran share 1 in none of these runs.
TEST(WorkerPool, TheCallerRunsSharesNoWorkerStarted) {
  WorkerPool pool(1);
  int on_caller = 0;
  for (int run = 0; run < 20; ++run) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));  // the worker falls asleep
    std::thread::id ran_share_1;
    pool.Run(2, [&](int share) {
      if (share == 1) ran_share_1 = std::this_thread::get_id();
    });
    on_caller += ran_share_1 == std::this_thread::get_id();
  }
  EXPECT_GE(on_caller, 1);
}

// Runs that come after the workers fell asleep (longer than the spin) still wake them.
TEST(WorkerPool, WakesSleepingWorkers) {
  WorkerPool pool(1);
  for (int run = 0; run < 3; ++run) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    std::atomic<int> done{0};
    pool.Run(2, [&](int) { done.fetch_add(1); });
    EXPECT_EQ(done.load(), 2);
  }
}

// More shares than threads: every share still runs once (without workers, on the caller).
TEST(WorkerPool, RunsMoreSharesThanThreads) {
  for (int workers = 0; workers < 2; ++workers) {
    WorkerPool pool(workers);
    std::vector<std::atomic<int>> counts(5);
    std::vector<std::thread::id> ids(5);
    pool.Run(5, [&](int share) {
      ids[share] = std::this_thread::get_id();
      counts[share].fetch_add(1);
    });
    for (int s = 0; s < 5; ++s) {
      EXPECT_EQ(counts[s].load(), 1) << workers << " workers, share " << s;
      if (s == 0 || workers == 0) {
        EXPECT_EQ(ids[s], std::this_thread::get_id());
      }
    }
  }
}

// While one caller runs a task, the pool's busy() mutex is held, so a second caller (another
// World's thread) sees it taken and runs its shares itself (internal::SharePlan).
TEST(WorkerPool, BusyWhileAnotherCallerRuns) {
  WorkerPool pool(1);
  std::atomic<bool> started{false};
  std::atomic<int> done{0};
  std::thread other([&] {
    std::lock_guard<std::mutex> lock(pool.busy());
    pool.Run(2, [&](int) {
      started.store(true);
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      done.fetch_add(1);
    });
  });
  while (!started.load()) std::this_thread::yield();
  std::unique_lock<std::mutex> lock(pool.busy(), std::try_to_lock);
  EXPECT_FALSE(lock.owns_lock());
  other.join();
  EXPECT_EQ(done.load(), 2);
  std::unique_lock<std::mutex> after(pool.busy(), std::try_to_lock);
  EXPECT_TRUE(after.owns_lock());
}

// RunInTwoParts: every share's first and second part run once, and each second part only after
// the first parts of the later shares it reads. With a worker awake (the first runs) or asleep
// (the last ones: the caller then runs the shares no one claimed inside its own wait), with more
// shares than threads, and without workers.
TEST(WorkerPool, SecondPartsWaitForTheFirstPartsTheyRead) {
  for (const int workers : {0, 1, 3}) {
    WorkerPool pool(workers);
    for (int run = 0; run < 600; ++run) {
      const int shares = 1 + run % 6;
      if (run >= 580) std::this_thread::sleep_for(std::chrono::milliseconds(3));
      std::vector<std::atomic<int>> firsts(shares), seconds(shares);
      std::atomic<int> early{0};
      const auto last_read = [shares](int share) { return std::min(share + 2, shares - 1); };
      pool.RunInTwoParts(
          shares,
          [&](int share) {
            if (share == shares - 1) std::this_thread::sleep_for(std::chrono::microseconds(30));
            firsts[share].fetch_add(1);
          },
          [&](int share) {
            for (int later = share + 1; later <= last_read(share); ++later) {
              if (firsts[later].load() != 1) early.fetch_add(1);
            }
            seconds[share].fetch_add(1);
          },
          last_read);
      EXPECT_EQ(early.load(), 0) << workers << " workers, run " << run;
      for (int s = 0; s < shares; ++s) {
        ASSERT_EQ(firsts[s].load(), 1) << workers << " workers, run " << run << ", share " << s;
        ASSERT_EQ(seconds[s].load(), 1) << workers << " workers, run " << run << ", share " << s;
      }
    }
  }
}

}  // namespace
}  // namespace msm_sim::core
