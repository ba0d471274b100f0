#pragma once

#include <memory>
#include <vector>

#include "msm_sim/mechanics/cache_line_allocator.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// The single-precision spring loops of ForceEvaluator (SpringPrecision::kSingle, docs/physics.md
/// §9). They hold twice the springs per SIMD register of the double loops (force_kernels.h) and
/// take a spring's two ends in one loop, each end scattering into its own force array, so a run
/// is one loop whatever its offset.

/// A run of the single-precision schedule: slots first .. first + count - 1 join nodes a0 + i and
/// a0 + offset + i. A slot is a spring of the model or a phantom: where one lattice row ends and
/// the next begins, or a surface leaves out a few springs, phantoms (stiffness 0, no dispersion)
/// bridge the gap, so that a box's rows of one direction form a few long runs; with 8 springs
/// per register a row of 19 springs left a third of the work to remainder loops.
struct SingleRun {
  int first;
  int a0;
  int offset;  // > 0
  int count;
};

/// Per-slot data in schedule order, single precision. Immutable once built; evaluators share it.
struct SinglePrecisionSprings {
  /// Longest gap (missing springs in a row of one offset) that phantoms bridge.
  static constexpr int kMaxGap = 8;
  /// Longest run. It bounded the threads' imbalance while shares were cut between runs; node
  /// shares (SingleShare) now cut runs anywhere, and longer runs were not tried.
  static constexpr int kMaxRunLength = 512;
  /// Every run starts at a node and a slot that are multiples of this (leading phantoms), so that
  /// a run's loads of 8 floats at its a ends and slots start where a 32-byte block starts, and
  /// never straddle two cache lines in arrays that start one (CacheLineFloats, and node blocks
  /// a multiple of 16 floats apart; docs/physics.md §9, docs/design/float-blocks.md). The b ends,
  /// at any offset, stay unaligned.
  static constexpr int kAlignment = 8;

  std::vector<SingleRun> runs;
  /// Per slot: k, L0, and each end's eMSM outflow v k L0 (v the model's dispersion weight at
  /// that end, docs/physics.md §3). The inflow q v L0 times the tension k (L - L0) is the same
  /// outflow times q (L - L0), so one array per end serves both passes, q applied per node
  /// (SingleDispersion); the first pass then reads three arrays per slot instead of four.
  CacheLineFloats rest, stiffness, outflow_a, outflow_b;
  /// The slot of each spring of the double schedule (SpringSchedule order), for per-spring data
  /// kept in slot order elsewhere (the stiffness product's, ForceEvaluator::RoundLinearization).
  std::vector<int> scheduled_slots;
  /// Slots that are no spring of the model: the phantoms, and the unused slots before a run.
  int num_phantoms = 0;
  /// The largest offset of a run: the longest overflow of a share (SingleShare).
  int max_offset = 0;

  int num_slots() const { return static_cast<int>(rest.size()); }

  /// The same springs in blocks of kAlignment consecutive a nodes (empty `offsets`: none; see
  /// ScheduleBlocks): for each block, for each of the model's few distinct offsets, the 8 slots
  /// joining the block's nodes a to a + offset (zeros where there is no spring). A block's loop
  /// keeps its a ends' positions, velocities, g and force sums in registers across a group of
  /// offsets, and loads and stores only the b ends per offset: about 14 loads and 3 stores per 8
  /// slots in the second pass, plus the a ends' once per group, instead of 24 and 6 along runs
  /// (docs/physics.md §9). The loops take the blocks where a share starts and ends at multiples
  /// of kAlignment (or at the last node).
  struct Blocks {
    /// The distinct offsets in groups: offsets [group_ends[g - 1], group_ends[g]) are group g,
    /// swept over all blocks in turn (see ScheduleBlocks), ascending in each.
    std::vector<int> offsets;
    std::vector<int> group_ends;
    int count = 0;  // blocks: nodes 0 .. 8 count - 1
    /// [group][block][offset of the group][k, L0, outflow a, outflow b][8 nodes of the block],
    /// as the slots above.
    CacheLineFloats slots;
  };
  Blocks blocks;
  /// Offsets beyond which, or occupancy (the model's springs per block slot) below which, the
  /// schedule has no blocks: the phantoms would cost more than the loads saved.
  static constexpr int kMaxBlockOffsets = 16;
  static constexpr double kMinBlockOccupancy = 0.75;
  /// Models of more nodes than this have no blocks either. Where the node arrays far outgrow a
  /// core's L2, the blocks ran slower than the runs and their times spread widely from run to
  /// run (docs/design/float-blocks.md).
  static constexpr int kMaxBlockNodes = 40000;
  /// Offsets of one group differ by a multiple of kAlignment or by at least this: a load that
  /// partly overlaps a b-end store of the same sweep then comes two blocks later at the soonest
  /// (docs/physics.md §9; why not 32: docs/design/float-blocks.md).
  static constexpr int kGroupSeparation = 16;
  int num_nodes = 0;  // the model's

  /// How far the loops read and write the node arrays: past the last node where a block's
  /// phantoms reach (its last block's nodes plus the largest offset). The node arrays must hold
  /// this many nodes, those past the model's finite (zeros).
  int PaddedNodes() const {
    return blocks.offsets.empty() ? num_nodes : kAlignment * blocks.count + max_offset;
  }

  /// Schedules `model`'s springs. Deterministic. Precondition: linear springs (the loops know
  /// t = k (L - L0) only).
  static std::shared_ptr<const SinglePrecisionSprings> Schedule(const Model& model);

 private:
  // The blocks of the runs' slots, or none (see Blocks).
  static Blocks ScheduleBlocks(const SinglePrecisionSprings& runs);
};

/// Node vectors as x, y, z blocks (structure of arrays), single precision.
struct SingleNodeArrays {
  const float* x;
  const float* y;
  const float* z;
};
struct MutableSingleNodeArrays {
  float* x;
  float* y;
  float* z;
};

/// Where the loops scatter: the a ends of every slot into `a`, the b ends into `b` (the caller
/// sums the two). Two arrays let one SIMD loop write both ends of a run of any offset.
struct SingleEndForces {
  MutableSingleNodeArrays a;
  MutableSingleNodeArrays b;
};

/// A thread's share of the loops: the slots whose a ends are nodes [begin, end). A share writes
/// the a ends' sums (forces, accumulators) of its own nodes only, and the b ends' of its own
/// nodes, except that b ends at node `end` or beyond go to the share's overflow (index 0 at node
/// `end`, at most the schedule's largest offset long). Disjoint shares therefore write disjoint
/// memory, and one share [0, n) takes every slot, its overflow never written (b < n). `limit`
/// (default `end`) moves where the overflow starts: the nodes [begin, end) of a share that owns
/// the nodes up to `limit`, its b ends below `limit` written in place.
struct SingleShare {
  int begin;
  int end;
  int limit = end;
};

// The loops take a share. `velocities` null: no dampers; else dampers of tension beta k dL/dt.
// They are compiled for AVX2 + FMA where the CPU has it (chosen at load time) and for baseline
// x86-64 otherwise; results for a given CPU and set of shares are deterministic. A slot of zero
// length (a phantom between coinciding nodes) exerts no force instead of NaN; a model spring of
// zero length is outside ForceEvaluator's preconditions.

// The layout conversions around the loops, vectorised like them.

/// Rounds column-major 3-vectors [begin, end) of n minus `origin` into float x, y, z blocks of
/// n (`arrays`).
void ToSingleNodeArrays(const double* vectors, long n, long begin, long end, const double origin[3],
                        float* arrays);

/// For nodes [begin, end), from the a ends' and the b ends' sums of v L0 t (`accumulators`: a
/// then b, n each): J = q (a + b) (q = `fraction`) and g = J / W (`inverse_star_weight` = 1 / W)
/// in double, rounded to float in `g_single`.
void SingleDispersion(const float* accumulators, double fraction, const double* inverse_star_weight,
                      long n, long begin, long end, float* g_single);

/// Adds the a ends' and the b ends' float x, y, z blocks (`end_forces`, 6 blocks of n) of nodes
/// [begin, end) to their column-major 3-vectors.
void AddSingleEndForces(const float* end_forces, long n, long begin, long end, double* vectors);
/// The same, storing the sums instead of adding them.
void StoreSingleEndForces(const float* end_forces, long n, long begin, long end, double* vectors);

/// Whether the loops below take `share` by the schedule's blocks (SinglePrecisionSprings::
/// Blocks): it has them and the share starts at a block (and ends at one, or at the last node).
/// Then they store the a ends' sums (forces, accumulators) of the share's nodes rather than add
/// them: those need no clearing, and only the b ends' arrays and the overflows are added to.
bool SingleLoopsByBlocks(const SinglePrecisionSprings& springs, const SingleShare& share);

/// Plain MSM: each slot's tension (spring plus damper) applied to both ends.
void SinglePlainRuns(const SinglePrecisionSprings& springs, const SingleShare& share,
                     const SingleNodeArrays& positions, const SingleNodeArrays* velocities,
                     float beta, const SingleEndForces& forces,
                     const MutableSingleNodeArrays& overflow);

/// eMSM first pass: adds each slot's end outflow v k L0 times its stretch L - L0 (the end weight
/// v L0 times the elastic tension) to the a ends' accumulators `j_a` and the b ends' `j_b` (from
/// node share.end on: `j_b_overflow`); SingleDispersion applies q. Dampers do not disperse, so
/// it takes no velocities.
void SingleInflowRuns(const SinglePrecisionSprings& springs, const SingleShare& share,
                      const SingleNodeArrays& positions, float* j_a, float* j_b,
                      float* j_b_overflow);

/// eMSM second pass: total tension = k (L - L0) + o_a g_a + o_b g_b plus the damper's (o the
/// end outflows v k L0, g = J / W per node), applied to both ends.
void SingleOutflowRuns(const SinglePrecisionSprings& springs, const SingleShare& share,
                       const SingleNodeArrays& positions, const SingleNodeArrays* velocities,
                       float beta, const float* dispersion_per_weight,
                       const SingleEndForces& forces, const MutableSingleNodeArrays& overflow);

}  // namespace msm_sim::core
