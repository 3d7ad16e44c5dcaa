// Binding motors to actuators or joints, reading their state, applying torque.

#include "bridge/motor_map.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "bridge/positions.h"
#include "core/mujoco_compat.h"
#include "core/strings.h"
#include "plumb/error.h"

namespace plumb::bridge {
using internal::Echo;

namespace {

// The first sensor of `type` on joint `joint`, as its sensordata address, or -1.
int SensorOn(const mjModel* m, int type, int objtype, int id) {
  if (type < 0) return -1;  // a sensor type this MuJoCo lacks
  for (int s = 0; s < m->nsensor; ++s) {
    if (m->sensor_type[s] == type && m->sensor_objtype[s] == objtype && m->sensor_objid[s] == id) {
      return m->sensor_adr[s];
    }
  }
  return -1;
}

std::string Label(const Model& model, int type, int id, const char* kind) {
  std::string name = model.Name(type, id);
  return fmt::format("{} '{}' (id {})", kind, name.empty() ? "#" + std::to_string(id) : name, id);
}

Motor FromActuator(const Model& model, int u, std::size_t index) {
  const mjModel* m = model.get();
  Motor motor;
  motor.name = model.Name(mjOBJ_ACTUATOR, u);
  motor.actuator = u;
  motor.ctrl = static_cast<int>(compat::ActuatorControls(m, u).first);
  motor.out = static_cast<int>(compat::ActuatorOutputs(m, u).first);
  std::string what =
      fmt::format("motor {} ({})", index, Label(model, mjOBJ_ACTUATOR, u, "actuator"));
  int trn = m->actuator_trntype[u];
  if (trn != mjTRN_JOINT && trn != mjTRN_JOINTINPARENT) {
    throw ValueError(what + " does not drive a joint: the bridge drives joint motors");
  }
  motor.joint = m->actuator_trnid[2 * u];
  int type = m->jnt_type[motor.joint];
  if (type != mjJNT_HINGE && type != mjJNT_SLIDE) {
    throw ValueError(what + " drives a ball or free joint: a motor turns one hinge or slide");
  }
  bool torque = m->actuator_gaintype[u] == mjGAIN_FIXED && m->actuator_biastype[u] == mjBIAS_NONE &&
                m->actuator_dyntype[u] == mjDYN_NONE;
  if (!torque) {
    throw ValueError(what +
                     " is not a torque motor (a position/velocity servo, muscle or filtered "
                     "actuator): the bridge computes the torque itself (kp, kd from the "
                     "command), so the model must take torque: use <motor>");
  }
  motor.gear = m->actuator_gear[6 * motor.out];
  motor.torque_per_ctrl = m->actuator_gainprm[u * mjNGAIN] * motor.gear;
  if (motor.torque_per_ctrl == 0) throw ValueError(what + " has zero gain x gear");
  if (m->actuator_ctrllimited[motor.ctrl]) {
    double a = m->actuator_ctrlrange[2 * motor.ctrl] * motor.torque_per_ctrl;
    double b = m->actuator_ctrlrange[2 * motor.ctrl + 1] * motor.torque_per_ctrl;
    motor.torque_lo = std::min(a, b);
    motor.torque_hi = std::max(a, b);
  }
  if (m->actuator_forcelimited[u]) {
    double gear = m->actuator_gear[6 * u];
    double a = m->actuator_forcerange[2 * u] * gear, b = m->actuator_forcerange[2 * u + 1] * gear;
    motor.torque_lo = std::max(motor.torque_lo, std::min(a, b));
    motor.torque_hi = std::min(motor.torque_hi, std::max(a, b));
  }
  return motor;
}

Motor FromJoint(const Model& model, int j, std::size_t index) {
  const mjModel* m = model.get();
  int type = m->jnt_type[j];
  if (type != mjJNT_HINGE && type != mjJNT_SLIDE) {
    throw ValueError(
        fmt::format("motor {} ({}) is a ball or free joint: a motor turns one hinge "
                    "or slide",
                    index, Label(model, mjOBJ_JOINT, j, "joint")));
  }
  Motor motor;
  motor.name = model.Name(mjOBJ_JOINT, j);
  motor.joint = j;
  return motor;
}

}  // namespace

MotorMap MotorMap::Bind(const Model& model, const std::vector<std::string>& names,
                        const BridgePositions& positions) {
  const mjModel* m = model.get();
  MotorMap map;
  if (names.empty()) {
    if (compat::ActuatorCount(m) == 0) {
      throw ValueError("'" + model.file() +
                       "' has no actuators: name the joints the motors drive in the bridge "
                       "configuration (motors = [\"hinge\"])");
    }
    for (int u = 0; u < compat::ActuatorCount(m); ++u) {
      map.motors_.push_back(FromActuator(model, u, map.size()));
    }
  }
  if (!names.empty() && std::all_of(names.begin(), names.end(),
                                    [](const std::string& name) { return name.empty(); })) {
    throw ValueError(fmt::format(
        "{}every slot in motors = [...] is empty: name at least one actuator or joint of '{}'",
        Place(positions, "motors[0]"), model.file()));
  }
  for (const std::string& name : names) {
    if (name.empty()) {  // a slot of the robot's the model has no motor for
      map.motors_.emplace_back();
      continue;
    }
    std::string place = Place(positions, fmt::format("motors[{}]", map.size()));
    int u = mj_name2id(m, mjOBJ_ACTUATOR, name.c_str());
    int j = mj_name2id(m, mjOBJ_JOINT, name.c_str());
    try {
      if (u >= 0) {
        map.motors_.push_back(FromActuator(model, u, map.size()));
      } else if (j >= 0) {
        map.motors_.push_back(FromJoint(model, j, map.size()));
      } else {
        throw ValueError(fmt::format("motor {}: '{}' is neither an actuator nor a joint of '{}'",
                                     map.size(), Echo(name), model.file()));
      }
    } catch (const ValueError& e) {
      throw ValueError(place + e.what());
    }
  }
  for (Motor& motor : map.motors_) {
    if (motor.empty()) continue;
    motor.qpos = m->jnt_qposadr[motor.joint];
    motor.dof = m->jnt_dofadr[motor.joint];
    motor.sensor_q = SensorOn(m, mjSENS_JOINTPOS, mjOBJ_JOINT, motor.joint);
    motor.sensor_dq = SensorOn(m, mjSENS_JOINTVEL, mjOBJ_JOINT, motor.joint);
    if (motor.actuator >= 0) {
      // the force at the joint when the model measures it there, else the actuator's own
      motor.sensor_tau = SensorOn(m, compat::kSensorJointActuatorFrc, mjOBJ_JOINT, motor.joint);
      motor.tau_at_joint = motor.sensor_tau >= 0;
      if (!motor.tau_at_joint) {
        motor.sensor_tau = SensorOn(m, mjSENS_ACTUATORFRC, mjOBJ_ACTUATOR, motor.actuator);
      }
    }
  }
  return map;
}

std::vector<bool> MotorMap::EmptySlots() const {
  std::vector<bool> empty;
  for (const Motor& motor : motors_) empty.push_back(motor.empty());
  return empty;
}

double MotorMap::Q(const mjData* d, std::size_t i) const {
  const Motor& motor = motors_[i];
  if (motor.empty()) return 0;
  return motor.sensor_q >= 0 ? d->sensordata[motor.sensor_q] : d->qpos[motor.qpos];
}

double MotorMap::Dq(const mjData* d, std::size_t i) const {
  const Motor& motor = motors_[i];
  if (motor.empty()) return 0;
  return motor.sensor_dq >= 0 ? d->sensordata[motor.sensor_dq] : d->qvel[motor.dof];
}

double MotorMap::TauEst(const mjData* d, std::size_t i) const {
  const Motor& motor = motors_[i];
  if (motor.empty()) return 0;
  if (motor.actuator < 0) return d->qfrc_applied[motor.dof];
  if (motor.tau_at_joint) return d->sensordata[motor.sensor_tau];
  // actuatorfrc is the actuator's scalar force; the joint sees it times the gear
  double force =
      motor.sensor_tau >= 0 ? d->sensordata[motor.sensor_tau] : d->actuator_force[motor.out];
  return force * motor.gear;
}

double MotorMap::Apply(mjData* d, std::size_t i, double tau) const {
  const Motor& motor = motors_[i];
  if (motor.empty()) return 0;
  double applied = std::clamp(tau, motor.torque_lo, motor.torque_hi);
  if (motor.actuator >= 0) {
    d->ctrl[motor.ctrl] = applied / motor.torque_per_ctrl;
  } else {
    d->qfrc_applied[motor.dof] = applied;
  }
  return applied;
}

}  // namespace plumb::bridge
