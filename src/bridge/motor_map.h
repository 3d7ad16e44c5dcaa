// Which element of the model each of the robot's motors is, and how to read and drive it.
//
// A motor is an actuator of the model (by default motor i is actuator i, the order of the
// Menagerie Go2 and G1) or, for models without actuators such as the chapter's pendulum, a
// hinge or slide joint driven through qfrc_applied. A driven actuator must be a torque motor
// (fixed gain, no bias, no activation dynamics): its ctrl is the torque divided by gain x gear.
// q and dq come from jointpos / jointvel sensors of the motor's joint when the model has them,
// else from qpos and qvel. An actuator's tau_est comes from a jointactuatorfrc sensor of its
// joint (the actuators' force measured at the joint, MuJoCo 3.x), else from an actuatorfrc
// sensor of the actuator times its gear, else from the force it applies; a joint's is the
// torque applied through qfrc_applied.
//
// A slot may be empty ("" in motors = [...]): the robot has the slot, the model no motor for
// it. Its q, dq and tau_est read 0 and what is applied to it goes nowhere.

#ifndef PLUMB_SRC_BRIDGE_MOTOR_MAP_H_
#define PLUMB_SRC_BRIDGE_MOTOR_MAP_H_

#include <string>
#include <vector>

#include "plumb/bridge.h"
#include "plumb/model.h"

namespace plumb::bridge {

struct Motor {
  std::string name;   // the actuator's or joint's name, for messages and logs
  int actuator = -1;  // the actuator driven, or -1 for a joint driven through qfrc_applied
  int ctrl = -1;      // its control in d->ctrl, and its force output in d->actuator_force
  int out = -1;       // (the same as `actuator` unless an actuator before it takes several)
  int joint = -1;     // the joint it moves (q, dq)
  int qpos = -1, dof = -1;
  double gear = 1;             // the actuator's gear (joint torque = gear x actuator force)
  double torque_per_ctrl = 1;  // gain x gear (actuators)
  double torque_lo = -1e300, torque_hi = 1e300;        // from forcerange and ctrlrange, N*m
  int sensor_q = -1, sensor_dq = -1, sensor_tau = -1;  // sensordata addresses, or -1
  bool tau_at_joint = false;  // sensor_tau is a jointactuatorfrc (joint torque, no gear)
  // An empty slot ("" in motors = [...]): no joint, no actuator.
  bool empty() const { return joint < 0; }
};

class MotorMap {
 public:
  // Binds `names` (actuator or joint names, one a motor, in motor order) or, when empty,
  // every actuator in order (by actuator, not by control: a pid takes two controls); an empty
  // name is an empty slot. @throws ValueError naming the motor and the element when a name is
  // unknown, an actuator is not a torque motor on a single joint, or a joint is not a hinge or
  // slide, or when every name is empty; with `positions` (BridgeConfig::positions) the message
  // starts at the name's file:line.
  static MotorMap Bind(const Model& model, const std::vector<std::string>& names,
                       const BridgePositions& positions = {});

  const std::vector<Motor>& motors() const { return motors_; }
  std::size_t size() const { return motors_.size(); }  // slots, empty ones included
  // Whether each slot is empty, in slot order.
  std::vector<bool> EmptySlots() const;

  double Q(const mjData* d, std::size_t i) const;
  double Dq(const mjData* d, std::size_t i) const;
  double TauEst(const mjData* d, std::size_t i) const;

  // Applies `tau` (N*m, clipped to the motor's limits) to motor i: ctrl for an actuator,
  // qfrc_applied for a joint, nothing for an empty slot (returns 0). Returns the torque applied.
  double Apply(mjData* d, std::size_t i, double tau) const;

 private:
  std::vector<Motor> motors_;
};

}  // namespace plumb::bridge

#endif  // PLUMB_SRC_BRIDGE_MOTOR_MAP_H_
