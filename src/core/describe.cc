#include "plumb/describe.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/joint_size.h"
#include "core/mujoco_compat.h"

namespace plumb {
using internal::JointDofSize;
using internal::JointQposSize;

namespace {

// What kind of actuator the gain and bias make: a motor passes ctrl through as force, a
// position (velocity) servo drives towards ctrl with a spring (damper) bias.
std::string ActuatorKind(const mjModel* m, int u) {
  if (m->actuator_gaintype[u] == mjGAIN_MUSCLE) return "muscle";
  if (m->actuator_gaintype[u] != mjGAIN_FIXED) {
    // MuJoCo's own kinds by their gain (dcmotor, so3, pid); affine and user gains are general
    std::string gain = compat::NameOf(compat::kGainTypes, m->actuator_gaintype[u]);
    bool named = gain != "affine" && gain != "user" && gain.rfind("type ", 0) != 0;
    return named ? gain : "general";
  }
  const mjtNum* bias = m->actuator_biasprm + mjNBIAS * u;
  if (m->actuator_biastype[u] == mjBIAS_NONE) return "motor";
  if (m->actuator_biastype[u] == mjBIAS_AFFINE && bias[0] == 0) {
    // an integrator in front of a position servo: ctrl is the velocity its target moves at
    if (bias[1] < 0 && m->actuator_dyntype[u] == mjDYN_INTEGRATOR) return "intvelocity";
    if (bias[1] < 0 && bias[2] <= 0) return "position";  // kv: a damped position servo
    if (bias[1] == 0 && bias[2] < 0) return "velocity";
  }
  return "general";
}

// The unit of each entry of sensor `s`.
std::string SensorUnit(const mjModel* m, int s) {
  int joint = m->sensor_objid[s];
  bool hinge = m->sensor_objtype[s] == mjOBJ_JOINT && m->jnt_type[joint] == mjJNT_HINGE;
  if (m->sensor_type[s] == compat::kSensorJointActuatorFrc) return hinge ? "N*m" : "N";
  switch (m->sensor_type[s]) {
    case mjSENS_TOUCH:
    case mjSENS_FORCE:
      return "N";
    case mjSENS_TORQUE:
      return "N*m";
    case mjSENS_ACCELEROMETER:
    case mjSENS_FRAMELINACC:
      return "m/s^2";
    case mjSENS_FRAMEANGACC:
      return "rad/s^2";
    case mjSENS_VELOCIMETER:
    case mjSENS_FRAMELINVEL:
    case mjSENS_SUBTREELINVEL:
      return "m/s";
    case mjSENS_GYRO:
    case mjSENS_BALLANGVEL:
    case mjSENS_FRAMEANGVEL:
      return "rad/s";
    case mjSENS_MAGNETOMETER:
      return "T";
    case mjSENS_RANGEFINDER:
    case mjSENS_FRAMEPOS:
    case mjSENS_SUBTREECOM:
    case mjSENS_TENDONPOS:
      return "m";
    case mjSENS_TENDONVEL:
      return "m/s";
    case mjSENS_JOINTPOS:
      return hinge ? "rad" : "m";
    case mjSENS_JOINTVEL:
      return hinge ? "rad/s" : "m/s";
    case mjSENS_SUBTREEANGMOM:
      return "kg*m^2/s";
    case mjSENS_CLOCK:
      return "s";
    default:  // quaternions, axes, actuator and limit quantities in their own units
      return "";
  }
}

// Body `b`: its parent, mass, centre of mass and principal inertia.
BodyDescription DescribeBody(const Model& model, int b) {
  const mjModel* m = model.get();
  BodyDescription body;
  body.id = b;
  body.name = b == 0 ? "world" : model.Name(mjOBJ_BODY, b);
  body.parent = m->body_parentid[b];
  body.mass = m->body_mass[b];
  for (int i = 0; i < 3; ++i) {
    body.com[i] = m->body_ipos[3 * b + i];
    body.inertia[i] = m->body_inertia[3 * b + i];
  }
  return body;
}

// Joint `j`: its type, addresses, limits, passive properties and position unit.
JointDescription DescribeJoint(const Model& model, int j) {
  const mjModel* m = model.get();
  JointDescription joint;
  joint.id = j;
  joint.name = model.Name(mjOBJ_JOINT, j);
  int type = m->jnt_type[j];
  joint.type = compat::NameOf(compat::kJointTypes, type);
  joint.body = m->jnt_bodyid[j];
  joint.qposadr = m->jnt_qposadr[j];
  joint.dofadr = m->jnt_dofadr[j];
  joint.nq = JointQposSize(type);
  joint.nv = JointDofSize(type);
  joint.limited = m->jnt_limited[j];
  joint.range = {m->jnt_range[2 * j], m->jnt_range[2 * j + 1]};
  joint.damping = m->dof_damping[joint.dofadr];
  joint.armature = m->dof_armature[joint.dofadr];
  joint.stiffness = m->jnt_stiffness[j];
  joint.frictionloss = m->dof_frictionloss[joint.dofadr];
  joint.position_unit = type == mjJNT_HINGE   ? "rad"
                        : type == mjJNT_SLIDE ? "m"
                        : type == mjJNT_BALL  ? "quat"
                                              : "m, quat";
  return joint;
}

// MuJoCo 3.12+ actuators may take several controls (a pid: two) and give several force
// outputs: ctrl-sized arrays by the first control, gear by the first output
ActuatorDescription DescribeActuator(const Model& model, int u) {
  const mjModel* m = model.get();
  ActuatorDescription act;
  act.id = u;
  auto [c, controls] = compat::ActuatorControls(m, u);
  long output = compat::ActuatorOutputs(m, u).first;
  act.name = model.Name(mjOBJ_ACTUATOR, u);
  int trn = m->actuator_trntype[u];
  act.transmission = compat::NameOf(compat::kTransmissions, trn);
  int target_type = trn == mjTRN_TENDON ? mjOBJ_TENDON
                    : trn == mjTRN_SITE ? mjOBJ_SITE
                    : trn == mjTRN_BODY ? mjOBJ_BODY
                                        : mjOBJ_JOINT;
  act.target = model.Name(target_type, m->actuator_trnid[2 * u]);
  act.gear = m->actuator_gear[6 * output];
  act.ctrllimited = controls > 0 && m->actuator_ctrllimited[c];
  if (controls > 0) {
    act.ctrlrange = {m->actuator_ctrlrange[2 * c], m->actuator_ctrlrange[2 * c + 1]};
  }
  act.forcelimited = m->actuator_forcelimited[u];
  act.forcerange = {m->actuator_forcerange[2 * u], m->actuator_forcerange[2 * u + 1]};
  // the joint (tendon) receives gear x the actuator force: a torque on a hinge, a force
  // on a slide or tendon
  std::string position = ActuatorPositionUnit(m, u);
  act.joint_force_unit = position == "rad" ? "N*m" : position == "m" ? "N" : "N, N*m";
  // with a gear the actuator's force is the joint's divided by it, its length multiplied
  bool geared = act.gear != 1;
  act.force_unit = geared ? act.joint_force_unit + "/gear" : act.joint_force_unit;
  if (geared) position = "gear*" + position;
  act.kind = ActuatorKind(m, u);
  act.ctrl_unit = act.kind == "motor"      ? act.force_unit
                  : act.kind == "position" ? position
                  : act.kind == "velocity" || act.kind == "intvelocity" ? position + "/s"
                  : act.kind == "muscle"   ? "activation 0..1"
                  : act.kind == "pid"      ? position + " (then a velocity setpoint)"
                                           : "set by gainprm";
  // the bounds of the actuator force: a motor's gain x ctrlrange, then forcerange
  double lo = -mjMAXVAL, hi = mjMAXVAL;
  if (act.kind == "motor" && act.ctrllimited) {
    double gain = m->actuator_gainprm[mjNGAIN * u];
    lo = std::min(gain * act.ctrlrange[0], gain * act.ctrlrange[1]);
    hi = std::max(gain * act.ctrlrange[0], gain * act.ctrlrange[1]);
    act.joint_force_limited = true;
  }
  if (act.forcelimited) {
    lo = std::max(lo, act.forcerange[0]);
    hi = std::min(hi, act.forcerange[1]);
    act.joint_force_limited = true;
  }
  // the joint's actuatorfrcrange bounds the force of all its actuators together: in joint
  // units, so brought to the actuator's by the gear
  if ((trn == mjTRN_JOINT || trn == mjTRN_JOINTINPARENT) && act.gear != 0) {
    if (auto joint = compat::JointActuatorForceRange(m, m->actuator_trnid[2 * u])) {
      double a = joint->first / act.gear, b = joint->second / act.gear;
      lo = std::max(lo, std::min(a, b));
      hi = std::min(hi, std::max(a, b));
      act.joint_force_limited = true;
    }
  }
  if (act.joint_force_limited) {
    act.joint_force_range = {std::min(act.gear * lo, act.gear * hi),
                             std::max(act.gear * lo, act.gear * hi)};
  }
  return act;
}

// What each role of path is, where it lives, what sets it, with this model's sizes.
std::vector<RoleDescription> Roles(const mjModel* m) {
  auto n = [](const char* field, long size) {
    return std::string(field) + " (" + std::to_string(size) + ")";
  };
  return {
      {"parameter", "mjModel",
       "opt.timestep, opt.gravity, body_mass, body_inertia, dof_damping, geom_size, "
       "actuator_gear, ...",
       "the MJCF compiler; fixed while the simulation runs (assign before a run)"},
      {"state", "mjData",
       "time, " + n("qpos", m->nq) + ", " + n("qvel", m->nv) + ", " + n("act", m->na) +
           (compat::PlasticSize(m) ? ", " + n("plastic", compat::PlasticSize(m)) : "") +
           (compat::HistorySize(m)
                ? ", " + n("history", compat::HistorySize(m)) + " (delays' ring buffer: read only)"
                : ""),
       "mj_step, which advances it; you may also set it, then call mj_forward"},
      {"input", "mjData",
       n("ctrl", m->nu) + ", " + n("qfrc_applied", m->nv) + ", " +
           n("xfrc_applied", 6L * m->nbody) + ", " + n("mocap_pos", 3L * m->nmocap),
       "your controller, before each mj_step"},
      {"derived", "mjData",
       n("qacc", m->nv) + ", " + n("xpos", 3L * m->nbody) + ", " + n("sensordata", m->nsensordata) +
           ", contact, qfrc_bias, ...",
       "MuJoCo, in mj_forward/mj_step; stale until one of them runs"},
  };
}

}  // namespace

std::string ActuatorPositionUnit(const mjModel* m, int actuator) {
  int trn = m->actuator_trntype[actuator];
  int target = m->actuator_trnid[2 * actuator];
  bool joint = trn == mjTRN_JOINT || trn == mjTRN_JOINTINPARENT;
  if (joint && m->jnt_type[target] == mjJNT_HINGE) return "rad";
  if ((joint && m->jnt_type[target] == mjJNT_SLIDE) || trn == mjTRN_TENDON) return "m";
  return "m, rad";
}

std::string DelayDescription::Warning() const {
  if (!shortened()) return "";
  return fmt::format(
      "{} '{}' (id {}): delay {:g} s is longer than its buffer of {} samples x timestep = {:g} s, "
      "so MuJoCo delays it by {:g} s only; set nsample=\"{}\" (or more) on the {} to keep "
      "{:g} s",
      kind, name.empty() ? "#" + std::to_string(id) : name, id, delay, nsample, buffer, buffer,
      needed_nsample, kind, delay);
}

std::vector<DelayDescription> Delays(const Model& model) {
  const mjModel* m = model.get();
  std::vector<DelayDescription> out;
  auto add = [&](const char* kind, int type, int id, compat::Delay d) {
    if (d.seconds <= 0) return;
    DelayDescription delay;
    delay.kind = kind;
    delay.id = id;
    delay.name = model.Name(type, id);
    delay.delay = d.seconds;
    delay.nsample = d.nsample;
    delay.buffer = static_cast<double>(d.nsample) * m->opt.timestep;
    delay.needed_nsample = static_cast<long>(std::ceil(d.seconds / m->opt.timestep - 1e-9));
    out.push_back(delay);
  };
  for (int u = 0; u < compat::ActuatorCount(m); ++u) {
    add("actuator", mjOBJ_ACTUATOR, u, compat::ActuatorDelay(m, u));
  }
  for (int s = 0; s < m->nsensor; ++s) add("sensor", mjOBJ_SENSOR, s, compat::SensorDelay(m, s));
  return out;
}

ModelDescription Describe(const Model& model) {
  const mjModel* m = model.get();
  ModelDescription out;
  out.file = model.file();
  out.model_name = m->names;  // the model name comes first in the names buffer
  out.sizes = {{"nbody", m->nbody},     {"njnt", m->njnt},
               {"nq", m->nq},           {"nv", m->nv},
               {"nu", m->nu},           {"na", m->na},
               {"nsensor", m->nsensor}, {"nsensordata", m->nsensordata},
               {"ngeom", m->ngeom},     {"nsite", m->nsite},
               {"ntendon", m->ntendon}, {"neq", m->neq},
               {"nmocap", m->nmocap},   {"nkey", m->nkey}};
  out.timestep = m->opt.timestep;
  out.integrator = compat::NameOf(compat::kIntegrators, m->opt.integrator);
  for (int i = 0; i < 3; ++i) out.gravity[i] = m->opt.gravity[i];

  for (int b = 0; b < m->nbody; ++b) {
    out.bodies.push_back(DescribeBody(model, b));
    out.total_mass += out.bodies.back().mass;
  }

  for (int j = 0; j < m->njnt; ++j) out.joints.push_back(DescribeJoint(model, j));

  for (int u = 0; u < compat::ActuatorCount(m); ++u) {
    out.actuators.push_back(DescribeActuator(model, u));
  }

  for (int s = 0; s < m->nsensor; ++s) {
    out.sensors.push_back({s, model.Name(mjOBJ_SENSOR, s),
                           compat::NameOf(compat::kSensorTypes, m->sensor_type[s]),
                           m->sensor_adr[s], m->sensor_dim[s], SensorUnit(m, s)});
  }
  out.delays = Delays(model);

  out.roles = Roles(m);
  return out;
}

}  // namespace plumb
