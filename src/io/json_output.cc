// JSON documents for model descriptions, states and warnings.

#include "plumb/json_output.h"

#include <nlohmann/json.hpp>

#include "plumb/version.h"

namespace plumb {

using nlohmann::ordered_json;

namespace {
std::string Dump(const ordered_json& j) { return j.dump(2) + "\n"; }

ordered_json StateJson(const StateSnapshot& s) {
  ordered_json j = {{"step", s.step}, {"time", s.time}, {"qpos", s.qpos},
                    {"qvel", s.qvel}, {"act", s.act},   {"ctrl", s.ctrl}};
  if (!s.qacc.empty()) j["qacc"] = s.qacc;  // NaN and Inf are written as null
  if (!s.note.empty()) j["note"] = s.note;
  // version 2 added the integration state (MuJoCo 3.5+'s history and 4.0's plastic state)
  j["format"] = "plumb.state";
  j["format_version"] = 2;
  j["integration_layout"] = IntegrationStateLayout();
  j["integration"] = s.integration;
  return j;
}

// `items` as a JSON array, each item by `to_json`.
template <typename T, typename F>
ordered_json ArrayOf(const std::vector<T>& items, F to_json) {
  ordered_json out = ordered_json::array();
  for (const T& item : items) out.push_back(to_json(item));
  return out;
}

// A body: its id, name, parent, mass, centre of mass and inertia.
ordered_json BodyJson(const BodyDescription& b) {
  return {{"id", b.id},     {"name", b.name}, {"parent", b.parent},
          {"mass", b.mass}, {"com", b.com},   {"inertia", b.inertia}};
}

// A joint: type, addresses, range and passive properties.
ordered_json JointJson(const JointDescription& jt) {
  return {{"id", jt.id},
          {"name", jt.name},
          {"type", jt.type},
          {"body", jt.body},
          {"qposadr", jt.qposadr},
          {"dofadr", jt.dofadr},
          {"nq", jt.nq},
          {"nv", jt.nv},
          {"limited", jt.limited},
          {"range", jt.range},
          {"position_unit", jt.position_unit},
          {"damping", jt.damping},
          {"armature", jt.armature},
          {"stiffness", jt.stiffness},
          {"frictionloss", jt.frictionloss}};
}

// An actuator: what it drives, its ranges and their units.
ordered_json ActuatorJson(const ActuatorDescription& a) {
  return {{"id", a.id},
          {"name", a.name},
          {"transmission", a.transmission},
          {"target", a.target},
          {"gear", a.gear},
          {"ctrllimited", a.ctrllimited},
          {"ctrlrange", a.ctrlrange},
          {"forcelimited", a.forcelimited},
          {"forcerange", a.forcerange},
          {"kind", a.kind},
          {"ctrl_unit", a.ctrl_unit},
          {"force_unit", a.force_unit},
          {"joint_force_range",
           a.joint_force_limited ? ordered_json(a.joint_force_range) : ordered_json(nullptr)},
          {"joint_force_unit", a.joint_force_unit}};
}

// A sensor: its type, sensordata entries and unit.
ordered_json SensorJson(const SensorDescription& s) {
  return {{"id", s.id},   {"name", s.name}, {"type", s.type},
          {"adr", s.adr}, {"dim", s.dim},   {"unit", s.unit}};
}

// A delay, and whether MuJoCo shortens it to its buffer.
ordered_json DelayJson(const DelayDescription& delay) {
  return {{"kind", delay.kind},
          {"id", delay.id},
          {"name", delay.name},
          {"delay", delay.delay},
          {"nsample", delay.nsample},
          {"buffer", delay.buffer},
          {"shortened", delay.shortened()},
          {"needed_nsample", delay.needed_nsample}};
}

// A role of path: where it lives and what writes it.
ordered_json RoleJson(const RoleDescription& r) {
  return {
      {"role", r.role}, {"where", r.where}, {"fields", r.examples}, {"who_writes", r.who_writes}};
}

}  // namespace

std::string DescriptionToJson(const ModelDescription& d, const std::string& mujoco) {
  ordered_json j;
  j["model"] = d.file;
  j["name"] = d.model_name;
  j["plumb_version"] = PLUMB_VERSION;
  j["mujoco_version"] = mujoco;
  ordered_json sizes = ordered_json::object();
  for (const auto& [name, value] : d.sizes) sizes[name] = value;
  j["sizes"] = sizes;
  j["options"] = {
      {"opt.timestep", d.timestep}, {"opt.integrator", d.integrator}, {"opt.gravity", d.gravity}};
  j["total_mass"] = d.total_mass;
  j["bodies"] = ArrayOf(d.bodies, BodyJson);
  j["joints"] = ArrayOf(d.joints, JointJson);
  j["actuators"] = ArrayOf(d.actuators, ActuatorJson);
  j["sensors"] = ArrayOf(d.sensors, SensorJson);
  j["delays"] = ArrayOf(d.delays, DelayJson);
  j["roles"] = ArrayOf(d.roles, RoleJson);
  j["units"] = {{"length", "m"},
                {"mass", "kg"},
                {"time", "s"},
                {"angle", "rad (at run time, whatever the MJCF <compiler angle> says)"},
                {"inertia", "kg*m^2"},
                {"hinge damping", "N*m*s/rad"},
                {"gravity", "m/s^2"}};
  return Dump(j);
}

std::string StateToJson(const StateSnapshot& state) { return Dump(StateJson(state)); }

std::string WarningsToJson(const std::vector<WarningSummary>& warnings) {
  ordered_json j = ordered_json::array();
  for (const WarningSummary& w : warnings) {
    j.push_back({{"kind", w.kind},
                 {"count", w.count},
                 {"first_step", w.first_step},
                 {"first_time", w.first_time},
                 {"message", w.message}});
  }
  return Dump(j);
}

}  // namespace plumb
