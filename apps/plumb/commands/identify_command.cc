// plumb identify: fit model parameters to logs, with standard errors, correlations,
// identifiability warnings, a validation log, and the fitted model written back.

#include <fmt/format.h>

#include <cstdio>

#include "cli_common.h"
#include "plumb/error.h"
#include "plumb/identify_job.h"
#include "plumb/report.h"
#include "plumb/result_json.h"
#include "plumb/result_table.h"

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

int RunIdentify(IdentifyCommandOptions o, const Context& ctx) {
  std::vector<internal::NamedPath> inputs =
      ModelInputs(o.model, {}, {{"the --validate log", o.validate}});
  for (const std::string& log : o.logs) inputs.push_back({"the --log file", log});
  internal::RefuseOutputsOntoInputs({{"-o", o.output}, {"--report", o.report}}, inputs);
  Model model = LoadModel(o.model);
  ApplyParameterAssignments(model, o.sets);
  o.identify.delay = ParseDelayKind(o.delay);
  Notices* notices = &CommandNotices();  // a cut log's note
  IdentifyRequest request{
      o.logs, o.columns, o.validate, o.identify, o.output, o.model, CommandStop().token(), notices};
  IdentifyJobResult r = RunIdentifyJob(model, request);
  if (!o.output.empty()) {
    std::fprintf(stderr, "plumb: wrote the fitted model %s\n", o.output.c_str());
  }
  if (!o.report.empty()) {
    WriteIdentifyReport(o.report, model, r.logs, r.fit, ReportInfo{ctx.argv}, r.HeldOut());
    std::fprintf(stderr, "plumb: wrote the report %s\n", o.report.c_str());
  }
  WriteStdout(o.format == "json"
                  ? WithNotices(IdentifyToJson(o.model, r.fit, r.logs, r.delay, r.HeldOut()))
                  : IdentifyTable(o.model, r.fit, r.logs, r.delay, r.HeldOut()));
  for (const ReplayResult& after : r.fit.after) {
    if (after.simulated.diverged) return kExitDiverged;
  }
  return kExitOk;
}

}  // namespace

void SetupIdentifyCommand(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<IdentifyCommandOptions>();
  CLI::App* cmd = AddCommand(
      app, "identify", "Fit model parameters to logs: estimates, standard errors, warnings",
      "Examples (each runs as written, in order, from the source folder):\n"
      "  plumb run models/pendulum.xml --set 'qpos[hinge]=0.7' --set 'dof_damping[hinge]=0.2' \\\n"
      "      --format csv --until 3 -o decay.csv\n"
      "  plumb identify models/pendulum.xml --log decay.csv --fit 'dof_damping[hinge]'\n"
      "  plumb identify models/pendulum.xml --log decay.csv --fit 'dof_damping[hinge]' \\\n"
      "      --bounds 'dof_damping[hinge]=0:5' -o pendulum-fitted.xml\n"
      "  plumb run models/pendulum.xml --set 'qpos[hinge]=0.7' \\\n"
      "      --set 'qfrc_applied[hinge]=0.5' --format csv -o pushed.csv \\\n"
      "      --columns 'time,qpos[hinge],qvel[hinge],qfrc_applied[hinge]'\n"
      "  plumb identify models/pendulum.xml --log pushed.csv --fit 'dof_damping[hinge]' \\\n"
      "      --delay ctrl\n"
      "Each log is one experiment (repeat --log for several; see plumb replay for the format).\n"
      "A log in the robot's own column names: --columns map.toml ([columns] \"angle\" =\n"
      "\"qpos[hinge]\"). The start state of each log is fitted too (a logged start carries the\n"
      "measurement noise).\n"
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
                  "restart from the logged state every S seconds (multiple shooting)")
      ->capture_default_str();
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
