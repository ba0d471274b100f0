#pragma once
// The implicit step benchmark's warm scenes, its unit (one explicit force pass) and its timing,
// shared by implicit_step_benchmark.cpp and implicit_step_parts.cpp, and the parts the latter
// times. The scenes and the pass are kept in the functions' statics, one set for the program.
#include <algorithm>
#include <functional>
#include <map>
#include <memory>
#include <tuple>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>

#include "implicit_step_scene.h"

namespace msm_sim::core::bench {

constexpr int kWarmSteps = 30;  // 30 ms: resting on the ground, the sphere pressed in

// A scene per (case, integrator), stepped kWarmSteps from rest when first asked for.
inline RealtimeScene& WarmScene(const BlockCase& block_case, Integrator integrator) {
  static std::map<std::tuple<double, double, int>, std::unique_ptr<RealtimeScene>> scenes;
  auto& scene = scenes[{block_case.poisson, block_case.spacing, static_cast<int>(integrator)}];
  if (!scene) {
    scene = std::make_unique<RealtimeScene>(RealtimeBlock(block_case), integrator);
    for (int k = 0; k < kWarmSteps; ++k) scene->Step();
  }
  return *scene;
}

// One pass (s): the median of 31 AccumulateForces at the warm explicit scene's state, after 5
// untimed.
inline double PassSeconds(const BlockCase& block_case) {
  static std::map<std::pair<double, double>, double> passes;
  double& pass = passes[{block_case.poisson, block_case.spacing}];
  if (pass == 0.0) {
    internal::Body& body = WarmScene(block_case, Integrator::kExplicit).block();
    Eigen::Matrix3Xd forces = Eigen::Matrix3Xd::Zero(3, body.model->num_nodes());
    std::vector<double> times;
    for (int k = 0; k < 5; ++k) {  // untimed: the arrays allocated and in the cache
      body.evaluator.AccumulateForces(body.state.positions, body.state.velocities,
                                      body.options.damping_beta, &forces);
    }
    for (int k = 0; k < 31; ++k) {
      const auto start = Clock::now();
      body.evaluator.AccumulateForces(body.state.positions, body.state.velocities,
                                      body.options.damping_beta, &forces);
      times.push_back(SecondsSince(start));
    }
    std::nth_element(times.begin(), times.begin() + 15, times.end());
    pass = times[15];
  }
  return pass;
}

inline KickState& WarmKickState(const BlockCase& block_case) {
  static std::map<std::pair<double, double>, std::unique_ptr<KickState>> states;
  auto& kick = states[{block_case.poisson, block_case.spacing}];
  if (!kick) {
    kick = std::make_unique<KickState>(WarmScene(block_case, Integrator::kImplicit).world());
  }
  return *kick;
}

// Times work() per iteration after an untimed prepare() (manual time); pass_eq is the mean
// over one pass.
inline void TimeEach(benchmark::State& state, const BlockCase& block_case,
                     const std::function<void()>& prepare, const std::function<void()>& work) {
  const double pass = PassSeconds(block_case);
  double total = 0.0;
  for (auto _ : state) {
    prepare();
    const auto start = Clock::now();
    work();
    const double seconds = SecondsSince(start);
    state.SetIterationTime(seconds);
    total += seconds;
  }
  state.counters["pass_eq"] = total / static_cast<double>(state.iterations()) / pass;
}

// The parts timed each on its own (implicit_step_parts.cpp); implicit_step_benchmark.cpp registers
// them with the whole steps, in its order.
void ComputeForcesPart(benchmark::State& state, const BlockCase& block_case);
void LinearizePart(benchmark::State& state, const BlockCase& block_case);
void StiffnessDiagonalPart(benchmark::State& state, const BlockCase& block_case);
void ApplyStiffnessFloat(benchmark::State& state, const BlockCase& block_case);
void ApplyStiffnessDouble(benchmark::State& state, const BlockCase& block_case);
void OperatorWrap(benchmark::State& state, const BlockCase& block_case);
void PcgIterationWork(benchmark::State& state, const BlockCase& block_case);
void DeepestContacts(benchmark::State& state, const BlockCase& block_case);
void ContactHolds(benchmark::State& state, const BlockCase& block_case);
void ContactStage(benchmark::State& state, const BlockCase& block_case);
void Drifts(benchmark::State& state, const BlockCase& block_case);

}  // namespace msm_sim::core::bench
