// plumb run's overhead over a bare mj_step loop: the humanoid, 20 000 steps, sampling
// every 0.1 s to CSV, against the same steps with nothing else.
//
//   build/bench/run_overhead_bench                      # Google Benchmark, wall time
//   build/bench/run_overhead_bench --count=bare|plumb   # one run, for callgrind
//   bench/callgrind_overhead.sh build                   # instruction counts of both
//
// PLUMB_BENCH_MODEL overrides the model.

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "plumb/path.h"
#include "plumb/run.h"
#include "plumb/sample_writer.h"

namespace {

constexpr long kSteps = 20000;

std::string ModelPath() {
  const char* env = std::getenv("PLUMB_BENCH_MODEL");
  return env ? env : "/usr/share/mujoco/model/humanoid/humanoid.xml";
}

// The same start for both: qpos0, derived quantities computed.
void Start(const plumb::Model& model, plumb::Data& data) {
  plumb::ApplyAssignments(const_cast<plumb::Model&>(model), data, {});
}

// Only the stepping loop: callgrind collects inside this function.
__attribute__((noinline)) void RunBareLoop(const mjModel* m, mjData* d) {
  for (long i = 0; i < kSteps; ++i) mj_step(m, d);
}

// plumb's loop with its checks, sampling and CSV writing: callgrind collects inside.
__attribute__((noinline)) plumb::RunResult RunPlumb(const plumb::Model& model, plumb::Data& data,
                                                    const plumb::RunSpec& spec,
                                                    plumb::SampleSink& sink) {
  return plumb::Run(model, data, spec, sink);
}

plumb::RunSpec Spec(const plumb::Model& model) {
  plumb::RunSpec spec;
  spec.until = kSteps * model->opt.timestep;
  spec.every = 0.1;
  spec.columns = plumb::DefaultColumns(model);
  return spec;
}

void BM_BareStepLoop(benchmark::State& state) {
  plumb::Model model = plumb::Model::Load(ModelPath());
  plumb::Data data(model);
  for (auto _ : state) {
    Start(model, data);
    RunBareLoop(model.get(), data.get());
    benchmark::DoNotOptimize(data->qpos[0]);
  }
  state.SetItemsProcessed(state.iterations() * kSteps);
}

void BM_PlumbRun(benchmark::State& state) {
  plumb::Model model = plumb::Model::Load(ModelPath());
  plumb::Data data(model);
  plumb::RunSpec spec = Spec(model);
  for (auto _ : state) {
    Start(model, data);
    std::FILE* out = std::tmpfile();
    auto writer = plumb::MakeSampleWriter(plumb::SampleFormat::kCsv, out);
    plumb::RunResult result = RunPlumb(model, data, spec, *writer);
    if (result.steps != kSteps) state.SkipWithError("the run stopped early");
    std::fclose(out);
  }
  state.SetItemsProcessed(state.iterations() * kSteps);
}

BENCHMARK(BM_BareStepLoop)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PlumbRun)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::strncmp(argv[1], "--count=", 8) == 0) {
    // one run of one variant, for instruction counting
    plumb::Model model = plumb::Model::Load(ModelPath());
    plumb::Data data(model);
    Start(model, data);
    if (std::strcmp(argv[1] + 8, "bare") == 0) {
      RunBareLoop(model.get(), data.get());
    } else {
      std::FILE* out = std::tmpfile();
      auto writer = plumb::MakeSampleWriter(plumb::SampleFormat::kCsv, out);
      RunPlumb(model, data, Spec(model), *writer);
      std::fclose(out);
    }
    std::printf("qpos[2] after %ld steps: %.17g\n", kSteps, data->qpos[2]);
    return 0;
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
