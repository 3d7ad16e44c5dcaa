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

// "realtime factor 0.983, 12 late periods (the worst 33.1 ms late)", and lockstep's waits
// for a late controller.
std::string Pacing(const BridgeStats& stats) {
  std::string text = std::isnan(stats.realtime_factor)
                         ? "no period ran"
                         : fmt::format("realtime factor {:.3f}", stats.realtime_factor);
  text += fmt::format(", {} late periods", stats.late_periods);
  if (stats.late_periods > 0) {
    text += fmt::format(" (the worst {:.1f} ms late)", stats.worst_lateness * 1000);
  }
  if (stats.late_commands > 0) {  // lockstep: simulated time waited for them
    text += fmt::format(", {} late commands waited for (the longest {:.2f} s)",
                        stats.late_commands, stats.longest_wait);
  }
  return text;
}

// ", 1500 sport-mode states, 300 gamepad messages, the band released at 2 s": what went out
// beside rt/lowstate.
std::string Extras(const BridgeStats& stats) {
  std::string text;
  if (stats.sport_states > 0) text += fmt::format(", {} sport-mode states", stats.sport_states);
  if (stats.secondary_imu_states > 0) {
    text += fmt::format(", {} secondary IMU states", stats.secondary_imu_states);
  }
  if (stats.gamepad_messages > 0) {
    text += fmt::format(", {} gamepad messages", stats.gamepad_messages);
  }
  if (!std::isnan(stats.band_released)) {
    text += fmt::format(", the band released at {:g} s", stats.band_released);
  }
  return text;
}

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
  std::printf(
      "plumb bridge: %.6g s simulated in %ld steps; %ld commands applied, %ld dropped for a bad "
      "CRC, %ld for NaN values, %ld from a second controller, %ld from a full lockstep queue; "
      "%ld states published%s; watchdog tripped %ld times; %s%s%s\n",
      stats.time, stats.steps, stats.commands, stats.bad_crc, stats.non_finite,
      stats.foreign_commands, stats.queue_drops, stats.states, Extras(stats).c_str(),
      stats.watchdog_trips, Pacing(stats).c_str(), config.log.empty() ? "" : "; log ",
      config.log.c_str());
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
