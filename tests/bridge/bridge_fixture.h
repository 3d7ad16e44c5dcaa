// What the bridge's tests share: a controller on loopback DDS (its own participant in the
// bridge's domain) and the pendulum-holding command.

#ifndef PLUMB_TESTS_BRIDGE_BRIDGE_FIXTURE_H_
#define PLUMB_TESTS_BRIDGE_BRIDGE_FIXTURE_H_

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <future>
#include <string>
#include <utility>
#include <vector>

#include "bridge/dds_link.h"
#include "bridge/test_domain.h"
#include "bridge/unitree_crc.h"
#include "fixture.h"
#include "plumb/bridge.h"

namespace plumb {

using Cmd = unitree_go_msg_dds__LowCmd_;
using State = unitree_go_msg_dds__LowState_;

// The first state's tick (BridgeConfig::start_tick's default).
inline long StartTick() {
  static const long tick = BridgeConfig().start_tick;
  return tick;
}

// A state's simulated time in ms: its tick less the first state's.
template <typename Message>
long SimMs(const Message& s) {
  return static_cast<long>(s.tick) - StartTick();
}

// A controller: its own participant in the bridge's domain.
class Controller {
 public:
  explicit Controller(std::uint32_t domain)
      : domain_(domain),
        commands_(domain_, "rt/lowcmd", &unitree_go_msg_dds__LowCmd__desc),
        states_(domain_, "rt/lowstate", &unitree_go_msg_dds__LowState__desc) {}

  // The next state, or false after `seconds` without one.
  bool Next(State* s, double seconds = 5) {
    auto deadline = std::chrono::steady_clock::now() +
                    std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                        std::chrono::duration<double>(seconds));
    while (std::chrono::steady_clock::now() < deadline) {
      if (states_.Take(s)) return true;
      states_.Wait(DDS_MSECS(20));
    }
    return false;
  }

  void Send(Cmd cmd, bool good_crc = true) {
    cmd.crc = bridge::UnitreeCrc(cmd);
    if (!good_crc) cmd.crc ^= 1;
    commands_.Write(cmd);
  }

  bool Matched(double seconds = 5) {
    auto start = std::chrono::steady_clock::now();
    while (commands_.Matched() == 0 &&
           std::chrono::steady_clock::now() - start < std::chrono::duration<double>(seconds)) {
      dds_sleepfor(DDS_MSECS(10));
    }
    return commands_.Matched() > 0;
  }

 private:
  bridge::DdsDomain domain_;
  bridge::DdsWriter<Cmd> commands_;
  bridge::DdsReader<State> states_;
};

// Hold the pendulum at `target` rad: gravity feed-forward plus PD, as a Unitree client does.
inline Cmd Hold(double target) {
  Cmd cmd;
  std::memset(&cmd, 0, sizeof cmd);
  cmd.head[0] = 0xFE;
  cmd.head[1] = 0xEF;
  cmd.level_flag = 0xFF;
  auto& m = cmd.motor_cmd[0];
  m.mode = 1;
  m.q = static_cast<float>(target);
  m.kp = 20;
  m.kd = 2;
  m.tau = static_cast<float>(1.0 * 9.81 * 0.5 * std::sin(target));  // m g d sin(q)
  return cmd;
}

using testing::Occurrences;

inline BridgeConfig PendulumConfig(std::uint32_t domain, double until) {
  BridgeConfig config;
  config.domain = domain;
  config.motors = {"hinge"};
  config.until = until;
  config.watchdog_timeout = 3.0;  // generous: a loaded CI machine
  return config;
}

// The pendulum behind a bridge of `config` that runs on a thread of its own from `start`
// ("PATH=VALUE" texts), and a controller in its domain. Finish() stops it and gives its stats.
class PendulumBridge {
 public:
  explicit PendulumBridge(BridgeConfig config, const std::vector<std::string>& start = {})
      : config_(std::move(config)),
        model_(Model::Load(testing::kPendulum)),
        controller(config_.domain) {
    for (const std::string& text : start) start_.push_back(ParseAssignment(model_, text));
    run_ = std::async(std::launch::async,
                      [this] { return RunBridge(model_, start_, config_, stop_.token()); });
  }
  ~PendulumBridge() {
    if (run_.valid()) Finish();
  }

  BridgeStats Finish() {
    stop_.RequestStop();
    return run_.get();
  }
  const BridgeConfig& config() const { return config_; }

 private:
  BridgeConfig config_;  // (declared before the controller, which is made from it)
  Model model_;

 public:
  Controller controller;

 private:
  std::vector<Assignment> start_;
  StopSource stop_;
  std::future<BridgeStats> run_;
};

}  // namespace plumb

#endif  // PLUMB_TESTS_BRIDGE_BRIDGE_FIXTURE_H_
