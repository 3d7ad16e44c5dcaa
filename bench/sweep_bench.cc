// Sweep throughput on the humanoid with 1 and 2 worker threads, measured in one run:
// 16 cases of a varied torso mass, each 1 s of simulation (200 steps) measured as
// state@1.
//
//   build/bench/sweep_bench

#include <benchmark/benchmark.h>

#include "plumb/sweep.h"

namespace {

void BM_SweepHumanoid(benchmark::State& state) {
  plumb::Model model = plumb::Model::Load("/usr/share/mujoco/model/humanoid/humanoid.xml");
  plumb::SweepSpec spec;
  spec.axes = {plumb::ParseSweepAxis(model, "body_mass[torso]=4:8:16")};
  spec.metrics = {plumb::ParseMetric(model, "state@1")};
  spec.threads = static_cast<int>(state.range(0));
  for (auto _ : state) {
    std::vector<plumb::SweepCase> cases = plumb::Sweep(model, spec);
    benchmark::DoNotOptimize(cases.back().metrics[0].value);
  }
  state.SetItemsProcessed(state.iterations() * 16);  // cases
}

BENCHMARK(BM_SweepHumanoid)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
