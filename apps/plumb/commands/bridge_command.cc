// plumb bridge: the model as virtual hardware over DDS, wire-compatible with Unitree SDK2.

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <optional>

#include "cli_common.h"
#include "plumb/bridge.h"
#include "plumb/check_table.h"
#include "plumb/error.h"
#include "plumb/rehearse.h"
#include "plumb/report.h"
#include "plumb/result_json.h"
#include "plumb/run.h"

namespace plumb::cli {
namespace {

struct BridgeCommandOptions {
  std::string model;
  std::vector<std::string> sets;
  std::string keyframe;
  StartPose pose;
  std::string config;
  std::optional<std::uint32_t> domain;
  std::string mode;
  std::optional<double> until;
  std::string log;
  std::string gamepad;
  // the rehearsal (--client)
  RehearsalClient client;
  std::vector<std::string> client_env;  // NAME=VALUE
  std::vector<std::string> assertions;
  std::string format = "table";
  TableDetail detail = TableDetail::kFindings;
  std::string report;
};

// --client-env NAME=VALUE into the client's environment.
std::vector<std::pair<std::string, std::string>> ClientEnvironment(
    const std::vector<std::string>& entries) {
  std::vector<std::pair<std::string, std::string>> env;
  for (const std::string& e : entries) {
    std::size_t eq = e.find('=');
    if (eq == 0 || eq == std::string::npos) {
      throw ArgumentError("--client-env", Quoted(e), "must be NAME=VALUE");
    }
    env.emplace_back(e.substr(0, eq), e.substr(eq + 1));
  }
  return env;
}

// plumb bridge --client: the rehearsal, its table (or JSON) on stdout, its report.
int RunRehearsalCommand(const BridgeCommandOptions& o, const Model& model,
                        const BridgeConfig& config, const std::vector<std::string>& argv) {
  RehearsalSpec spec;
  spec.config = config;
  spec.client = o.client;
  spec.client.environment = ClientEnvironment(o.client_env);
  for (const std::string& text : o.assertions) {
    spec.assertions.push_back(ParseRehearsalAssertion(model, config, text));
  }
  std::fprintf(stderr, "plumb: rehearsal on DDS domain %u (%s) until t = %g s; the client: %s\n",
               config.domain, config.mode == BridgeMode::kLockstep ? "lockstep" : "realtime",
               config.until, o.client.command.c_str());
  std::vector<Assignment> start = StartAssignments(model, o.keyframe, o.pose, o.sets);
  RehearsalResult result = Rehearse(
      model, start, spec, CommandStop().token(),
      PrintNotice,
      &CommandNotices());
  if (!o.report.empty()) {
    WriteRehearsalReport(o.report, model, start, result, ReportInfo{argv});
    std::fprintf(stderr, "plumb: wrote the report %s\n", o.report.c_str());
  }
  std::string text = o.format == "json" ? WithNotices(RehearsalToJson(o.model, result))
                                        : RehearsalTable(o.model, result, o.detail, kSeeAllRows);
  std::fwrite(text.data(), 1, text.size(), stdout);
  if (o.format != "json") {
    std::printf("plumb bridge: %s\n", BridgeSummary(result.bridge, config).c_str());
  }
  if (result.bridge.diverged) return kExitDiverged;
  if (CommandStop().stop_requested()) return kExitInterrupted;
  return result.passed() ? kExitOk : kExitCheckFailed;
}

int RunBridgeCommand(const BridgeCommandOptions& o, const std::vector<std::string>& argv) {
  Model model = LoadModel(o.model);
  BridgeConfig config = o.config.empty() ? BridgeConfig{} : LoadBridgeConfig(o.config);
  if (o.domain) config.domain = *o.domain;
  if (!o.mode.empty())
    config.mode = o.mode == "realtime" ? BridgeMode::kRealtime : BridgeMode::kLockstep;
  if (o.until) config.until = *o.until;
  if (!o.log.empty()) config.log = o.log;
  if (!o.gamepad.empty()) config.gamepad.events = o.gamepad;
  if (o.client.command.empty() &&
      (!o.assertions.empty() || !o.report.empty() || o.format != "table")) {
    throw ArgumentError(!o.assertions.empty() ? "--assert" : !o.report.empty() ? "--report" : "--format",
                        "", "judges a rehearsal: give the client to run with --client 'CMD'");
  }
  internal::RefuseOutputsOntoInputs(
      {{o.log.empty() ? "--config's log" : "--log", config.log},
       {"--report", o.report},
       {"--client-output", o.client.output}},
      ModelInputs(
          o.model, o.pose,
          {{"the --config file", o.config}, {"the gamepad events file", config.gamepad.events}}));
  if (!o.client.command.empty()) return RunRehearsalCommand(o, model, config, argv);
  std::fprintf(stderr,
               "plumb: bridge on DDS domain %u (loopback), %s, rt/lowcmd -> %s -> rt/lowstate; "
               "Ctrl-C stops it\n",
               config.domain, config.mode == BridgeMode::kLockstep ? "lockstep" : "realtime",
               model.file().c_str());
  BridgeStats stats = RunBridge(
      model, StartAssignments(model, o.keyframe, o.pose, o.sets), config, CommandStop().token(),
      PrintNotice);
  std::printf("plumb bridge: %s\n", BridgeSummary(stats, config).c_str());
  if (stats.diverged) {
    std::fprintf(stderr, "plumb: %s\n", stats.problem.c_str());
    return kExitDiverged;
  }
  if (CommandStop().stop_requested()) return kExitInterrupted;
  return kExitOk;
}

}  // namespace

void SetupBridgeCommand(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<BridgeCommandOptions>();
  CLI::App* cmd = AddCommand(
      app, "bridge",
      "Run the model as virtual hardware over DDS: Unitree SDK2's rt/lowcmd in; rt/lowstate, "
      "rt/sportmodestate, rt/secondary_imu and the wireless controller out",
      "Examples:\n"
      "  plumb bridge go2.xml --config bridge.toml\n"
      "  plumb bridge models/pendulum.xml --config pendulum-bridge.toml --until 10 --log run.csv\n"
      "  plumb bridge go2.xml --config bridge.toml --pose lying.txt   (or --qpos with nq numbers)\n"
      "  plumb bridge go2.xml --config bridge.toml --until 10 --client 'python3 deploy.py lo' \\\n"
      "      --assert 'min(xpos[base][2]) > 0.2' --assert 'mean(saturated[*]) < 0.05' --report r.html\n"
      "The configuration (TOML): family = \"go\"|\"hg\", mode = \"lockstep\"|\"realtime\", "
      "domain,\n"
      "control_period, motors = [names, \"\" for an empty slot], check_crc, log, until,\n"
      "command_queue (lockstep),\n"
      "[watchdog] timeout_ms, kd; [imu] and [secondary_imu] quaternion, gyroscope,\n"
      "accelerometer, body; [sport_state] publish, base, feet; [band] body, anchor, stiffness,\n"
      "damping, length, release_at, release_button; [gamepad] events, rate, topics; [[faults]].\n"
      "A gamepad events file: t = 2.0: start; t = 3.0: lx = 0.5 for 1.0 s\n"
      "With --client, a rehearsal: the client starts once the bridge is up ({domain} in it is\n"
      "the domain id; PLUMB_BRIDGE_DOMAIN and CYCLONEDDS_URI are set for it), gets SIGINT at\n"
      "--until and SIGKILL after --grace; the verdict: the assertions, what plumb saw of the\n"
      "client's commands, how it ended.\n"
      "Exit codes: 0 ok (a rehearsal: it passed), 1 the rehearsal failed (an assertion, the\n"
      "client ended early, never commanded, was killed, ...), 2 bad input (a --qpos whose\n"
      "length is not nq, a bad --pose file line, a bad --assert, ...), 3 the simulation\n"
      "diverged, 5 DDS cannot start or this build has no bridge, 130 stopped by Ctrl-C.");
  AddModelOptions(cmd, &o->model, &o->sets, "before the run");
  AddKeyframeOption(cmd, &o->keyframe);
  AddStartPoseOptions(cmd, &o->pose);
  cmd->add_option("--config", o->config, "the bridge configuration (TOML)");
  cmd->add_option_function<std::uint32_t>(
         "--domain", [o](std::uint32_t v) { o->domain = v; }, "DDS domain id (overrides the file)")
      ->check(CLI::Range(0, 232));
  cmd->add_option("--mode", o->mode, "lockstep or realtime (overrides the file)")
      ->check(CLI::IsMember({"lockstep", "realtime"}));
  cmd->add_option_function<double>(
      "--until", [o](double v) { o->until = v; }, "stop after this much simulated time, s");
  cmd->add_option("--log", o->log, "the flight recorder's CSV file (overrides the file)");
  cmd->add_option("--gamepad", o->gamepad,
                  "a file of timed gamepad events for the wireless controller (overrides the "
                  "file's [gamepad] events)");
  cmd->add_option("--client", o->client.command,
                  "rehearse: run this command (/bin/sh -c) against the bridge and judge it; needs "
                  "--until");
  cmd->add_option("--client-cwd", o->client.directory, "the client's working directory");
  cmd->add_option("--client-env", o->client_env, "NAME=VALUE in the client's environment");
  cmd->add_option("--client-output", o->client.output, "a file for the client's whole output");
  cmd->add_option("--first-command-timeout", o->client.first_command_timeout,
                  "s of wall time the client has for its first command (default 60)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--grace", o->client.grace,
                  "s between SIGINT and SIGKILL when the client is stopped (default 5)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--assert", o->assertions,
                  "an assertion over the rehearsal: 'min(xpos[pelvis][2]) > 0.5', 'mean(qvel[0]) "
                  "> 0.3 during [7, 11]', 'max(tracking_error[*]) < 0.3', 'mean(saturated[*]) < "
                  "0.05'");
  AddFormatOption(cmd, &o->format, {"table", "json"});
  AddTableDetailOptions(cmd, &o->detail);
  AddReportOption(cmd, &o->report);
  cmd->callback([o, &ctx] { ctx.action = [o, &ctx] { return RunBridgeCommand(*o, ctx.argv); }; });
}

}  // namespace plumb::cli
