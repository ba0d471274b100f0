#pragma once

// The single loops' blocks (SinglePrecisionSprings::Blocks), for single_precision_kernels.cpp
// only: every function here is inlined into that file's SIMD clones (simd_clones.h), each
// compiled for its own instructions.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <type_traits>

#include "mechanics/single_precision_kernels.h"
#include "mechanics/spring_arithmetic.h"

namespace msm_sim::core::internal {

// The blocks' loops (SinglePrecisionSprings::Blocks) in GCC's vector types of 8 floats, so that
// a block's a ends are values, held in registers across a group's offsets. Each clone lowers them
// to its own instructions (two SSE halves for the baseline). The types never cross a call
// (everything here is inlined), so the ABI note GCC gives for 32-byte vectors does not apply.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
constexpr int kLanes = SinglePrecisionSprings::kAlignment;
using Lanes = float __attribute__((vector_size(kLanes * sizeof(float))));

inline __attribute__((always_inline)) Lanes Load(const float* from) {
  Lanes lanes;
  std::memcpy(&lanes, from, sizeof lanes);
  return lanes;
}
inline __attribute__((always_inline)) void Store(float* to, Lanes lanes) {
  std::memcpy(to, &lanes, sizeof lanes);
}
inline __attribute__((always_inline)) Lanes Sqrt(Lanes x) {
  Lanes root;
  for (int l = 0; l < kLanes; ++l) root[l] = std::sqrt(x[l]);  // one SIMD square root
  return root;
}

// Subtracts `lanes` from the b ends' floats at nodes [b, b + 8): in place (`shared`) below
// `limit`, else in the share's overflow (`overflow`, from node `limit`). kInPlace: all below.
template <bool kInPlace>
inline __attribute__((always_inline)) void SubtractAtBEnds(Lanes lanes, int b, int limit,
                                                           float* shared, float* overflow) {
  if (kInPlace || b + kLanes <= limit) {
    Store(shared + b, Load(shared + b) - lanes);
  } else if (b >= limit) {
    Store(overflow + (b - limit), Load(overflow + (b - limit)) - lanes);
  } else {  // across the limit
    for (int l = 0; l < kLanes; ++l)
      (b + l < limit ? shared[b + l] : overflow[b + l - limit]) -= lanes[l];
  }
}

// The blocks of a share's nodes [begin, end): from the first block at `begin` (a multiple of 8)
// to the last one that holds a node below `end`, at most `count`.
struct BlockRange {
  int first, last;  // [first, last)
  BlockRange(const SingleShare& share, int count)
      : first(share.begin / kLanes), last(std::min((share.end + kLanes - 1) / kLanes, count)) {}
};

// Whether every b end of block k lies below `limit` (or no later share exists: a share's nodes
// up to the model's last, whose arrays reach every phantom; SinglePrecisionSprings::PaddedNodes).
inline bool BlockInPlace(int k, int max_offset, int limit, int nodes) {
  return limit >= nodes || kLanes * (k + 1) + max_offset <= limit;
}

// The offsets of a group (SinglePrecisionSprings::Blocks), and where its slots start.
struct OffsetGroup {
  const int* first;
  const int* last;
  const int* begin() const { return first; }
  const int* end() const { return last; }
  const float* slots;  // of its first block
  std::size_t per_block;
  // The first group stores the a ends' sums, the others add them: the a ends' arrays of a share
  // its blocks take need no clearing (SingleLoopsByBlocks).
  bool first_group;
};

// Calls block(in_place, k, slots, group) for each group of offsets in turn, and in it for the
// blocks k of `share` from the last down (a node's b-end sum then takes its slots in order of
// offset, whatever blocks ran before: NodeStages::rounds_ahead's early part runs a share's last
// blocks first). in_place: std::true_type where every b end of block k lies below share.limit
// (BlockInPlace), else std::false_type. Precondition: share.begin a multiple of 8.
template <typename Block>
inline __attribute__((always_inline)) void SweepBlocks(const SinglePrecisionSprings& springs,
                                                       const SingleShare& share, Block&& block) {
  const SinglePrecisionSprings::Blocks& blocks = springs.blocks;
  const BlockRange range(share, blocks.count);
  int begin = 0;
  for (const int end : blocks.group_ends) {
    const std::size_t per_block = std::size_t{4} * kLanes * (end - begin);
    const OffsetGroup group{blocks.offsets.data() + begin, blocks.offsets.data() + end,
                            blocks.slots.data() + std::size_t{4} * kLanes * begin * blocks.count,
                            per_block, begin == 0};
    for (int k = range.last - 1; k >= range.first; --k) {
      const float* slots = group.slots + group.per_block * k;
      if (BlockInPlace(k, springs.max_offset, share.limit, springs.num_nodes)) {
        block(std::true_type{}, k, slots, group);
      } else {
        block(std::false_type{}, k, slots, group);
      }
    }
    begin = end;
  }
}

// The eMSM first pass over block k (InflowRun's sums): J_a's sum over the block's offsets in
// registers, added once; J_b per offset.
template <bool kInPlace>
inline __attribute__((always_inline)) void InflowBlock(int k, const float* slots,
                                                       const OffsetGroup& offsets, const float* px,
                                                       const float* py, const float* pz, float* j_a,
                                                       float* j_b, float* j_b_overflow, int limit) {
  const int a = kLanes * k;
  const Lanes xa = Load(px + a), ya = Load(py + a), za = Load(pz + a);
  Lanes sum = {};
  for (const int d : offsets) {
    const int b = a + d;
    const Lanes rx = Load(px + b) - xa, ry = Load(py + b) - ya, rz = Load(pz + b) - za;
    const Lanes stretch = Sqrt(rx * rx + ry * ry + rz * rz) - Load(slots + kLanes);
    sum += Load(slots + 2 * kLanes) * stretch;
    SubtractAtBEnds<kInPlace>(-(Load(slots + 3 * kLanes) * stretch), b, limit, j_b, j_b_overflow);
    slots += 4 * kLanes;
  }
  Store(j_a + a, offsets.first_group ? sum : Load(j_a + a) + sum);
}

// InflowBlock over the blocks of `share` (SweepBlocks).
inline __attribute__((always_inline)) void InflowBlocks(const SinglePrecisionSprings& springs,
                                                        const SingleShare& share,
                                                        const SingleNodeArrays& p, float* j_a,
                                                        float* j_b, float* j_b_overflow) {
  const float *px = p.x, *py = p.y, *pz = p.z;
  SweepBlocks(
      springs, share,
      [&](auto in_place, int k, const float* slots, const OffsetGroup& group)
          __attribute__((always_inline)) {
            InflowBlock<decltype(in_place)::value>(k, slots, group, px, py, pz, j_a, j_b,
                                                   j_b_overflow, share.limit);
          });
}

// The node arrays and forces of a block's loop, as locals (read through the structs, GCC loaded
// the pointers again after every store).
struct BlockArrays {
  const float *px, *py, *pz, *vx, *vy, *vz, *g;
  float *fax, *fay, *faz, *fbx, *fby, *fbz, *ox, *oy, *oz;
};

// The plain pass, or the eMSM second pass when Dispersed, over block k (SpringForcesAlongRun's
// forces, spring_run_loops.h): the a ends' sums over the block's offsets in registers, added
// once; the b ends' per offset.
template <bool Damped, bool Dispersed, bool kInPlace>
inline __attribute__((always_inline)) void ForceBlock(int k, const float* slots,
                                                      const OffsetGroup& offsets,
                                                      const BlockArrays& m, float beta, int limit) {
  const int a = kLanes * k;
  const Lanes xa = Load(m.px + a), ya = Load(m.py + a), za = Load(m.pz + a);
  Lanes vxa = {}, vya = {}, vza = {}, ga = {};
  if constexpr (Damped) vxa = Load(m.vx + a), vya = Load(m.vy + a), vza = Load(m.vz + a);
  if constexpr (Dispersed) ga = Load(m.g + a);
  Lanes sum_x = {}, sum_y = {}, sum_z = {};
  for (const int d : offsets) {
    const int b = a + d;
    const Lanes rx = Load(m.px + b) - xa, ry = Load(m.py + b) - ya, rz = Load(m.pz + b) - za;
    const Lanes length = Sqrt(rx * rx + ry * ry + rz * rz);
    const Lanes inverse_length = 1.0f / (length + 1e-30f);  // as InverseLength (float)
    const Lanes stiffness = Load(slots);
    Lanes t = ElasticTension(stiffness, length, Load(slots + kLanes));
    if constexpr (Dispersed) {
      t += DispersedTension(Load(slots + 2 * kLanes), ga, Load(slots + 3 * kLanes), Load(m.g + b));
    }
    if constexpr (Damped) {
      const Lanes rate =
          StretchRate(Load(m.vx + b) - vxa, Load(m.vy + b) - vya, Load(m.vz + b) - vza, rx, ry, rz);
      t += DamperTension(beta * stiffness, rate, inverse_length);
    }
    const Lanes scale = t * inverse_length;
    const Lanes sx = scale * rx, sy = scale * ry, sz = scale * rz;
    sum_x += sx;
    sum_y += sy;
    sum_z += sz;
    SubtractAtBEnds<kInPlace>(sx, b, limit, m.fbx, m.ox);
    SubtractAtBEnds<kInPlace>(sy, b, limit, m.fby, m.oy);
    SubtractAtBEnds<kInPlace>(sz, b, limit, m.fbz, m.oz);
    slots += 4 * kLanes;
  }
  Store(m.fax + a, offsets.first_group ? sum_x : Load(m.fax + a) + sum_x);
  Store(m.fay + a, offsets.first_group ? sum_y : Load(m.fay + a) + sum_y);
  Store(m.faz + a, offsets.first_group ? sum_z : Load(m.faz + a) + sum_z);
}

// ForceBlock over the blocks of `share` (SweepBlocks).
template <bool Damped, bool Dispersed>
inline __attribute__((always_inline)) void ForceBlocks(
    const SinglePrecisionSprings& springs, const SingleShare& share, const SingleNodeArrays& p,
    const SingleNodeArrays* velocities, float beta, const float* g, const SingleEndForces& forces,
    const MutableSingleNodeArrays& overflow) {
  const SingleNodeArrays v = velocities != nullptr ? *velocities : SingleNodeArrays{};
  const BlockArrays m{p.x,        p.y,        p.z,        v.x,        v.y,        v.z,
                      g,          forces.a.x, forces.a.y, forces.a.z, forces.b.x, forces.b.y,
                      forces.b.z, overflow.x, overflow.y, overflow.z};
  SweepBlocks(
      springs, share,
      [&](auto in_place, int k, const float* slots, const OffsetGroup& group)
          __attribute__((always_inline)) {
            ForceBlock<Damped, Dispersed, decltype(in_place)::value>(k, slots, group, m, beta,
                                                                     share.limit);
          });
}
#pragma GCC diagnostic pop

}  // namespace msm_sim::core::internal
