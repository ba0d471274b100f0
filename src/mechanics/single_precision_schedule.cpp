// The single-precision schedule: the model's springs in runs of one offset
// (phantoms bridging the gaps) and, where they pay, in blocks of 8 consecutive
// a nodes (docs/physics.md §9).

#include <algorithm>
#include <vector>

#include "mechanics/single_precision_kernels.h"
#include "mechanics/spring_schedule.h"

namespace msm_sim::core {

namespace {

void AddSlot(float k, float rest, float outflow_a, float outflow_b, SinglePrecisionSprings* out) {
  out->stiffness.push_back(k);
  out->rest.push_back(rest);
  out->outflow_a.push_back(outflow_a);
  out->outflow_b.push_back(outflow_b);
}

void AddPhantoms(int count, SinglePrecisionSprings* out) {
  for (int g = 0; g < count; ++g) AddSlot(0.0f, 0.0f, 0.0f, 0.0f, out);
  out->num_phantoms += count;
}

// Appends model spring s joining nodes a < a + offset (its end weights swapped with its ends
// where `swapped`) to the last run, bridging a short gap by phantoms, or starts a run with it.
void AddSpring(const Model& model, SpringIndex s, bool swapped, int a, int offset,
               SinglePrecisionSprings* out) {
  constexpr int kAlignment = SinglePrecisionSprings::kAlignment;
  SingleRun* run = out->runs.empty() ? nullptr : &out->runs.back();
  const int gap = run != nullptr ? a - (run->a0 + run->count) : -1;
  if (run != nullptr && run->offset == offset && gap >= 0 &&
      gap <= SinglePrecisionSprings::kMaxGap &&
      run->count + gap < SinglePrecisionSprings::kMaxRunLength) {
    AddPhantoms(gap, out);
    run->count += gap + 1;
  } else {
    // A run starts at a node and a slot that are multiples of kAlignment: phantoms from the
    // aligned node on, and unused zero slots before them.
    const int a0 = a - a % kAlignment;
    AddPhantoms((kAlignment - out->num_slots() % kAlignment) % kAlignment + (a - a0), out);
    out->runs.push_back({out->num_slots() - (a - a0), a0, offset, a - a0 + 1});
  }
  out->max_offset = std::max(out->max_offset, offset);
  const double k = model.spring_stiffness()[s];
  const double rest = model.spring_rest_length()[s];
  const double outflow_a = model.dispersion_weight_a()[s] * rest * k;
  const double outflow_b = model.dispersion_weight_b()[s] * rest * k;
  AddSlot(static_cast<float>(k), static_cast<float>(rest),
          static_cast<float>(swapped ? outflow_b : outflow_a),
          static_cast<float>(swapped ? outflow_a : outflow_b), out);
}

}  // namespace

std::shared_ptr<const SinglePrecisionSprings> SinglePrecisionSprings::Schedule(const Model& model) {
  // The double schedule's order (each spring oriented a < b, sorted by offset, then a), its
  // runs extended across short gaps by phantoms.
  const SpringSchedule sorted = ScheduleSprings(model);
  auto springs = std::make_shared<SinglePrecisionSprings>();
  SinglePrecisionSprings& out = *springs;
  for (const SpringRun& row : sorted.runs) {
    for (int i = 0; i < row.count; ++i) {
      AddSpring(model, sorted.model_index[row.first + i], sorted.swapped[row.first + i], row.a0 + i,
                row.offset, &out);
      out.scheduled_slots.push_back(out.num_slots() - 1);
    }
  }
  out.num_nodes = model.num_nodes();
  out.blocks = ScheduleBlocks(out);
  return springs;
}

namespace {

constexpr int kAlignment = SinglePrecisionSprings::kAlignment;
constexpr int kFields = 4;  // k, L0, outflow a, outflow b per slot

// The distinct offsets of the runs, ascending (runs are sorted by offset).
std::vector<int> DistinctOffsets(const std::vector<SingleRun>& runs) {
  std::vector<int> sorted;
  for (const SingleRun& run : runs) {
    if (sorted.empty() || sorted.back() != run.offset) sorted.push_back(run.offset);
  }
  return sorted;
}

// Groups of offsets whose b ends' stores never partly overlap a load soon after (offsets a
// multiple of 8 apart hit the same 8 nodes, or at least kGroupSeparation apart): a load that
// partly overlaps a store still in flight waits for it to retire.
std::vector<std::vector<int>> GroupOffsets(const std::vector<int>& sorted) {
  std::vector<std::vector<int>> groups;
  for (const int d : sorted) {
    const auto fits = [d](const std::vector<int>& group) {
      return std::all_of(group.begin(), group.end(), [d](int other) {
        return (d - other) % kAlignment == 0 ||
               d - other >= SinglePrecisionSprings::kGroupSeparation;
      });
    };
    auto group = std::find_if(groups.begin(), groups.end(), fits);
    if (group == groups.end()) group = groups.insert(groups.end(), std::vector<int>{});
    group->push_back(d);
  }
  return groups;
}

// Where each offset (by position in `sorted`) lies: its group and its index in the group.
struct OffsetPlaces {
  std::vector<int> group_of, index_in_group;
};

// Lays the groups' offsets into `blocks` and returns each offset's place.
OffsetPlaces LayGroups(const std::vector<int>& sorted, const std::vector<std::vector<int>>& groups,
                       SinglePrecisionSprings::Blocks* blocks) {
  const int offsets = static_cast<int>(sorted.size());
  OffsetPlaces places{std::vector<int>(offsets), std::vector<int>(offsets)};
  for (std::size_t g = 0; g < groups.size(); ++g) {
    for (std::size_t j = 0; j < groups[g].size(); ++j) {
      const int o =
          static_cast<int>(std::find(sorted.begin(), sorted.end(), groups[g][j]) - sorted.begin());
      places.group_of[o] = static_cast<int>(g);
      places.index_in_group[o] = static_cast<int>(j);
      blocks->offsets.push_back(groups[g][j]);
    }
    blocks->group_ends.push_back(static_cast<int>(blocks->offsets.size()));
  }
  return places;
}

// Copies each slot of the runs into its group, block, offset and lane (a phantom's zeros stay
// zeros); false where two springs join the same nodes (the blocks have one slot for them).
bool PlaceSlots(const SinglePrecisionSprings& runs, const std::vector<int>& sorted,
                const OffsetPlaces& places, SinglePrecisionSprings::Blocks* blocks) {
  int o = 0;
  for (const SingleRun& run : runs.runs) {
    while (sorted[o] != run.offset) ++o;
    const int g = places.group_of[o];
    const std::size_t group_begin = g == 0 ? 0 : blocks->group_ends[g - 1];
    const std::size_t group_size = blocks->group_ends[g] - group_begin;
    for (int i = 0; i < run.count; ++i) {
      const int slot = run.first + i, a = run.a0 + i;
      if (runs.stiffness[slot] == 0.0f && runs.outflow_a[slot] == 0.0f &&
          runs.outflow_b[slot] == 0.0f) {
        continue;  // a phantom (or a spring of no force, which it equals)
      }
      const std::size_t block = a / kAlignment;
      const std::size_t at =
          (group_begin * blocks->count + block * group_size + places.index_in_group[o]) * kFields *
              kAlignment +
          a % kAlignment;
      float* slots = blocks->slots.data() + at;
      if (slots[0] != 0.0f || slots[kAlignment] != 0.0f) return false;
      slots[0] = runs.stiffness[slot];
      slots[kAlignment] = runs.rest[slot];
      slots[2 * kAlignment] = runs.outflow_a[slot];
      slots[3 * kAlignment] = runs.outflow_b[slot];
    }
  }
  return true;
}

}  // namespace

SinglePrecisionSprings::Blocks SinglePrecisionSprings::ScheduleBlocks(
    const SinglePrecisionSprings& runs) {
  const std::vector<int> sorted = DistinctOffsets(runs.runs);
  Blocks blocks;
  const int offsets = static_cast<int>(sorted.size());
  blocks.count = (runs.num_nodes + kAlignment - 1) / kAlignment;
  const double block_slots = static_cast<double>(blocks.count) * kAlignment * offsets;
  const int springs = runs.num_slots() - runs.num_phantoms;
  if (offsets == 0 || offsets > kMaxBlockOffsets || springs < kMinBlockOccupancy * block_slots ||
      runs.num_nodes > kMaxBlockNodes) {
    return {};
  }
  const OffsetPlaces places = LayGroups(sorted, GroupOffsets(sorted), &blocks);
  blocks.slots.assign(static_cast<std::size_t>(block_slots) * kFields, 0.0f);
  if (!PlaceSlots(runs, sorted, places, &blocks)) return {};
  return blocks;
}

}  // namespace msm_sim::core
