#pragma once

#include <cstddef>
#include <new>
#include <vector>

namespace msm_sim::core {

/// Bytes in a cache line of x86-64 cores.
inline constexpr std::size_t kCacheLineBytes = 64;

/// A std::allocator whose blocks start on a cache line. The single-precision spring loops load
/// 8 floats (32 bytes) at a time from where a run starts: from a block that starts on a cache
/// line, at node and slot indices that are multiples of 8 (SinglePrecisionSprings::kAlignment),
/// no load straddles two lines (std::vector's and Eigen's large blocks start 16 bytes into one,
/// past glibc's header, and a straddling load costs two; docs/physics.md §9).
template <typename T>
struct CacheLineAllocator {
  using value_type = T;
  CacheLineAllocator() = default;
  template <typename U>
  explicit CacheLineAllocator(const CacheLineAllocator<U>& /*other*/) {}
  T* allocate(std::size_t count) {
    return static_cast<T*>(::operator new(count * sizeof(T), std::align_val_t(kCacheLineBytes)));
  }
  void deallocate(T* block, std::size_t /*count*/) {
    ::operator delete(block, std::align_val_t(kCacheLineBytes));
  }
  template <typename U>
  bool operator==(const CacheLineAllocator<U>& /*other*/) const {
    return true;
  }
  template <typename U>
  bool operator!=(const CacheLineAllocator<U>& /*other*/) const {
    return false;
  }
};

/// Floats from the start of a cache line.
using CacheLineFloats = std::vector<float, CacheLineAllocator<float>>;

/// `count` floats rounded up to whole cache lines: blocks of this many floats, laid one after
/// another from the start of a line, each start one.
constexpr long WholeCacheLinesOfFloats(long count) {
  constexpr long kLine = kCacheLineBytes / sizeof(float);
  return (count + kLine - 1) / kLine * kLine;
}

}  // namespace msm_sim::core
