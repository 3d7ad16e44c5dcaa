// plumb crosscheck: the five checks in order, against one adapter process.

#include "plumb/crosscheck.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/worker_pool.h"
#include "crosscheck/engine_session.h"
#include "crosscheck/stage_compare.h"
#include "crosscheck/statistics_check.h"
#include "crosscheck/support_check.h"
#include "crosscheck/trajectory_check.h"
#include "plumb/error.h"
#include "plumb/rollout.h"
#include "plumb/timing.h"

namespace plumb {
using internal::CapacityRow;
using internal::CompareStages;
using internal::CpuStages;
using internal::EngineSession;
using internal::GeomPairs;
using internal::RefusalRow;
using internal::RequireKnownEngine;
using internal::StageValues;
using internal::StatisticsCheck;
using internal::SupportRows;
using internal::ThreadsOrAllCores;
using internal::TrajectoryCheck;

namespace {

bool Wants(const CrosscheckOptions& o, const char* check) {
  return std::find(o.checks.begin(), o.checks.end(), check) != o.checks.end();
}

void Validate(const CrosscheckOptions& o) {
  RequireKnownEngine(o.engine);
  if (o.device != "cpu" && o.device != "cuda") {
    throw ArgumentError("device", Quoted(o.device), "use cpu or cuda");
  }
  static const std::vector<std::string> kChecks = {"support", "stages", "trajectory", "statistics",
                                                   "throughput"};
  for (const std::string& c : o.checks) {
    if (std::find(kChecks.begin(), kChecks.end(), c) == kChecks.end()) {
      throw ArgumentError("checks", Quoted(c),
                          "the checks are support, stages, trajectory, statistics, throughput");
    }
  }
  auto positive = [](const char* name, double v) {
    if (!(v > 0) || !std::isfinite(v))
      throw ArgumentError(name, fmt::format("{:g}", v), "must be > 0");
  };
  positive("until", o.until);
  positive("tol", o.tol);
  positive("margin", o.margin);
  RequireCtrlNoise(o.ctrl_noise);
  if (o.samples < 1) throw ArgumentError("samples", std::to_string(o.samples), "must be >= 1");
  if (o.starts < 1) throw ArgumentError("starts", std::to_string(o.starts), "must be >= 1");
  if (o.worlds < 2) throw ArgumentError("worlds", std::to_string(o.worlds), "must be >= 2");
  if (!(o.alpha > 0 && o.alpha < 0.5)) {
    throw ArgumentError("alpha", fmt::format("{:g}", o.alpha), "must be in (0, 0.5)");
  }
  if (!(o.chaos_ratio > 0 && o.chaos_ratio <= 1)) {
    throw ArgumentError("chaos_ratio", fmt::format("{:g}", o.chaos_ratio), "must be in (0, 1]");
  }
  if (o.throughput_steps < 1) {
    throw ArgumentError("throughput_steps", std::to_string(o.throughput_steps), "must be >= 1");
  }
}

std::vector<long> EvenSteps(long steps, int count, double fraction) {
  std::vector<long> at;
  for (int k = 0; k < count; ++k) {
    at.push_back(static_cast<long>(std::llround(fraction * steps * k / count)));
  }
  return at;
}

// CPU MuJoCo's nominal run of `until` from `start`, made once for every check: the states the
// stage check samples (evenly along it), the trajectory check's starts (evenly along its first
// half), and the geom pairs in contact at any step (what the support table's collision entries
// judge).
struct NominalRun {
  std::vector<Data> samples, starts;
  GeomPairs touching;
};

NominalRun RunNominal(const Model& model, const Data& start, const CrosscheckOptions& o) {
  const long steps = StepsToReach(o.until, model->opt.timestep);
  const std::vector<long> samples = EvenSteps(steps, o.samples, 1);
  const std::vector<long> starts = EvenSteps(steps, o.starts, 0.5);
  NominalRun run;
  Data d = start.Clone();
  for (long step = 0; step <= steps; ++step) {
    if (step > 0) {
      if (o.stop.stop_requested()) throw Interrupted("plumb crosscheck: interrupted");
      mj_step(model.get(), d.get());
    }
    for (int i = 0; i < d->ncon; ++i) {
      const int a = d->contact[i].geom1, b = d->contact[i].geom2;
      run.touching.insert({std::min(a, b), std::max(a, b)});
    }
    for (long at : samples) {
      if (at == step) run.samples.push_back(d.Clone());
    }
    for (long at : starts) {
      if (at == step) run.starts.push_back(d.Clone());
    }
  }
  return run;
}

std::vector<const mjData*> Pointers(const std::vector<Data>& states) {
  std::vector<const mjData*> out;
  for (const Data& d : states) out.push_back(d.get());
  return out;
}

CheckRow Skipped(const char* check, const std::string& why) {
  CheckRow row;
  row.id = check;
  row.section = check;
  row.status = CheckStatus::kSkip;
  row.explanation = why;
  return row;
}

std::vector<CheckRow> StageCheck(const Model& loaded, const std::vector<Data>& states,
                                 EngineSession& engine) {
  std::vector<double> times;
  for (const Data& d : states) times.push_back(d->time);
  const StageValues cpu = CpuStages(loaded, Pointers(states));
  const StageValues other = engine.Stages(loaded, Pointers(states));
  std::vector<CheckRow> rows = CompareStages(loaded, cpu, other, times);
  if (CheckRow capacity = CapacityRow(other.overflow_contacts, other.overflow_constraints);
      !capacity.id.empty()) {
    rows.push_back(capacity);
  }
  return rows;
}

CheckRow ThroughputCheck(const Model& model, const Model& loaded, const Data& start,
                         EngineSession& engine, const CrosscheckOptions& o,
                         ThroughputFigures* figures) {
  figures->worlds = o.worlds;
  figures->steps = o.throughput_steps;
  std::tie(figures->engine_steps_per_second, figures->engine_compile_seconds) =
      engine.Throughput(loaded, start.get(), o.worlds, o.throughput_steps);
  RolloutSpec spec;
  spec.count = o.worlds;
  spec.until = o.throughput_steps * loaded->opt.timestep;
  spec.sets = o.sets;
  spec.threads = ThreadsOrAllCores(o.threads);
  figures->cpu_threads = spec.threads;
  const auto begin = std::chrono::steady_clock::now();
  Rollout(
      model, spec, [](const RolloutResult&) {}, o.stop);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  figures->cpu_steps_per_second = double(o.worlds) * o.throughput_steps / std::max(seconds, 1e-9);
  CheckRow row;
  row.id = "throughput";
  row.section = "throughput";
  row.title = "world-steps per second: the engine against plumb rollout on all cores";
  row.measured = {figures->engine_steps_per_second, "steps/s"};
  row.reference = {figures->cpu_steps_per_second, "steps/s"};
  row.measured_text = fmt::format("{:.4g} steps/s ({} worlds x {} steps; first step {:.3g} s)",
                                  figures->engine_steps_per_second, o.worlds, o.throughput_steps,
                                  figures->engine_compile_seconds);
  row.reference_text = fmt::format("plumb rollout {:.4g} steps/s on {} thread(s)",
                                   figures->cpu_steps_per_second, spec.threads);
  const double ratio = figures->engine_steps_per_second / figures->cpu_steps_per_second;
  if (o.device == "cuda" && ratio < 1) {
    row.status = CheckStatus::kWarn;
    row.explanation = fmt::format(
        "the GPU engine is {:.2g}x plumb's CPU rollout at {} worlds: "
        "it does not pay for this model at this size",
        ratio, o.worlds);
    row.fix = "raise the number of worlds: GPU engines need thousands of them to fill the device";
  } else {
    row.status = CheckStatus::kPass;
    row.explanation =
        o.device == "cpu"
            ? fmt::format(
                  "ratio {:.2g}; CPU figures: the engine runs on the CPU here, which is "
                  "for development; GPU figures need the cuda device",
                  ratio)
            : fmt::format("the GPU engine is {:.2g}x plumb's CPU rollout", ratio);
  }
  return row;
}

}  // namespace

const std::vector<std::string>& CrosscheckEngines() {
  static const std::vector<std::string> kEngines = {"warp", "mjx"};
  return kEngines;
}

int CrosscheckReport::Count(CheckStatus status) const { return CountUnaccepted(rows, status); }

CrosscheckReport Crosscheck(const Model& model, const CrosscheckOptions& o) {
  Validate(o);
  RequireStepsToReach(o.until, RunTimestep(model, o.sets), "until");
  CrosscheckReport report;
  report.model = model.file();
  report.mujoco_version = mj_versionString();
  Model loaded = model.Clone();
  Data start(loaded);
  ApplyAssignments(loaded, start, o.sets);
  EngineSession engine(o.setup, o.engine, o.device, o.stop);
  report.engine = engine.info();
  auto add = [&](std::vector<CheckRow> rows) {
    report.rows.insert(report.rows.end(), rows.begin(), rows.end());
  };
  const NominalRun nominal = RunNominal(loaded, start, o);
  std::vector<CheckRow> support =
      SupportRows(loaded, report.engine, report.mujoco_version, nominal.touching);
  try {
    report.model_transfer = engine.Load(loaded);
  } catch (const EngineRefused& refused) {
    support.insert(support.begin(), RefusalRow(loaded, o.engine, refused.what()));
    if (Wants(o, "support")) add(support);
    for (const char* check : {"stages", "trajectory", "statistics", "throughput"}) {
      if (Wants(o, check)) report.rows.push_back(Skipped(check, "the engine refused the model"));
    }
    return report;
  }
  if (Wants(o, "support")) add(support);
  if (Wants(o, "stages")) add(StageCheck(loaded, nominal.samples, engine));
  if (Wants(o, "trajectory")) {
    add(TrajectoryCheck(loaded, Pointers(nominal.starts), engine, o, &report.divergence));
  }
  if (Wants(o, "statistics")) add(StatisticsCheck(model, loaded, engine, o));
  if (Wants(o, "throughput")) {
    report.rows.push_back(ThroughputCheck(model, loaded, start, engine, o, &report.throughput));
  }
  return report;
}

}  // namespace plumb
