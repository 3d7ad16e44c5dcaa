// plumb bridge: the model as virtual hardware over DDS, wire-compatible with Unitree SDK2.

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <optional>

#include "cli_common.h"
#include "plumb/bridge.h"
#include "plumb/error.h"
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
};

int RunBridgeCommand(const BridgeCommandOptions& o) {
  Model model = LoadModel(o.model);
  BridgeConfig config = o.config.empty() ? BridgeConfig{} : LoadBridgeConfig(o.config);
  if (o.domain) config.domain = *o.domain;
  if (!o.mode.empty())
    config.mode = o.mode == "realtime" ? BridgeMode::kRealtime : BridgeMode::kLockstep;
  if (o.until) config.until = *o.until;
  if (!o.log.empty()) config.log = o.log;
  if (!o.gamepad.empty()) config.gamepad.events = o.gamepad;
  internal::RefuseOutputsOntoInputs(
      {{o.log.empty() ? "--config's log" : "--log", config.log}},
      ModelInputs(
          o.model, o.pose,
          {{"the --config file", o.config}, {"the gamepad events file", config.gamepad.events}}));
  std::fprintf(stderr,
               "plumb: bridge on DDS domain %u (loopback), %s, rt/lowcmd -> %s -> rt/lowstate; "
               "Ctrl-C stops it\n",
               config.domain, config.mode == BridgeMode::kLockstep ? "lockstep" : "realtime",
               model.file().c_str());
  BridgeStats stats = RunBridge(
      model, StartAssignments(model, o.keyframe, o.pose, o.sets), config, CommandStop().token(),
      [](const std::string& text) { std::fprintf(stderr, "plumb: %s\n", text.c_str()); });
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
      "The configuration (TOML): family = \"go\"|\"hg\", mode = \"lockstep\"|\"realtime\", "
      "domain,\n"
      "control_period, motors = [names], check_crc, log, until, command_queue (lockstep),\n"
      "[watchdog] timeout_ms, kd; [imu] and [secondary_imu] quaternion, gyroscope,\n"
      "accelerometer, body; [sport_state] publish, base, feet; [band] body, anchor, stiffness,\n"
      "damping, length, release_at, release_button; [gamepad] events, rate, topics; [[faults]].\n"
      "A gamepad events file: t = 2.0: start; t = 3.0: lx = 0.5 for 1.0 s\n"
      "Exit codes: 0 ok, 2 bad input (a --qpos whose length is not nq, a bad --pose file\n"
      "line, ...), 3 the simulation diverged, 5 DDS cannot start or this build has no bridge,\n"
      "130 stopped by Ctrl-C.");
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
  cmd->callback([o, &ctx] { ctx.action = [o] { return RunBridgeCommand(*o); }; });
}

}  // namespace plumb::cli
