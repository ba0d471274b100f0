#pragma once
// Shared by the tests that feed damaged files to a reader: runs a function in a forked child,
// optionally under an address-space limit and an alarm, and reports how the child ended, its
// wall time and its peak resident memory. A reader that crashes, hangs or runs out of memory
// then fails the test instead of taking the test binary (or the machine) down with it.

#include <sys/resource.h>
#include <sys/time.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <exception>
#include <fstream>
#include <string>

namespace msm_sim::testing {

/// Exit code of a child whose function threw something other than the expected error.
inline constexpr int kUnexpectedException = 3;

struct ChildRun {
  bool exited = false;        ///< ended by _exit (not by a signal)
  int exit_code = -1;         ///< when exited
  int signal = 0;             ///< when not exited
  double seconds = 0;         ///< wall time, fork to reaped
  double max_rss_mb = 0;      ///< the child's peak resident memory, what it inherited included
  double rss_at_fork_mb = 0;  ///< the parent's resident memory when it forked

  /// The resident memory to hold against a bound: the child's peak, or under AddressSanitizer
  /// what the child added to the parent's pages it started with (by the time the readers' tests
  /// run, the parent's shadow memory and quarantine are about 740 MB of every child's peak).
  double bounded_rss_mb() const {
#ifdef __SANITIZE_ADDRESS__
    return max_rss_mb - rss_at_fork_mb;
#else
    return max_rss_mb;
#endif
  }

  std::string Describe() const {
    return exited ? "exit " + std::to_string(exit_code)
                  : "signal " + std::to_string(signal) + " (" + strsignal(signal) + ")";
  }
};

/// This process's resident memory (MB, VmRSS), 0 if /proc does not say.
inline double ResidentMb() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return 0.0;
}

/// Runs `body` (returning the exit code) in a forked child; `address_space_bytes` (0: none) limits
/// its virtual memory (RLIMIT_AS: a large allocation fails with std::bad_alloc instead of
/// growing), `alarm_seconds` (0: none) ends it with SIGALRM if it takes longer. An exception
/// escaping `body` exits with kUnexpectedException. The parent must not hold locks other threads
/// could need (gtest runs tests on one thread).
template <typename Body>
ChildRun RunInChild(Body&& body, std::uint64_t address_space_bytes, unsigned alarm_seconds) {
  const double rss_at_fork_mb = ResidentMb();
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
#ifndef __SANITIZE_ADDRESS__
    if (address_space_bytes > 0) {
      const rlimit limit{address_space_bytes, address_space_bytes};
      setrlimit(RLIMIT_AS, &limit);
    }
#else
    // AddressSanitizer reserves terabytes of shadow address space at start-up, so any cap on the
    // address space fails its own allocations (make test-sanitize); the alarm still applies, and
    // ASan ends a child whose allocation exceeds its own limit (exit code 86, a failure here).
    (void)address_space_bytes;
#endif
    if (alarm_seconds > 0) alarm(alarm_seconds);
    int code = kUnexpectedException;
    try {
      code = body();
    } catch (...) {
    }
    _exit(code);  // no atexit handlers, no gtest teardown in the child
  }
  ChildRun run;
  run.rss_at_fork_mb = rss_at_fork_mb;
  if (pid < 0) return run;
  int status = 0;
  rusage usage{};
  while (wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
  }
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.max_rss_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB
  run.exited = WIFEXITED(status);
  run.exit_code = run.exited ? WEXITSTATUS(status) : -1;
  run.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  return run;
}

}  // namespace msm_sim::testing
