// plumb bridge on loopback DDS with a controller in the loop (a thread of this program with
// its own participant): what the link costs.
//
//   bridge_bench lockstep MODEL MOTOR SECONDS   periods a second with the controller in the
//                                               loop, against the same steps without DDS
//   bridge_bench realtime MODEL MOTOR SECONDS   state inter-arrival times (jitter) and the
//                                               time from writing a command to receiving
//                                               the first state that shows it applied
// MOTOR is the joint or actuator the controller drives (one motor). Prints JSON lines.
//
// "Shows it applied": every command carries a distinct feed-forward torque and no gains; the
// motor is a joint driven through qfrc_applied, so the published tau_est equals the torque
// applied: the first state whose tau_est equals a command's torque marks that command as
// applied (it took effect at the step before that state was published).

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <future>
#include <map>
#include <string>
#include <vector>

#include "bridge/dds_link.h"
#include "bridge/unitree_crc.h"
#include "plumb/bridge.h"
#include "plumb/run.h"

namespace {

using Clock = std::chrono::steady_clock;
using Cmd = unitree_go_msg_dds__LowCmd_;
using State = unitree_go_msg_dds__LowState_;

double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, std::size_t(p * (v.size() - 1) + 0.5))];
}

Cmd Torque(float tau) {
  Cmd cmd;
  std::memset(&cmd, 0, sizeof cmd);
  cmd.motor_cmd[0].mode = 1;
  cmd.motor_cmd[0].tau = tau;
  cmd.crc = plumb::bridge::UnitreeCrc(cmd);
  return cmd;
}

// The controller's end of the link: its own participant in the bridge's domain.
struct Controller {
  explicit Controller(std::uint32_t domain_id)
      : domain(domain_id),
        commands(domain, "rt/lowcmd", &unitree_go_msg_dds__LowCmd__desc),
        states(domain, "rt/lowstate", &unitree_go_msg_dds__LowState__desc) {}
  plumb::bridge::DdsDomain domain;
  plumb::bridge::DdsWriter<Cmd> commands;
  plumb::bridge::DdsReader<State> states;
};

int Lockstep(const plumb::Model& model, plumb::BridgeConfig config, double seconds) {
  config.until = seconds;
  Controller link(config.domain);
  auto& commands = link.commands;
  auto& states = link.states;
  plumb::StopSource stop;
  auto run = std::async(std::launch::async,
                        [&] { return plumb::RunBridge(model, {}, config, stop.token()); });
  State s;
  long answered = 0;
  Clock::time_point first;
  while (states.Wait(DDS_SECS(5))) {
    if (!states.Take(&s)) continue;
    if (answered == 0) first = Clock::now();
    if (s.tick - config.start_tick >= std::lround(seconds * 1000)) break;
    commands.Write(Torque(0.0f));
    ++answered;
  }
  double loop = std::chrono::duration<double>(Clock::now() - first).count();
  stop.RequestStop();
  plumb::BridgeStats stats = run.get();
  // the same steps without DDS
  plumb::Model plain_model = model.Clone();
  plumb::Data data(plain_model);
  plumb::RunSpec spec;
  spec.until = seconds;
  spec.every = seconds;
  plumb::NullSink sink;
  auto t0 = Clock::now();
  plumb::RunResult plain = plumb::Run(plain_model, data, spec, sink);
  double plain_s = std::chrono::duration<double>(Clock::now() - t0).count();
  std::printf(
      "{\"mode\": \"lockstep\", \"periods\": %ld, \"steps\": %ld, \"seconds\": %.4f, "
      "\"periods_per_s\": %.0f, \"plain_steps\": %ld, \"plain_seconds\": %.5f, "
      "\"plain_steps_per_s\": %.0f, \"us_per_period_over_plain\": %.1f}\n",
      answered, stats.steps, loop, answered / loop, plain.steps, plain_s, plain.steps / plain_s,
      1e6 * (loop / answered -
             plain_s / std::max(1L, plain.steps) * stats.steps / std::max(1L, answered)));
  return 0;
}

int Realtime(const plumb::Model& model, plumb::BridgeConfig config, double seconds) {
  config.mode = plumb::BridgeMode::kRealtime;
  config.until = seconds;
  Controller link(config.domain);
  auto& commands = link.commands;
  auto& states = link.states;
  plumb::StopSource stop;
  auto run = std::async(std::launch::async,
                        [&] { return plumb::RunBridge(model, {}, config, stop.token()); });
  std::vector<double> gaps, latencies;
  std::map<float, Clock::time_point> sent;  // torque -> when its command was written
  Clock::time_point last;
  bool have_last = false;
  int k = 0;
  State s;
  while (states.Wait(DDS_SECS(5))) {
    while (states.Take(&s)) {
      auto now = Clock::now();
      if (have_last) gaps.push_back(std::chrono::duration<double, std::micro>(now - last).count());
      last = now;
      have_last = true;
      auto it = sent.find(s.motor_state[0].tau_est);
      if (it != sent.end()) {
        latencies.push_back(std::chrono::duration<double, std::micro>(now - it->second).count());
        sent.erase(sent.begin(), std::next(it));
      }
      if (s.tick - config.start_tick >= std::lround(seconds * 1000) - 10) goto done;
      // a new command every 10 states: each with its own small torque
      if (++k % 10 == 0) {
        float tau = 0.001f * float(k / 10 % 500 + 1);
        sent[tau] = Clock::now();
        commands.Write(Torque(tau));
      }
    }
  }
done:
  stop.RequestStop();
  run.get();
  double mean = 0;
  for (double g : gaps) mean += g / gaps.size();
  double var = 0;
  for (double g : gaps) var += (g - mean) * (g - mean) / gaps.size();
  std::printf(
      "{\"mode\": \"realtime\", \"states\": %zu, \"period_us\": %.0f, \"gap_mean_us\": %.1f, "
      "\"gap_sd_us\": %.1f, \"gap_p1_us\": %.1f, \"gap_p99_us\": %.1f, \"commands_seen\": %zu, "
      "\"cmd_to_state_median_us\": %.1f, \"cmd_to_state_p99_us\": %.1f}\n",
      gaps.size() + 1, config.control_period * 1e6, mean, std::sqrt(var), Percentile(gaps, 0.01),
      Percentile(gaps, 0.99), latencies.size(), Percentile(latencies, 0.5),
      Percentile(latencies, 0.99));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: bridge_bench lockstep|realtime MODEL MOTOR SECONDS\n");
    return 2;
  }
  plumb::Model model = plumb::Model::Load(argv[2]);
  plumb::BridgeConfig config;
  config.domain = 200;
  config.motors = {argv[3]};
  config.watchdog_timeout = 5;
  std::string mode = argv[1];
  double seconds = std::atof(argv[4]);
  return mode == "lockstep" ? Lockstep(model, config, seconds) : Realtime(model, config, seconds);
}
