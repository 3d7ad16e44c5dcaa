// plumb replay: a log's inputs drive the model from the log's start state; how well does
// the simulation match what was measured?

#include <fmt/format.h>

#include <cstdio>

#include "cli_common.h"
#include "plumb/error.h"
#include "plumb/replay.h"
#include "plumb/report.h"
#include "plumb/result_json.h"
#include "plumb/result_table.h"
#include "plumb/robot_log.h"

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

int RunReplay(const ReplayCommandOptions& o, const Context& ctx) {
  internal::RefuseOutputsOntoInputs({{"--report", o.report}},
                                    ModelInputs(o.model, {}, {{"the --log file", o.log}}));
  Model model = LoadModel(o.model);
  ApplyParameterAssignments(model, o.sets);
  CheckReplayOptions(o.replay);
  RobotLog log = std::move(LoadRobotLogs(model, {o.log}, o.columns, &CommandNotices()).front());
  ReplayOptions replay = o.replay;
  replay.stop = CommandStop().token();
  ReplayResult r = Replay(model, log, replay);
  if (!o.report.empty()) {
    WriteReplayReport(o.report, model, log, r, replay, ReportInfo{ctx.argv});
    std::fprintf(stderr, "plumb: wrote the report %s\n", o.report.c_str());
  }
  WriteStdout(o.format == "json" ? WithNotices(ReplayToJson(o.model, log, o.replay, r))
                                 : ReplayTable(o.model, log, o.replay, r));
  return r.simulated.diverged ? kExitDiverged : kExitOk;
}

}  // namespace

void SetupReplayCommand(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<ReplayCommandOptions>();
  CLI::App* cmd = AddCommand(
      app, "replay", "Drive the model with a log's inputs from its start state; compare",
      "Examples (each runs as written, in order, from the source folder):\n"
      "  plumb run models/pendulum.xml --set 'qpos[hinge]=0.7' --set 'dof_damping[hinge]=0.2' \\\n"
      "      --format csv --until 3 -o decay.csv\n"
      "  plumb replay models/pendulum.xml --log decay.csv\n"
      "  plumb replay models/pendulum.xml --log decay.csv --window 0.5 --format json\n"
      "  plumb replay models/pendulum.xml --log decay.csv --set 'dof_damping[hinge]=0.2'\n"
      "A log in the robot's own column names: --columns map.toml, whose [columns] table names\n"
      "a plumb path for each (\"angle\" = \"qpos[hinge]\").\n"
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
                  "restart from the logged state every S seconds (multiple shooting)")
      ->capture_default_str();
  cmd->add_option("--input-delay", o->replay.input_delay, "inputs act S seconds after logged")
      ->capture_default_str();
  cmd->add_option("--sensor-delay", o->replay.sensor_delay,
                  "measurements show the state S seconds before their time stamp")
      ->capture_default_str();
  AddFormatOption(cmd, &o->format, {"table", "json"});
  AddReportOption(cmd, &o->report);
  cmd->callback([o, &ctx] { ctx.action = [o, &ctx] { return RunReplay(*o, ctx); }; });
}

}  // namespace plumb::cli
