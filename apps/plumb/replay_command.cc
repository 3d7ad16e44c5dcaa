// plumb replay: a log's inputs drive the model from the log's start state; how well does
// the simulation match what was measured?

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "cli_common.h"
#include "log_options.h"
#include "plumb/error.h"
#include "plumb/replay.h"
#include "plumb/report.h"

namespace plumb::cli {
namespace {

struct ReplayCommandOptions {
  std::string model;
  std::vector<std::string> sets;
  std::string log;
  std::string columns;  // column map
  ReplayOptions replay;
  std::string format = "table";
  std::string report;  // --report FILE.html
};

std::string Json(const ReplayResult& r, const RobotLog& log, const ReplayCommandOptions& o) {
  nlohmann::ordered_json j;
  j["model"] = o.model;
  j["log"] = log.source;
  j["window"] = o.replay.window;
  j["input_delay"] = o.replay.input_delay;
  j["sensor_delay"] = o.replay.sensor_delay;
  nlohmann::ordered_json signals = nlohmann::ordered_json::array();
  for (const SignalFit& f : r.signals) {
    signals.push_back({{"column", f.column},
                       {"path", f.path},
                       {"samples", f.samples},
                       {"rms", JsonNumber(f.rms)},
                       {"max_abs", JsonNumber(f.max_abs)},
                       {"worst_time", f.worst_time},
                       {"fit", JsonNumber(f.fit)}});
  }
  j["signals"] = signals;
  j["fit"] = JsonNumber(r.fit);
  j["diverged"] = r.simulated.diverged;
  j["problem"] = r.simulated.problem;
  j["notes"] = r.notes;
  return j.dump(2) + "\n";
}

std::string Table(const ReplayResult& r, const RobotLog& log, const ReplayCommandOptions& o) {
  std::string inputs;
  for (const LogSignal& s : log.inputs) inputs += (inputs.empty() ? "" : ", ") + s.column;
  std::string out =
      fmt::format("replay of {} on {}: {:g} s from t = {:g} s; inputs: {}\n", log.source, o.model,
                  log.end - log.start, log.start, inputs.empty() ? "none" : inputs);
  if (o.replay.window > 0) {
    out += fmt::format("restarted from the logged state every {:g} s\n", o.replay.window);
  }
  if (o.replay.input_delay != 0 || o.replay.sensor_delay != 0) {
    out += fmt::format("input delay {:g} s, sensor delay {:g} s\n", o.replay.input_delay,
                       o.replay.sensor_delay);
  }
  out += "\n" + FitTable(r.signals) + "\n";
  out += fmt::format(
      "overall fit {:.2f} % (mean of the signals; 100: the log exactly, 0: no "
      "better than each signal's mean)\n",
      r.fit);
  for (const std::string& note : r.notes) out += "note: " + note + "\n";
  if (r.simulated.diverged) out += r.simulated.problem + "\n";
  return out;
}

int RunReplay(const ReplayCommandOptions& o, const Context& ctx) {
  Model model = LoadModel(o.model);
  ApplyParameterSets(model, o.sets);
  if (!(o.replay.window >= 0 && std::isfinite(o.replay.window))) {
    throw ValueError(
        fmt::format("--window {:g}: give a positive number of seconds (or leave it "
                    "out for one run from the start)",
                    o.replay.window));
  }
  RobotLog log = std::move(LoadLogs(model, {o.log}, o.columns).front());
  ReplayOptions replay = o.replay;
  replay.stop = CommandStop().token();
  ReplayResult r = Replay(model, log, replay);
  if (!o.report.empty()) {
    WriteReplayReport(o.report, model, log, r, replay, ReportInfo{ctx.argv});
    std::fprintf(stderr, "plumb: wrote the report %s\n", o.report.c_str());
  }
  WriteStdout(o.format == "json" ? Json(r, log, o) : Table(r, log, o));
  return r.simulated.diverged ? kExitDiverged : kExitOk;
}

}  // namespace

void SetupReplayCommand(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<ReplayCommandOptions>();
  CLI::App* cmd = AddCommand(
      app, "replay", "Drive the model with a log's inputs from its start state; compare",
      "Examples:\n"
      "  plumb replay models/pendulum.xml --log decay.csv\n"
      "  plumb replay models/pendulum.xml --log flight.csv --window 0.5 --format json\n"
      "  plumb replay robot.xml --log robot.csv --columns robot-columns.toml\n"
      "The log: CSV with a time column and plumb paths (plumb run --format csv, the bridge's\n"
      "flight recorder); inputs (ctrl, qfrc_applied, ...) are held between samples, measured\n"
      "columns (qpos, qvel, sensordata, ...) are compared at their times.\n"
      "Exit codes: 0 replayed, 2 bad input (the message names the file, row and column),\n"
      "3 the simulation diverged.");
  AddModelOptions(cmd, &o->model, &o->sets, "(model parameters only) before the replay");
  cmd->add_option("--log", o->log, "the log (CSV)")->required();
  cmd->add_option("--columns", o->columns,
                  "column map (TOML: [columns] \"robot name\" = \"plumb path\")");
  cmd->add_option("--window", o->replay.window,
                  "restart from the logged state every S seconds (multiple shooting)");
  cmd->add_option("--input-delay", o->replay.input_delay, "inputs act S seconds after logged");
  cmd->add_option("--sensor-delay", o->replay.sensor_delay,
                  "measurements show the state S seconds before their time stamp");
  AddFormatOption(cmd, &o->format, {"table", "json"});
  AddReportOption(cmd, &o->report);
  cmd->callback([o, &ctx] { ctx.action = [o, &ctx] { return RunReplay(*o, ctx); }; });
}

}  // namespace plumb::cli
