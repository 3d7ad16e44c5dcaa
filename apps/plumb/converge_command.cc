// plumb converge: does the answer converge as the timestep shrinks, and at what order?

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "cli_common.h"
#include "plumb/converge.h"
#include "plumb/error.h"
#include "plumb/report.h"
#include "plumb/timing.h"

namespace plumb::cli {
namespace {

constexpr double kUnset = -1e300;

struct ConvergeOptions {
  std::string model;
  std::vector<std::string> sets;
  std::string keyframe;
  std::string metric;
  double dt = kUnset;  // the model's timestep
  int halvings = 4;
  double tol = 1e-3;
  double until = kUnset;  // the metric's default
  std::string format = "table";
  std::string report;  // --report FILE.html
};

// The result as a JSON document.
std::string ConvergeJson(const ConvergenceResult& r, const ConvergeOptions& o, double expected) {
  nlohmann::ordered_json j;
  j["metric"] = r.metric;
  j["model"] = o.model;
  j["integrator_expected_order"] = expected;
  nlohmann::ordered_json levels = nlohmann::ordered_json::array();
  for (const ConvergenceLevel& l : r.levels) {
    levels.push_back({{"dt", l.dt},
                      {"value", JsonNumber(l.value)},
                      {"diff", JsonNumber(l.diff)},
                      {"order", JsonNumber(l.order)},
                      {"error", JsonNumber(l.error)},
                      {"error_is_richardson", l.error_is_richardson},
                      {"roundoff", l.roundoff}});
  }
  j["levels"] = levels;
  j["observed_order"] = r.estimate.resolved ? JsonNumber(r.estimate.order) : nullptr;
  j["order_resolved"] = r.estimate.resolved;
  j["extrapolated"] = JsonNumber(r.estimate.extrapolated);  // an estimate, not a measured level
  j["scale"] = r.scale;
  j["tol"] = r.tol;
  j["recommended_dt"] = r.recommended_dt > 0 ? JsonNumber(r.recommended_dt) : nullptr;
  j["contacts"] = r.max_contacts;
  j["caveat"] =
      r.caveat.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(r.caveat);
  j["note"] = r.ok ? r.estimate.note : r.problem;
  return j.dump(2) + "\n";
}

// The result as the table a person reads: the levels, then the verdict.
std::string ConvergeTable(const ConvergenceResult& r, const ConvergeOptions& o, double until,
                          double expected) {
  std::string out = fmt::format("metric {} on {}, over {:g} s\n\n", r.metric, o.model, until);
  out += fmt::format("{:>12} {:>22} {:>12} {:>8} {:>12}\n", "dt [s]", "value", "diff", "order",
                     "est. error");
  auto num = [](double v, const char* spec) {
    return std::isfinite(v) ? fmt::format(fmt::runtime(spec), v) : std::string("-");
  };
  for (const ConvergenceLevel& l : r.levels) {
    out += fmt::format("{:>12g} {:>22} {:>12} {:>8} {:>12}{}{}\n", l.dt, num(l.value, "{:.15g}"),
                       num(l.diff, "{:.3e}"), num(l.order, "{:.2f}"), num(l.error, "{:.3e}"),
                       l.roundoff ? "  (diff is round-off)" : "",
                       l.error_is_richardson ? "  (Richardson estimate: no finer level)" : "");
  }
  out += "\n";
  if (!r.ok) {
    out += (r.diverged ? "diverged " : "cannot measure ") + r.problem + "\n";
  } else {
    out += r.estimate.resolved
               ? fmt::format("observed order  {:.2f} (the integrator's is {:g})\n",
                             r.estimate.order, expected)
               : fmt::format("observed order  unresolved (the integrator's is {:g})\n", expected);
    bool measured = r.estimate.extrapolated == r.levels.back().value;
    out += fmt::format("value           {:.15g} ({}: {})\n", r.estimate.extrapolated,
                       measured ? "measured at the finest level" : "an estimate", r.estimate.note);
    out += r.recommended_dt > 0
               ? fmt::format(
                     "recommended dt  {:g} s: the largest tested level with estimated error "
                     "below tol {:g} x scale {:.3g}\n",
                     r.recommended_dt, r.tol, r.scale)
               : std::string(
                     "recommended dt  none (no tested level is shown to meet the tolerance; "
                     "try a smaller --dt or more --halvings)\n");
    if (!r.caveat.empty()) out += "caveat          " + r.caveat + "\n";
  }
  return out;
}

int RunConverge(const ConvergeOptions& o, const Context& ctx) {
  Model model = LoadModel(o.model);
  std::vector<Assignment> sets = StartAssignments(model, o.keyframe, o.sets);
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
  ConvergenceResult r = Converge(model, sets, metric, dt0, o.halvings, o.tol, until, CommandStop().token());
  double expected = ExpectedOrder(nominal->opt.integrator);
  if (!r.ok && !r.diverged) {
    // the metric does not apply to this run: the user must choose another or run longer
    throw ValueError(
        fmt::format("--metric '{}': {}. Start the motion (--set) or choose another metric.",
                    o.metric, r.problem));
  }

  if (!o.report.empty()) {
    ReportInfo info{ctx.argv};
    info.nominal_until = until;
    WriteConvergeReport(o.report, model, sets, {r}, nominal->opt.integrator, info);
    std::fprintf(stderr, "plumb: wrote the report %s\n", o.report.c_str());
  }
  std::string text =
      o.format == "json" ? ConvergeJson(r, o, expected) : ConvergeTable(r, o, until, expected);
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
