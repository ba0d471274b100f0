#pragma once

#include <cstdlib>
#include <thread>

namespace msm_sim::core {

// The threads the benchmarks give the spring passes (WorldOptions::threads): the environment's
// MSM_SIM_THREADS (picks a column of the README's tables), else every hardware thread. A
// World's own default is one.
inline int BenchThreads() {
  if (const char* text = std::getenv("MSM_SIM_THREADS")) {
    const int threads = std::atoi(text);
    if (threads >= 1) return threads;
  }
  const int hardware = static_cast<int>(std::thread::hardware_concurrency());
  return hardware >= 1 ? hardware : 1;
}

}  // namespace msm_sim::core
