// The motor's control law, as Unitree's motor controllers run it, evaluated at every
// physics step from the latest command:
//
//   tau = tau_ff + kp * (q_des - q) + kd * (dq_des - dq)
//
// A motor whose mode is 0 gives no torque. Non-finite commands are refused upstream (the
// bridge counts them); the result is clipped to the motor's limits by MotorMap::Apply.

#ifndef PLUMB_SRC_BRIDGE_PD_LAW_H_
#define PLUMB_SRC_BRIDGE_PD_LAW_H_

#include <cmath>
#include <cstdint>

namespace plumb::bridge {

struct MotorCommand {
  std::uint8_t mode = 0;  // 0: off
  double q = 0, dq = 0, tau = 0, kp = 0, kd = 0;

  bool finite() const {
    return std::isfinite(q) && std::isfinite(dq) && std::isfinite(tau) && std::isfinite(kp) &&
           std::isfinite(kd);
  }
};

inline double PdTorque(const MotorCommand& c, double q, double dq) {
  if (c.mode == 0) return 0;
  return c.tau + c.kp * (c.q - q) + c.kd * (c.dq - dq);
}

}  // namespace plumb::bridge

#endif  // PLUMB_SRC_BRIDGE_PD_LAW_H_
