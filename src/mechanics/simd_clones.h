#pragma once

// MSM_SIM_SIMD_CLONES before a function compiles it twice, for AVX2 + FMA (x86-64-v3) and for
// baseline x86-64, and the loader picks the CPU's version (GCC's target_clones); with other
// compilers once, for the baseline. AVX2 + FMA doubles the lanes of the baseline's SSE2
// (measured 1.8x on the double plain pass). The spring loops' files use it.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define MSM_SIM_SIMD_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define MSM_SIM_SIMD_CLONES
#endif
