// Compiled with -fno-math-errno (CMakeLists.txt), as force_kernels.cpp: std::sqrt then becomes
// one SIMD instruction, which lets the loops vectorise.

#include "mechanics/single_precision_kernels.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <type_traits>
#include <utility>

#include "mechanics/simd_clones.h"

namespace msm_sim::core {

std::shared_ptr<const SinglePrecisionSprings> SinglePrecisionSprings::Schedule(const Model& model) {
  const int count = model.num_springs();
  const auto& node_a = model.spring_node_a();
  const auto& node_b = model.spring_node_b();
  // Each spring oriented a < b (its end weights swapped with it), sorted by offset, then a.
  std::vector<SpringIndex> order(count);
  std::iota(order.begin(), order.end(), 0);
  const auto low = [&](SpringIndex s) { return std::min(node_a[s], node_b[s]); };
  const auto offset = [&](SpringIndex s) { return std::abs(node_b[s] - node_a[s]); };
  std::stable_sort(order.begin(), order.end(), [&](SpringIndex i, SpringIndex j) {
    return offset(i) != offset(j) ? offset(i) < offset(j) : low(i) < low(j);
  });
  auto springs = std::make_shared<SinglePrecisionSprings>();
  SinglePrecisionSprings& out = *springs;
  const auto add_slot = [&](float k, float rest, float outflow_a, float outflow_b) {
    out.stiffness.push_back(k);
    out.rest.push_back(rest);
    out.outflow_a.push_back(outflow_a);
    out.outflow_b.push_back(outflow_b);
  };
  for (int p = 0; p < count; ++p) {
    const SpringIndex s = order[p];
    const int a = low(s);
    SingleRun* run = out.runs.empty() ? nullptr : &out.runs.back();
    const int gap = run != nullptr ? a - (run->a0 + run->count) : -1;
    const bool extend = run != nullptr && run->offset == offset(s) && gap >= 0 && gap <= kMaxGap &&
                        run->count + gap < kMaxRunLength;
    if (extend) {
      for (int g = 0; g < gap; ++g) add_slot(0.0f, 0.0f, 0.0f, 0.0f);
      out.num_phantoms += gap;
      run->count += gap + 1;
    } else {
      // A run starts at a node and a slot that are multiples of kAlignment: phantoms from the
      // aligned node on, and unused zero slots before them.
      const int a0 = a - a % kAlignment;
      const int unused = (kAlignment - out.num_slots() % kAlignment) % kAlignment;
      for (int g = 0; g < unused + (a - a0); ++g) add_slot(0.0f, 0.0f, 0.0f, 0.0f);
      out.num_phantoms += unused + (a - a0);
      out.runs.push_back({out.num_slots() - (a - a0), a0, offset(s), a - a0 + 1});
    }
    out.max_offset = std::max(out.max_offset, offset(s));
    const bool swapped = node_a[s] > node_b[s];
    const double k = model.spring_stiffness()[s];
    const double rest = model.spring_rest_length()[s];
    const double outflow_a = model.dispersion_weight_a()[s] * rest * k;
    const double outflow_b = model.dispersion_weight_b()[s] * rest * k;
    add_slot(static_cast<float>(k), static_cast<float>(rest),
             static_cast<float>(swapped ? outflow_b : outflow_a),
             static_cast<float>(swapped ? outflow_a : outflow_b));
  }
  out.num_nodes = model.num_nodes();
  out.blocks = ScheduleBlocks(out);
  return springs;
}

SinglePrecisionSprings::Blocks SinglePrecisionSprings::ScheduleBlocks(
    const SinglePrecisionSprings& runs) {
  std::vector<int> sorted;  // the distinct offsets, ascending (runs are sorted by offset)
  for (const SingleRun& run : runs.runs) {
    if (sorted.empty() || sorted.back() != run.offset) sorted.push_back(run.offset);
  }
  Blocks blocks;
  const int offsets = static_cast<int>(sorted.size());
  blocks.count = (runs.num_nodes + kAlignment - 1) / kAlignment;
  const double block_slots = static_cast<double>(blocks.count) * kAlignment * offsets;
  const int springs = runs.num_slots() - runs.num_phantoms;
  if (offsets == 0 || offsets > kMaxBlockOffsets || springs < kMinBlockOccupancy * block_slots ||
      runs.num_nodes > kMaxBlockNodes) {
    return {};
  }
  // Groups of offsets whose b ends' stores never partly overlap a load soon after
  // (offsets a multiple of 8 apart hit the same 8 nodes, or at least kGroupSeparation apart):
  // a load that partly overlaps a store still in flight waits for it to retire (offsets 39,
  // 40 and 41 in one sweep made the blocks no faster than the runs).
  std::vector<std::vector<int>> groups;
  for (const int d : sorted) {
    const auto fits = [d](const std::vector<int>& group) {
      return std::all_of(group.begin(), group.end(), [d](int other) {
        return (d - other) % kAlignment == 0 || d - other >= kGroupSeparation;
      });
    };
    auto group = std::find_if(groups.begin(), groups.end(), fits);
    if (group == groups.end()) group = groups.insert(groups.end(), std::vector<int>{});
    group->push_back(d);
  }
  std::vector<int> group_of(offsets), index_in_group(offsets);  // by position in `sorted`
  for (std::size_t g = 0; g < groups.size(); ++g) {
    for (std::size_t j = 0; j < groups[g].size(); ++j) {
      const int o =
          static_cast<int>(std::find(sorted.begin(), sorted.end(), groups[g][j]) - sorted.begin());
      group_of[o] = static_cast<int>(g);
      index_in_group[o] = static_cast<int>(j);
      blocks.offsets.push_back(groups[g][j]);
    }
    blocks.group_ends.push_back(static_cast<int>(blocks.offsets.size()));
  }
  // Each slot of the runs into its group, block, offset and lane; a phantom's zeros stay zeros.
  constexpr int kFields = 4;
  blocks.slots.assign(static_cast<std::size_t>(block_slots) * kFields, 0.0f);
  int o = 0;
  for (const SingleRun& run : runs.runs) {
    while (sorted[o] != run.offset) ++o;
    const int g = group_of[o];
    const std::size_t group_begin = g == 0 ? 0 : blocks.group_ends[g - 1];
    const std::size_t group_size = blocks.group_ends[g] - group_begin;
    for (int i = 0; i < run.count; ++i) {
      const int slot = run.first + i, a = run.a0 + i;
      if (runs.stiffness[slot] == 0.0f && runs.outflow_a[slot] == 0.0f &&
          runs.outflow_b[slot] == 0.0f) {
        continue;  // a phantom (or a spring of no force, which it equals)
      }
      const std::size_t block = a / kAlignment;
      const std::size_t at = (group_begin * blocks.count + block * group_size + index_in_group[o]) *
                                 kFields * kAlignment +
                             a % kAlignment;
      if (blocks.slots[at] != 0.0f || blocks.slots[at + kAlignment] != 0.0f) {
        return {};  // two springs join the same nodes: the blocks have one slot for them
      }
      blocks.slots[at] = runs.stiffness[slot];
      blocks.slots[at + kAlignment] = runs.rest[slot];
      blocks.slots[at + 2 * kAlignment] = runs.outflow_a[slot];
      blocks.slots[at + 3 * kAlignment] = runs.outflow_b[slot];
    }
  }
  return blocks;
}

namespace {

// 1 / L, finite for a slot of zero length (see the header): its r is then 0, and so is its
// force. The 1e-30 m leaves any length above 1e-22 m unchanged (it is below half its last
// place); a select on L > 0, or std::max, would not vectorise (GCC keeps the comparison's
// control flow, the division it guards may trap).
inline __attribute__((always_inline)) float InverseLength(float length) {
  return 1.0f / (length + 1e-30f);
}

// Adds slot i's force (sx, sy, sz) to its a end and subtracts it from its b end (arrays from the
// run's a0 and a0 + offset).
inline __attribute__((always_inline)) void ApplyToEnds(int i, float sx, float sy, float sz,
                                                       float* __restrict fax, float* __restrict fay,
                                                       float* __restrict faz, float* __restrict fbx,
                                                       float* __restrict fby,
                                                       float* __restrict fbz) {
  fax[i] += sx;
  fay[i] += sy;
  faz[i] += sz;
  fbx[i] -= sx;
  fby[i] -= sy;
  fbz[i] -= sz;
}

// The damper's tension beta k (v_b - v_a) . r / L of slot i, offset d, velocities from the
// run's a0.
inline __attribute__((always_inline)) float DamperTension(const float* __restrict vx,
                                                          const float* __restrict vy,
                                                          const float* __restrict vz, int i, int d,
                                                          float rx, float ry, float rz,
                                                          float beta_k, float inverse_length) {
  // r as three scalars: an array passed by pointer is a memory object the loop cannot vectorise.
  const float rate = (vx[i + d] - vx[i]) * rx + (vy[i + d] - vy[i]) * ry + (vz[i + d] - vz[i]) * rz;
  return beta_k * rate * inverse_length;
}

// A node array from a run's a0, or null for none (no dampers, no dispersion).
inline const float* From(const float* array, int a0) {
  return array != nullptr ? array + a0 : nullptr;
}

// Calls part(a, count, beyond) for the slots of `run` in `share`: first those whose b ends lie
// below share.limit (beyond false), then those whose b ends lie at share.limit or past it (true).
template <typename Part>
inline __attribute__((always_inline)) void ForRunInShare(const SingleRun& run,
                                                         const SingleShare& share, Part&& part) {
  const int lo = std::max(run.a0, share.begin);
  const int hi = std::min(run.a0 + run.count, share.end);
  if (lo >= hi) return;
  const int split = std::clamp(share.limit - run.offset, lo, hi);
  if (split > lo) part(lo, split - lo, false);
  if (hi > split) part(split, hi - split, true);
}

// Where a part's b ends go: the shared arrays from node b, or the share's overflow from b - end.
inline float* BEnd(float* shared, float* overflow, int b, int end, bool beyond) {
  return beyond ? overflow + (b - end) : shared + b;
}

// One run of the eMSM first pass, its pointers as restrict parameters (GCC then trusts them;
// as restrict locals it kept a scalar fallback and took it). Only the elastic tension feeds the
// accumulators (as the outflow times the stretch L - L0), so this pass needs no velocities and
// no 1 / L, and it stores nothing per slot. Node arrays start at the run's a0, per-slot arrays at
// its first slot, jb at node a0 + d.
inline __attribute__((always_inline)) void InflowRun(
    int n, int d, const float* __restrict px, const float* __restrict py,
    const float* __restrict pz, const float* __restrict rest, const float* __restrict outflow_a,
    const float* __restrict outflow_b, float* __restrict ja, float* __restrict jb) {
#pragma omp simd
  for (int i = 0; i < n; ++i) {
    const float rx = px[i + d] - px[i], ry = py[i + d] - py[i], rz = pz[i + d] - pz[i];
    const float stretch = std::sqrt(rx * rx + ry * ry + rz * rz) - rest[i];
    ja[i] += outflow_a[i] * stretch;
    jb[i] += outflow_b[i] * stretch;
  }
}

// One run of the pass that applies the springs' forces, its pointers as restrict parameters
// (as InflowRun): the plain pass, and the eMSM second pass when Dispersed, which adds the
// dispersed tension o_a g_a + o_b g_b (o the end outflows v k L0, g from the run's a0). The second
// pass recomputes L and 1 / L rather than reading them from the first: on the 12k block the two
// stored arrays cost more than the square root and the division (docs/physics.md §9). The b ends'
// forces start at node a0 + d.
template <bool Damped, bool Dispersed>
inline __attribute__((always_inline)) void ForceRun(
    int n, int d, const float* __restrict px, const float* __restrict py,
    const float* __restrict pz, const float* __restrict vx, const float* __restrict vy,
    const float* __restrict vz, float beta, const float* __restrict g, const float* __restrict k,
    const float* __restrict rest, const float* __restrict outflow_a,
    const float* __restrict outflow_b, float* __restrict fax, float* __restrict fay,
    float* __restrict faz, float* __restrict fbx, float* __restrict fby, float* __restrict fbz) {
#pragma omp simd
  for (int i = 0; i < n; ++i) {
    const float rx = px[i + d] - px[i], ry = py[i + d] - py[i], rz = pz[i + d] - pz[i];
    const float length = std::sqrt(rx * rx + ry * ry + rz * rz);
    const float inverse_length = InverseLength(length);
    float t = k[i] * (length - rest[i]);
    if constexpr (Dispersed) t += outflow_a[i] * g[i] + outflow_b[i] * g[i + d];
    if constexpr (Damped)
      t += DamperTension(vx, vy, vz, i, d, rx, ry, rz, beta * k[i], inverse_length);
    const float scale = t * inverse_length;
    ApplyToEnds(i, scale * rx, scale * ry, scale * rz, fax, fay, faz, fbx, fby, fbz);
  }
}

// The forces of the slots in `share`; Dispersed: by `g` per node (the eMSM second pass).
template <bool Damped, bool Dispersed>
inline __attribute__((always_inline)) void ForcesImpl(
    const SinglePrecisionSprings& springs, const SingleShare& share,
    const SingleNodeArrays& positions, const SingleNodeArrays* velocities, float beta,
    const float* g, const SingleEndForces& forces, const MutableSingleNodeArrays& overflow) {
  const SingleNodeArrays v = velocities != nullptr ? *velocities : SingleNodeArrays{};
  for (const SingleRun& run : springs.runs) {
    ForRunInShare(run, share, [&](int a, int count, bool beyond) {
      const int b = a + run.offset, f = run.first + (a - run.a0), end = share.limit;
      ForceRun<Damped, Dispersed>(count, run.offset, positions.x + a, positions.y + a,
                                  positions.z + a, From(v.x, a), From(v.y, a), From(v.z, a), beta,
                                  From(g, a), springs.stiffness.data() + f, springs.rest.data() + f,
                                  springs.outflow_a.data() + f, springs.outflow_b.data() + f,
                                  forces.a.x + a, forces.a.y + a, forces.a.z + a,
                                  BEnd(forces.b.x, overflow.x, b, end, beyond),
                                  BEnd(forces.b.y, overflow.y, b, end, beyond),
                                  BEnd(forces.b.z, overflow.z, b, end, beyond));
    });
  }
}

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

// The plain pass, or the eMSM second pass when Dispersed, over block k (ForceRun's forces): the
// a ends' sums over the block's offsets in registers, added once; the b ends' per offset.
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
    const Lanes inverse_length = 1.0f / (length + 1e-30f);  // as InverseLength
    const Lanes stiffness = Load(slots);
    Lanes t = stiffness * (length - Load(slots + kLanes));
    if constexpr (Dispersed) {
      t += Load(slots + 2 * kLanes) * ga + Load(slots + 3 * kLanes) * Load(m.g + b);
    }
    if constexpr (Damped) {
      const Lanes rate =
          (Load(m.vx + b) - vxa) * rx + (Load(m.vy + b) - vya) * ry + (Load(m.vz + b) - vza) * rz;
      t += beta * stiffness * rate * inverse_length;
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

}  // namespace

bool SingleLoopsByBlocks(const SinglePrecisionSprings& springs, const SingleShare& share) {
  return !springs.blocks.offsets.empty() && share.begin % kLanes == 0 &&
         (share.end % kLanes == 0 || share.end >= springs.num_nodes);
}

namespace {

// The force loops of SinglePlainRuns and SingleOutflowRuns: by blocks or along the runs, with
// or without dampers (`velocities` null), each a loop compiled for its case.
template <bool Dispersed>
inline __attribute__((always_inline)) void Forces(const SinglePrecisionSprings& springs,
                                                  const SingleShare& share,
                                                  const SingleNodeArrays& p,
                                                  const SingleNodeArrays* velocities, float beta,
                                                  const float* g, const SingleEndForces& forces,
                                                  const MutableSingleNodeArrays& overflow) {
  if (SingleLoopsByBlocks(springs, share)) {
    if (velocities != nullptr) {
      ForceBlocks<true, Dispersed>(springs, share, p, velocities, beta, g, forces, overflow);
    } else {
      ForceBlocks<false, Dispersed>(springs, share, p, velocities, beta, g, forces, overflow);
    }
  } else if (velocities != nullptr) {
    ForcesImpl<true, Dispersed>(springs, share, p, velocities, beta, g, forces, overflow);
  } else {
    ForcesImpl<false, Dispersed>(springs, share, p, velocities, beta, g, forces, overflow);
  }
}

}  // namespace

MSM_SIM_SIMD_CLONES
void ToSingleNodeArrays(const double* vectors, long n, long begin, long end, const double origin[3],
                        float* arrays) {
  const double* __restrict from = vectors;
  float* __restrict x = arrays;
  float* __restrict y = arrays + n;
  float* __restrict z = arrays + 2 * n;
  const double ox = origin[0], oy = origin[1], oz = origin[2];
  for (long i = begin; i < end; ++i) {
    x[i] = static_cast<float>(from[3 * i] - ox);
    y[i] = static_cast<float>(from[3 * i + 1] - oy);
    z[i] = static_cast<float>(from[3 * i + 2] - oz);
  }
}

namespace {

// SingleDispersion's loop; kDouble: also storing J and g in double.
template <bool kDouble>
inline __attribute__((always_inline)) void Dispersion(const float* accumulators, double fraction,
                                                      const double* inverse_star_weight, long n,
                                                      long begin, long end, double* j, double* g,
                                                      float* g_single) {
  const float* __restrict ja = accumulators;
  const float* __restrict jb = accumulators + n;
  const double* __restrict w = inverse_star_weight;
  double* __restrict j_out = j;
  double* __restrict g_out = g;
  float* __restrict gs = g_single;
  for (long i = begin; i < end; ++i) {
    const double sum = fraction * (static_cast<double>(ja[i]) + static_cast<double>(jb[i]));
    const double per_weight = sum * w[i];
    if constexpr (kDouble) {
      j_out[i] = sum;
      g_out[i] = per_weight;
    }
    gs[i] = static_cast<float>(per_weight);
  }
}

}  // namespace

MSM_SIM_SIMD_CLONES
void SingleDispersion(const float* accumulators, double fraction, const double* inverse_star_weight,
                      long n, long begin, long end, double* j, double* g, float* g_single) {
  if (j != nullptr) {
    Dispersion<true>(accumulators, fraction, inverse_star_weight, n, begin, end, j, g, g_single);
  } else {
    Dispersion<false>(accumulators, fraction, inverse_star_weight, n, begin, end, j, g, g_single);
  }
}

namespace {

// Each node's a-end plus b-end force (float blocks of n, x y z for the a ends, then the b ends),
// added to or stored in n column-major 3-vectors, for nodes [begin, end).
template <bool kAdd>
inline __attribute__((always_inline)) void SumEndForces(const float* end_forces, long n, long begin,
                                                        long end, double* vectors) {
  const float* __restrict a = end_forces;
  const float* __restrict b = end_forces + 3 * n;
  double* __restrict to = vectors;
  for (long i = begin; i < end; ++i) {
    for (long d = 0; d < 3; ++d) {
      const double sum = static_cast<double>(a[d * n + i]) + static_cast<double>(b[d * n + i]);
      to[3 * i + d] = kAdd ? to[3 * i + d] + sum : sum;
    }
  }
}

}  // namespace

MSM_SIM_SIMD_CLONES
void AddSingleEndForces(const float* end_forces, long n, long begin, long end, double* vectors) {
  SumEndForces<true>(end_forces, n, begin, end, vectors);
}

MSM_SIM_SIMD_CLONES
void StoreSingleEndForces(const float* end_forces, long n, long begin, long end, double* vectors) {
  SumEndForces<false>(end_forces, n, begin, end, vectors);
}

MSM_SIM_SIMD_CLONES
void SinglePlainRuns(const SinglePrecisionSprings& springs, const SingleShare& share,
                     const SingleNodeArrays& positions, const SingleNodeArrays* velocities,
                     float beta, const SingleEndForces& forces,
                     const MutableSingleNodeArrays& overflow) {
  Forces<false>(springs, share, positions, velocities, beta, nullptr, forces, overflow);
}

MSM_SIM_SIMD_CLONES
void SingleInflowRuns(const SinglePrecisionSprings& springs, const SingleShare& share,
                      const SingleNodeArrays& positions, float* j_a, float* j_b,
                      float* j_b_overflow) {
  if (SingleLoopsByBlocks(springs, share)) {
    InflowBlocks(springs, share, positions, j_a, j_b, j_b_overflow);
    return;
  }
  for (const SingleRun& run : springs.runs) {
    ForRunInShare(run, share, [&](int a, int count, bool beyond) {
      const int b = a + run.offset, f = run.first + (a - run.a0);
      InflowRun(count, run.offset, positions.x + a, positions.y + a, positions.z + a,
                springs.rest.data() + f, springs.outflow_a.data() + f, springs.outflow_b.data() + f,
                j_a + a, BEnd(j_b, j_b_overflow, b, share.limit, beyond));
    });
  }
}

MSM_SIM_SIMD_CLONES
void SingleOutflowRuns(const SinglePrecisionSprings& springs, const SingleShare& share,
                       const SingleNodeArrays& positions, const SingleNodeArrays* velocities,
                       float beta, const float* dispersion_per_weight,
                       const SingleEndForces& forces, const MutableSingleNodeArrays& overflow) {
  Forces<true>(springs, share, positions, velocities, beta, dispersion_per_weight, forces,
               overflow);
}

}  // namespace msm_sim::core
