// Fault injection between the controller and the simulated robot, as robot companies do it
// at the link layer (chapter 1.3.2). Every fault is seeded (draws are Philox, keyed by the
// fault and the message or step number: the same seed gives the same faults), runs from
// `start` to `stop` seconds of simulated time, and is logged when it starts and stops.
//
//   latency      command or state messages held back by fixed_ms + U(0, jitter_ms)
//   drop         command or state messages lost with `probability`
//   noise        Gaussian noise (sigma) and a bias added to a published signal: q, dq,
//                tau_est (one motor or all), gyro, accel, quat (rt/lowstate's IMU, which
//                rt/sportmodestate repeats), position, velocity, foot_force (rt/sportmodestate;
//                `motor` picks a component: an axis, or a foot)
//   torque_limit the motors' torque clipped to +-limit (saturation below the model's)
//   motor_failure one motor gives zero torque ("zero") or holds where it is ("stuck")
//   imu_freeze   the IMU repeats its last reading
//   controller_pause commands that arrive are ignored (the watchdog sees silence)

#ifndef PLUMB_SRC_BRIDGE_FAULTS_H_
#define PLUMB_SRC_BRIDGE_FAULTS_H_

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "plumb/bridge.h"

namespace plumb::bridge {

class Faults {
 public:
  Faults(std::vector<FaultSpec> specs, std::uint64_t seed);

  // Texts of faults that started or stopped at or before time `t` since the last call.
  std::vector<std::string> Transitions(double t);

  bool DropCommand(double t, std::uint32_t n) const { return Drop(false, t, n); }
  bool DropState(double t, std::uint32_t n) const { return Drop(true, t, n); }
  double CommandLatency(double t, std::uint32_t n) const { return Latency(false, t, n); }
  double StateLatency(double t, std::uint32_t n) const { return Latency(true, t, n); }
  // What noise and bias add to `signal` of `motor` (or component) in message n.
  double Noise(const std::string& signal, int motor, double t, std::uint32_t n) const;
  double TorqueLimit(int motor, double t) const;
  // 0: working, 1: zero torque, 2: stuck.
  int Failure(int motor, double t) const;
  bool ImuFrozen(double t) const;
  bool ControllerPaused(double t) const;

  bool empty() const { return specs_.empty(); }

 private:
  bool Active(const FaultSpec& f, double t) const { return t >= f.start && t < f.stop; }
  bool Drop(bool state, double t, std::uint32_t n) const;
  double Latency(bool state, double t, std::uint32_t n) const;
  std::vector<FaultSpec> specs_;
  std::vector<int> phase_;  // 0 not started, 1 running, 2 over
  std::uint64_t seed_;
};

}  // namespace plumb::bridge

#endif  // PLUMB_SRC_BRIDGE_FAULTS_H_
