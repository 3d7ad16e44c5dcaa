// plumb converge: does the answer converge as the timestep shrinks, and at what order?

#include <fmt/format.h>

#include <cmath>
#include <cstdio>

#include "cli_common.h"
#include "plumb/converge.h"
#include "plumb/error.h"
#include "plumb/report.h"
#include "plumb/result_json.h"
#include "plumb/result_table.h"
#include "plumb/timing.h"

namespace plumb::cli {
namespace {

constexpr double kUnset = -1e300;

struct ConvergeOptions {
  std::string model;
  std::vector<std::string> sets;
  std::string keyframe;
  StartPose pose;
  std::string metric;
  double dt = kUnset;  // the model's timestep
  int halvings = 4;
  double tol = 1e-3;
  double until = kUnset;  // the metric's default
  std::string format = "table";
  std::string report;  // --report FILE.html
};

int RunConverge(const ConvergeOptions& o, const Context& ctx) {
  Model model = LoadModel(o.model);
  std::vector<Assignment> sets = StartAssignments(model, o.keyframe, o.pose, o.sets);
  Metric metric = ParseMetric(model, o.metric);
  // the nominal model after --set decides the default dt and the integrator
  Model nominal = model.Clone();
  {
    Data data(nominal);
    ApplyAssignments(nominal, data, sets);
  }
  auto positive = [](double v, const char* option, const char* what) {
    if (v != kUnset && !(v > 0 && std::isfinite(v))) {
      throw ValueError(
          fmt::format("{} {:g}: {} must be a positive, finite number.", option, v, what));
    }
  };
  positive(o.dt, "--dt", "the coarsest timestep (s)");
  positive(o.until, "--until", "the run length (s)");
  positive(o.tol, "--tol", "the relative tolerance");
  double dt0 = o.dt != kUnset ? o.dt : RunTimestep(model, sets);
  double until = o.until != kUnset ? o.until : DefaultDuration(metric);
  ReportInfo info{ctx.argv};
  if (!o.report.empty()) {
    info.nominal_until = until;
    info.ahead = StartPictures(model, sets, info);  // drawn while the ladder runs
  }
  ConvergenceResult r =
      Converge(model, sets, metric, dt0, o.halvings, o.tol, until, CommandStop().token());
  if (!r.ok && !r.diverged) {
    // the metric does not apply to this run: the user must choose another or run longer
    throw ValueError(
        fmt::format("--metric '{}': {}. Start the motion (--set) or choose another metric.",
                    o.metric, r.problem));
  }

  if (!o.report.empty()) {
    WriteConvergeReport(o.report, model, sets, {r}, nominal->opt.integrator, info);
    std::fprintf(stderr, "plumb: wrote the report %s\n", o.report.c_str());
  }
  std::string text = o.format == "json" ? ConvergeToJson(r) : ConvergeTable(r);
  std::fwrite(text.data(), 1, text.size(), stdout);
  return r.ok ? kExitOk : kExitDiverged;
}

}  // namespace

void SetupConvergeCommand(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<ConvergeOptions>();
  CLI::App* cmd = AddCommand(
      app, "converge", "Run a metric at dt, dt/2, dt/4, ...: observed order, extrapolation, advice",
      "Examples:\n"
      "  plumb converge models/pendulum.xml --set 'qpos[hinge]=0.7' --metric 'qpos[hinge]@2'\n"
      "  plumb converge models/pendulum.xml --set 'qpos[hinge]=0.7' --set opt.integrator=RK4 \\\n"
      "      --metric 'qpos[hinge]@2'\n"
      "Metrics: PATH@T, period(PATH), maxabs(PATH), energy_drift, state@T.\n"
      "Exit codes: 0 ok, 2 bad input or a metric that cannot be measured, 3 a level diverged.");
  AddModelOptions(cmd, &o->model, &o->sets, "before each run");
  AddKeyframeOption(cmd, &o->keyframe);
  AddStartPoseOptions(cmd, &o->pose);
  cmd->add_option("--metric", o->metric, "what to measure, e.g. 'qpos[hinge]@2'")->required();
  cmd->add_option("--dt", o->dt, "coarsest timestep in s (default: the model's)");
  cmd->add_option("--halvings", o->halvings, "number of halvings of dt")
      ->capture_default_str()
      ->check(CLI::Range(2, 20));
  cmd->add_option("--tol", o->tol, "relative tolerance for the recommended dt")
      ->capture_default_str();
  cmd->add_option("--until", o->until,
                  "run length in s for period/maxabs/energy_drift (default 20 for period, else 2)");
  AddFormatOption(cmd, &o->format, {"table", "json"});
  AddReportOption(cmd, &o->report);
  cmd->callback([o, &ctx] { ctx.action = [o, &ctx] { return RunConverge(*o, ctx); }; });
}

}  // namespace plumb::cli
