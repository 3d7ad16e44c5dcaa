// plumb identify: fit model parameters to logs, with standard errors, correlations,
// identifiability warnings, a validation log, and the fitted model written back.

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "cli_common.h"
#include "log_options.h"
#include "plumb/error.h"
#include "plumb/identify.h"
#include "plumb/model_edit.h"
#include "plumb/report.h"

namespace plumb::cli {
namespace {

struct IdentifyCommandOptions {
  std::string model;
  std::vector<std::string> sets;
  std::vector<std::string> logs;
  std::string columns;
  IdentifyOptions identify;
  std::string delay;  // "", "ctrl" or "sensor"
  std::string validate;
  std::string output;  // -o FITTED.xml
  std::string format = "table";
  std::string report;  // --report FILE.html
};

std::string Changes(const IdentifyResult& r) {
  std::string out;
  for (const Estimate& e : r.estimates) {
    if (e.value == e.nominal) continue;
    out += fmt::format("  {}: {:.6g} -> {:.6g}", e.path, e.nominal, e.value);
    if (e.nominal != 0) out += fmt::format(" ({:+.1f} %)", 100 * (e.value / e.nominal - 1));
    out += "\n";
  }
  return out.empty() ? "  (nothing)\n" : out;
}

std::string Table(const IdentifyResult& r, const std::vector<RobotLog>& logs,
                  const IdentifyCommandOptions& o, const HeldOutLog* v) {
  long samples = 0;
  for (const RobotLog& log : logs) {
    for (const LogSignal& s : log.measured) samples += static_cast<long>(s.value.size());
  }
  std::string out = fmt::format("identify on {} from {} log(s), {} measured samples\n\n", o.model,
                                logs.size(), samples);
  std::size_t width = 10;
  for (const Estimate& e : r.estimates) width = std::max(width, e.path.size());
  out += fmt::format("{:<{}} {:>12} {:>12} {:>11} {:>25}\n", "parameter", width, "nominal",
                     "estimate", "std error", "95 % interval");
  for (const Estimate& e : r.estimates) {
    std::string interval = std::isfinite(e.std_error)
                               ? fmt::format("[{:.5g}, {:.5g}]", e.value - 1.96 * e.std_error,
                                             e.value + 1.96 * e.std_error)
                               : std::string("-");
    out += fmt::format("{:<{}} {:>12.6g} {:>12.6g} {:>11.3g} {:>25}{}\n", e.path, width, e.nominal,
                       e.value, e.std_error, interval, e.at_bound ? "  (on its bound)" : "");
  }
  if (o.identify.delay != DelayKind::kNone) {
    out += fmt::format(
        "{:<{}} {:>12} {:>12.6g} {:>11} {:>25}\n",
        o.identify.delay == DelayKind::kInput ? "input delay [s]" : "sensor delay [s]", width, "0",
        r.delay, "-",
        fmt::format("(resolution {:g} s)", r.delay_scan.size() > 1 ? r.delay_scan[1].first : 0.0));
  }
  if (r.estimates.size() > 1) {
    out += "\ncorrelation\n";
    for (std::size_t i = 0; i < r.estimates.size(); ++i) {
      out += fmt::format("  {:<{}}", r.estimates[i].path, width);
      for (std::size_t j = 0; j <= i; ++j) out += fmt::format(" {:>7.3f}", r.correlation[i][j]);
      out += "\n";
    }
  }
  out += fmt::format(
      "\nsolver: {}\nresidual variance {:.3g} (about 1 when the model explains all but the "
      "noise)\n",
      DescribeSolves(r), r.residual_variance);
  out += "\nnoise per signal (rms of the residuals):\n";
  for (std::size_t l = 0; l < logs.size(); ++l) {
    for (std::size_t i = 0; i < logs[l].measured.size(); ++i) {
      out += fmt::format("  {}  {}: {:.4g}\n", logs[l].source, logs[l].measured[i].column,
                         r.noise[l][i]);
    }
  }
  out += "\nfit per log (%): nominal -> fitted\n";
  for (std::size_t l = 0; l < logs.size(); ++l) {
    out += fmt::format("  {}: {:.2f} -> {:.2f}\n", logs[l].source, r.before[l].fit, r.after[l].fit);
  }
  if (v != nullptr) {
    out +=
        fmt::format("validation on {} (not used for the fit): nominal {:.2f} %, fitted {:.2f} %\n",
                    o.validate, v->nominal.fit, v->fitted.fit);
  }
  out += "\nchanged:\n" + Changes(r);
  for (const std::string& w : r.warnings) out += "warning: " + w + "\n";
  return out;
}

std::string Json(const IdentifyResult& r, const std::vector<RobotLog>& logs,
                 const IdentifyCommandOptions& o, const HeldOutLog* v) {
  nlohmann::ordered_json j;
  j["model"] = o.model;
  nlohmann::ordered_json estimates = nlohmann::ordered_json::array();
  for (const Estimate& e : r.estimates) {
    estimates.push_back({{"path", e.path},
                         {"nominal", e.nominal},
                         {"value", e.value},
                         {"std_error", JsonNumber(e.std_error)},
                         {"lo", JsonNumber(e.lo)},
                         {"hi", JsonNumber(e.hi)},
                         {"at_bound", e.at_bound},
                         {"sensitivity", JsonNumber(e.sensitivity)}});
  }
  j["estimates"] = estimates;
  nlohmann::ordered_json correlation = nlohmann::ordered_json::array();
  for (const std::vector<double>& row : r.correlation) {
    nlohmann::ordered_json cells = nlohmann::ordered_json::array();
    for (double c : row) cells.push_back(JsonNumber(c));
    correlation.push_back(cells);
  }
  j["correlation"] = correlation;
  j["singular_values"] = r.singular_values;
  if (o.identify.delay != DelayKind::kNone) {
    j["delay"] = {{"kind", o.delay}, {"value", r.delay}};
  }
  j["first_solve"] = {{"iterations", r.first_pass_iterations}, {"cost", r.first_pass_cost}};
  j["iterations"] = r.iterations;  // of the noise-weighted solve
  j["solved_again"] = r.solved_again;
  j["weight_change"] = r.weight_change;
  j["converged"] = r.converged;
  j["termination"] = r.termination;
  j["runs"] = r.runs;  // simulations of the logs, for every solve and the standard errors
  j["cost"] = r.cost;
  j["residual_variance"] = JsonNumber(r.residual_variance);
  nlohmann::ordered_json per_log = nlohmann::ordered_json::array();
  for (std::size_t l = 0; l < logs.size(); ++l) {
    nlohmann::ordered_json noise;
    for (std::size_t i = 0; i < logs[l].measured.size(); ++i) {
      noise[logs[l].measured[i].column] = JsonNumber(r.noise[l][i]);
    }
    per_log.push_back({{"log", logs[l].source},
                       {"fit_nominal", JsonNumber(r.before[l].fit)},
                       {"fit_fitted", JsonNumber(r.after[l].fit)},
                       {"noise", noise}});
  }
  j["logs"] = per_log;
  if (v != nullptr) {
    j["validation"] = {{"log", o.validate},
                       {"fit_nominal", JsonNumber(v->nominal.fit)},
                       {"fit_fitted", JsonNumber(v->fitted.fit)}};
  }
  j["warnings"] = r.warnings;
  return j.dump(2) + "\n";
}

int RunIdentify(IdentifyCommandOptions o, const Context& ctx) {
  Model model = LoadModel(o.model);
  ApplyParameterSets(model, o.sets);
  if (o.delay == "ctrl") o.identify.delay = DelayKind::kInput;
  if (o.delay == "sensor") o.identify.delay = DelayKind::kSensor;
  if (!(o.identify.replay.window >= 0 && std::isfinite(o.identify.replay.window))) {
    throw ValueError(
        fmt::format("--window {:g}: give a positive number of seconds", o.identify.replay.window));
  }
  if (!(o.identify.max_delay > 0 && std::isfinite(o.identify.max_delay))) {
    throw ValueError(
        fmt::format("--max-delay {:g}: give a positive number of seconds", o.identify.max_delay));
  }
  if (!o.output.empty() && !CanSaveEditedXml()) {
    SaveXmlWithParameters(o.model, model, {}, o.output);  // says why, before the work
  }
  // everything that can be wrong with the input is found before the fit starts
  ResolveFitParameters(model, o.identify.fit, o.identify.bounds);
  std::vector<RobotLog> logs = LoadLogs(model, o.logs, o.columns);
  std::vector<RobotLog> validation;
  if (!o.validate.empty()) validation = LoadLogs(model, {o.validate}, o.columns);

  o.identify.stop = CommandStop().token();
  o.identify.replay.stop = o.identify.stop;
  IdentifyResult r = Identify(model, logs, o.identify);
  Model fitted = model.Clone();
  ApplyEstimates(fitted, r);
  HeldOutLog v;
  if (!validation.empty()) {
    v.log = &validation.front();
    ReplayOptions replay = o.identify.replay;
    if (o.identify.delay == DelayKind::kInput) replay.input_delay = r.delay;
    if (o.identify.delay == DelayKind::kSensor) replay.sensor_delay = r.delay;
    v.nominal = Replay(model, validation.front(), o.identify.replay);
    v.fitted = Replay(fitted, validation.front(), replay);
  }
  if (!o.output.empty()) {
    std::vector<Path> paths;
    for (const Estimate& e : r.estimates) paths.push_back(ResolvePath(fitted, e.path));
    SaveXmlWithParameters(o.model, fitted, paths, o.output);
    std::fprintf(stderr, "plumb: wrote the fitted model %s\n", o.output.c_str());
  }
  if (!o.report.empty()) {
    WriteIdentifyReport(o.report, model, logs, r, ReportInfo{ctx.argv},
                        validation.empty() ? nullptr : &v);
    std::fprintf(stderr, "plumb: wrote the report %s\n", o.report.c_str());
  }
  const HeldOutLog* shown = validation.empty() ? nullptr : &v;
  WriteStdout(o.format == "json" ? Json(r, logs, o, shown) : Table(r, logs, o, shown));
  for (const ReplayResult& after : r.after) {
    if (after.simulated.diverged) return kExitDiverged;
  }
  return kExitOk;
}

}  // namespace

void SetupIdentifyCommand(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<IdentifyCommandOptions>();
  CLI::App* cmd = AddCommand(
      app, "identify", "Fit model parameters to logs: estimates, standard errors, warnings",
      "Examples:\n"
      "  plumb identify models/pendulum.xml --log decay.csv --fit 'dof_damping[hinge]'\n"
      "  plumb identify arm.xml --log chirp.csv --log steps.csv --fit 'dof_damping[*]' \\\n"
      "      --fit 'dof_frictionloss[*]' --bounds 'dof_damping[elbow]=0:5' --validate held-out.csv "
      "\\\n"
      "      -o arm-fitted.xml\n"
      "  plumb identify models/pendulum.xml --log flight.csv --columns map.toml \\\n"
      "      --fit 'dof_damping[hinge]' --delay ctrl\n"
      "Each log is one experiment (see plumb replay for the format). The start state of each\n"
      "log is fitted too (a logged start carries the measurement noise).\n"
      "Exit codes: 0 fitted (warnings are printed), 2 bad input (file, row and column named),\n"
      "3 the fitted model diverges on a log, 5 -o needs MuJoCo 3.10 or later.");
  AddModelOptions(cmd, &o->model, &o->sets, "(model parameters only) before the fit");
  cmd->add_option("--log", o->logs, "a log (CSV); repeat for several experiments")->required();
  cmd->add_option("--fit", o->identify.fit,
                  "a parameter to fit (plumb path, '*' for every row); repeat")
      ->required();
  cmd->add_option("--bounds", o->identify.bounds, "PATH=LO:HI; repeat");
  cmd->add_option("--columns", o->columns,
                  "column map (TOML: [columns] \"robot name\" = \"plumb path\")");
  cmd->add_option("--window", o->identify.replay.window,
                  "restart from the logged state every S seconds (multiple shooting)");
  cmd->add_option("--delay", o->delay, "estimate a pure delay on the inputs or measurements")
      ->check(CLI::IsMember({"ctrl", "sensor"}));
  cmd->add_option("--max-delay", o->identify.max_delay, "the longest delay tried, s")
      ->capture_default_str();
  cmd->add_option("--validate", o->validate, "a log not used for the fit, to check it on");
  cmd->add_option("-o", o->output, "write the model with the fitted values (MJCF)");
  cmd->add_option("--threads", o->identify.threads, "worker threads (0: every core)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1024));
  cmd->add_option("--max-iterations", o->identify.max_iterations,
                  "solver iterations at most, per solve")
      ->capture_default_str()
      ->check(CLI::Range(1, 10000));
  AddFormatOption(cmd, &o->format, {"table", "json"});
  AddReportOption(cmd, &o->report);
  cmd->callback([o, &ctx] { ctx.action = [o, &ctx] { return RunIdentify(*o, ctx); }; });
}

}  // namespace plumb::cli
