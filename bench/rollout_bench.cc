// Rollout throughput on the humanoid: with and without randomization and recording (the
// per-step overhead), and with 1 and 2 worker threads, all in one run.
//
//   build/bench/rollout_bench

#include <benchmark/benchmark.h>

#include "plumb/rollout.h"

namespace {

constexpr long kRollouts = 64;
constexpr double kUntil = 1.0;  // 200 steps of 5 ms each

plumb::RolloutSpec Spec(const plumb::Model& model, bool randomized, int threads) {
  plumb::RolloutSpec spec;
  spec.count = kRollouts;
  spec.until = kUntil;
  spec.threads = threads;
  spec.ctrl_noise = 0.01;
  if (randomized) {
    spec.randomize = {plumb::ParseRandomization(model, "body_mass[*]=*U(0.9,1.1)"),
                      plumb::ParseRandomization(model, "geom_friction[*][0]=U(0.5,1.2)")};
    spec.metrics = {plumb::ParseMetric(model, "xpos[torso][2]@1"),
                    plumb::ParseMetric(model, "maxabs(qvel[root][0])")};
  }
  return spec;
}

void Run(benchmark::State& state, bool randomized) {
  plumb::Model model = plumb::Model::Load("/usr/share/mujoco/model/humanoid/humanoid.xml");
  plumb::RolloutSpec spec = Spec(model, randomized, static_cast<int>(state.range(0)));
  for (auto _ : state) {
    double sink = 0;
    plumb::Rollout(model, spec, [&](const plumb::RolloutResult& r) { sink += r.index; });
    benchmark::DoNotOptimize(sink);
  }
  state.SetItemsProcessed(state.iterations() * kRollouts * 200);  // steps
}

void BM_RolloutPlain(benchmark::State& state) { Run(state, false); }
void BM_RolloutRandomized(benchmark::State& state) { Run(state, true); }

BENCHMARK(BM_RolloutPlain)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_RolloutRandomized)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
