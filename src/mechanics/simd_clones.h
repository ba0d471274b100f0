#pragma once

// MSM_SIM_SIMD_CLONES before a function compiles it three times, for AVX-512 (x86-64-v4), for
// AVX2 + FMA (x86-64-v3) and for baseline x86-64, and the loader picks the CPU's version (GCC's
// target_clones); with other compilers once, for the baseline. AVX2 + FMA doubles the lanes of
// the baseline's SSE2. The AVX-512 version keeps 256-bit vectors (-mprefer-vector-width=256,
// CMakeLists.txt) and gains 32 vector registers and masked tails (docs/physics.md §9; the gains:
// docs/design/single-precision-springs.md). The AVX-512 and AVX2 versions contract the same
// operations into FMAs, so they give the same results to the bit (checked on the realtime
// block's peak force with the run loops, before the block loops of single_precision_kernels.cpp);
// the baseline has no FMA. The spring loops' files use it.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define MSM_SIM_SIMD_CLONES \
  __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define MSM_SIM_SIMD_CLONES
#endif
