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

struct ConvergeCommandOptions {
  std::string model;
  std::vector<std::string> sets;
  std::string keyframe;
  StartPose pose;
  std::string metric;
  std::optional<double> dt;  // unset: the model's timestep
  int halvings = ConvergeOptions{}.halvings;
  double tol = ConvergeOptions{}.tol;
  std::optional<double> until;  // unset: the metric's default
  std::string format = "table";
  std::string report;  // --report FILE.html
};

int RunConverge(const ConvergeCommandOptions& o, const Context& ctx) {
  internal::RefuseOutputsOntoInputs({{"--report", o.report}}, ModelInputs(o.model, o.pose));
  Model model = LoadModel(o.model);
  Metric metric = ParseMetric(model, o.metric);
  ConvergeOptions options;
  options.sets = StartAssignments(model, o.keyframe, o.pose, o.sets);
  options.dt = o.dt;
  options.halvings = o.halvings;
  options.tol = o.tol;
  options.until = o.until;
  options.stop = CommandStop().token();
  ReportInfo info{ctx.argv};
  if (!o.report.empty()) {
    info.nominal_until = o.until ? *o.until : DefaultDuration(metric);
    info.ahead = StartPictures(model, options.sets, info);  // drawn while the ladder runs
  }
  ConvergenceResult r = Converge(model, metric, options);

  if (!o.report.empty()) {
    WriteConvergeReport(o.report, model, options.sets, {r}, r.integrator, info);
    std::fprintf(stderr, "plumb: wrote the report %s\n", o.report.c_str());
  }
  std::string text = o.format == "json" ? WithNotices(ConvergeToJson(r)) : ConvergeTable(r);
  std::fwrite(text.data(), 1, text.size(), stdout);
  return r.ok ? kExitOk : kExitDiverged;
}

}  // namespace

void SetupConvergeCommand(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<ConvergeCommandOptions>();
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
  cmd->add_option_function<double>(
      "--dt", [o](double v) { o->dt = v; }, "coarsest timestep in s (default: the model's)");
  cmd->add_option("--halvings", o->halvings, "number of halvings of dt")
      ->capture_default_str()
      ->check(CLI::Range(2, 20));
  cmd->add_option("--tol", o->tol, "relative tolerance for the recommended dt")
      ->capture_default_str();
  cmd->add_option_function<double>(
      "--until", [o](double v) { o->until = v; },
      "run length in s for period/maxabs/energy_drift (default 20 for period, else 2)");
  AddFormatOption(cmd, &o->format, {"table", "json"});
  AddReportOption(cmd, &o->report);
  cmd->callback([o, &ctx] { ctx.action = [o, &ctx] { return RunConverge(*o, ctx); }; });
}

}  // namespace plumb::cli
