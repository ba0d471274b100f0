#pragma once

#include <vector>

#include "mechanics/spring_schedule.h"

namespace msm_sim::core {

/// Node vectors as structure of arrays (x, y, z components each contiguous), the layout the run
/// kernels load and store with whole SIMD registers.
struct NodeArrays {
  const double* x;
  const double* y;
  const double* z;
};
struct MutableNodeArrays {
  double* x;
  double* y;
  double* z;
};

/// Per-spring data in schedule order (SpringSchedule), linear springs t = k (L - L0).
struct ScheduledSprings {
  const SpringRun* runs;
  const double* rest;
  const double* stiffness;
  const double* inflow_a;  // q v L0 at the scheduled a end (eMSM)
  const double* inflow_b;
  const double* outflow_a;  // v k L0 at the scheduled a end (eMSM)
  const double* outflow_b;
};

/// Spring dampers: velocities (nullptr for none) and beta (s); tension beta k dL/dt.
struct RunDamping {
  const NodeArrays* velocities;
  double beta;
};

// The kernels take runs [run_begin, run_end) and write the per-spring results at schedule
// positions. They are compiled for AVX2 + FMA where the CPU has it (chosen at load time) and
// for baseline x86-64 otherwise; results for a given CPU and thread count are deterministic.
// Preconditions: no spring has zero length; the arrays hold every node the runs touch.

/// Plain MSM: adds each spring's force (tension plus damper) to both ends and stores the total
/// tension.
void PlainRuns(const ScheduledSprings& springs, int run_begin, int run_end,
               const NodeArrays& positions, const RunDamping& damping,
               const MutableNodeArrays& forces, double* total_tensions);

/// eMSM first pass: stores each spring's direct tension and 1 / L and accumulates
/// J += inflow * t at both ends.
void InflowRuns(const ScheduledSprings& springs, int run_begin, int run_end,
                const NodeArrays& positions, double* tensions, double* inverse_lengths,
                double* accumulator);

/// eMSM second pass: total tension t + outflow_a g_a + outflow_b g_b (+ damper), with
/// g = J / W per node, applied to both ends and stored.
void OutflowRuns(const ScheduledSprings& springs, int run_begin, int run_end,
                 const NodeArrays& positions, const RunDamping& damping,
                 const double* dispersion_per_weight, const double* tensions,
                 const double* inverse_lengths, const MutableNodeArrays& forces,
                 double* total_tensions);

}  // namespace msm_sim::core

namespace msm_sim::core {

/// The schedule-order copy of a model's springs that the run kernels read; immutable, so that
/// copies of an evaluator share it.
struct ScheduledSpringData {
  SpringSchedule schedule;
  std::vector<double> rest, stiffness, inflow_a, inflow_b, outflow_a, outflow_b;

  ScheduledSprings View() const {
    return {schedule.runs.data(), rest.data(),      stiffness.data(), inflow_a.data(),
            inflow_b.data(),      outflow_a.data(), outflow_b.data()};
  }
};

}  // namespace msm_sim::core
