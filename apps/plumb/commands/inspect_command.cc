// plumb inspect: the chapter's tables for any model, with units.

#include <fmt/format.h>

#include <cstdio>

#include "cli_common.h"
#include "plumb/describe.h"
#include "plumb/json_output.h"

namespace plumb::cli {
namespace {

struct InspectOptions {
  std::string model;
  std::vector<std::string> sets;
  std::string format = "table";
};

const char* SizeMeaning(const std::string& name) {
  if (name == "nbody") return "bodies, including the world body (id 0)";
  if (name == "njnt") return "joints";
  if (name == "nq") return "generalized positions: length of qpos";
  if (name == "nv") return "degrees of freedom: length of qvel, qacc, qfrc_*";
  if (name == "nu") return "actuators: length of ctrl";
  if (name == "na") return "actuator activations: length of act";
  if (name == "nsensor") return "sensors";
  if (name == "nsensordata") return "length of sensordata";
  if (name == "ngeom") return "geoms";
  if (name == "nsite") return "sites";
  if (name == "ntendon") return "tendons";
  if (name == "neq") return "equality constraints";
  if (name == "nmocap") return "mocap bodies";
  if (name == "nkey") return "keyframes";
  return "";
}

std::string Vec(const std::array<double, 3>& v) {
  return fmt::format("{:.6g} {:.6g} {:.6g}", v[0], v[1], v[2]);
}

// The text of `plumb inspect`, a line at a time.
struct Printer {
  std::string out;
  void operator()(const std::string& s) { out += s + "\n"; }
};

// The model's sizes and the options that set its time and gravity.
void PrintSizes(const ModelDescription& d, Printer& line) {
  line("sizes");
  long nq = 0, nv = 0;
  for (const auto& [name, value] : d.sizes) {
    line(fmt::format("  {:<12} {:>6}  {}", name, value, SizeMeaning(name)));
    if (name == "nq") nq = value;
    if (name == "nv") nv = value;
  }
  if (nq != nv) {
    line(
        fmt::format("  nq != nv ({} vs {}): a free joint has 7 qpos (position + quaternion) but 6 "
                    "dofs, a ball joint 4 and 3; never index qvel with qpos addresses.",
                    nq, nv));
  }
  line("");
  line("options");
  line(fmt::format("  {:<15} {:<24} s", "opt.timestep", fmt::format("{:g}", d.timestep)));
  line(fmt::format("  {:<15} {:<24}", "opt.integrator", d.integrator));
  line(fmt::format("  {:<15} {:<24} m/s^2", "opt.gravity", Vec(d.gravity)));
}

// Every body: parent, mass, centre of mass, principal inertia.
void PrintBodies(const ModelDescription& d, Printer& line) {
  line(fmt::format("bodies (total mass {:.6g} kg)", d.total_mass));
  line(fmt::format("  {:>3} {:<16} {:>6} {:>12} {:<30} {}", "id", "name", "parent", "mass [kg]",
                   "com in body frame [m]", "principal inertia [kg*m^2]"));
  for (const BodyDescription& b : d.bodies) {
    line(fmt::format("  {:>3} {:<16} {:>6} {:>12.6g} {:<30} {}", b.id, b.name, b.parent, b.mass,
                     Vec(b.com), Vec(b.inertia)));
  }
}

// Every joint: type, addresses, range, damping, armature.
void PrintJoints(const ModelDescription& d, Printer& line) {
  line("joints (angles in rad at run time, whatever the MJCF <compiler angle> says)");
  if (d.joints.empty())
    line("  (none)");
  else
    line(fmt::format("  {:>3} {:<16} {:<6} {:>4} {:>7} {:>6} {:<26} {:>10} {:>10}", "id", "name",
                     "type", "body", "qposadr", "dofadr", "range", "damping", "armature"));
  for (const JointDescription& j : d.joints) {
    std::string range =
        j.limited ? fmt::format("[{:.6g}, {:.6g}] {}", j.range[0], j.range[1], j.position_unit)
                  : "unlimited";
    line(fmt::format("  {:>3} {:<16} {:<6} {:>4} {:>7} {:>6} {:<26} {:>10.6g} {:>10.6g}", j.id,
                     j.name, j.type, j.body, j.qposadr, j.dofadr, range, j.damping, j.armature));
  }
  line("  units: damping N*m*s/rad (hinge) or N*s/m (slide); armature kg*m^2 or kg");
}

// Every actuator: its kind, what it drives, and its ranges in their units.
void PrintActuators(const ModelDescription& d, Printer& line) {
  line("actuators");
  if (d.actuators.empty())
    line("  (none: a passive system, ctrl is empty)");
  else
    line(fmt::format("  {:>3} {:<16} {:<9} {:<24} {:>8} {:<26} {:<24} {}", "id", "name", "kind",
                     "drives", "gear", "ctrlrange", "joint force", "forcerange"));
  auto range = [](const std::array<double, 2>& r, const std::string& unit) {
    return fmt::format("[{:.6g}, {:.6g}] {}", r[0], r[1], unit);
  };
  for (const ActuatorDescription& a : d.actuators) {
    std::string ctrl =
        a.ctrllimited ? range(a.ctrlrange, a.ctrl_unit) : "unlimited (" + a.ctrl_unit + ")";
    std::string joint = a.joint_force_limited ? range(a.joint_force_range, a.joint_force_unit)
                                              : "unlimited (" + a.joint_force_unit + ")";
    std::string force = a.forcelimited ? range(a.forcerange, a.force_unit) : "unlimited";
    line(fmt::format("  {:>3} {:<16} {:<9} {:<24} {:>8.6g} {:<26} {:<24} {}", a.id, a.name, a.kind,
                     a.transmission + ":" + a.target, a.gear, ctrl, joint, force));
  }
  if (!d.actuators.empty()) {
    line("  units: the joint (tendon) receives gear x actuator force; a motor's ctrl is its");
    line("  actuator force (N/gear: ctrl 1 with gear 10 is 10 N at the joint), a servo's ctrl");
    line("  a target of the actuator length (gear x the joint position) or its velocity");
  }
}

// Every sensor: its type, sensordata entries and unit.
void PrintSensors(const ModelDescription& d, Printer& line) {
  line("sensors");
  if (d.sensors.empty())
    line("  (none: sensordata is empty)");
  else
    line(fmt::format("  {:>3} {:<16} {:<17} {:<22} {}", "id", "name", "type", "entries", "unit"));
  for (const SensorDescription& s : d.sensors) {
    line(fmt::format("  {:>3} {:<16} {:<17} {:<22} {}", s.id, s.name, s.type,
                     fmt::format("sensordata[{}..{}]", s.adr, s.adr + s.dim - 1),
                     s.unit.empty() ? "-" : s.unit));
  }
}

// The delays, and each one MuJoCo shortens to its buffer; nothing when there are none.
void PrintDelays(const ModelDescription& d, Printer& line) {
  if (!d.delays.empty()) {
    line("");
    line("delays (MuJoCo keeps nsample past values: it delays by at most nsample x timestep)");
    line(fmt::format("  {:<8} {:>3} {:<16} {:>10} {:>8} {:>10}  {}", "kind", "id", "name",
                     "delay [s]", "nsample", "buffer [s]", "applied"));
    for (const DelayDescription& delay : d.delays) {
      line(fmt::format("  {:<8} {:>3} {:<16} {:>10.6g} {:>8} {:>10.6g}  {}", delay.kind, delay.id,
                       delay.name, delay.delay, delay.nsample, delay.buffer,
                       delay.shortened()
                           ? fmt::format("{:g} s: SHORTENED, nsample {} keeps {:g} s", delay.buffer,
                                         delay.needed_nsample, delay.delay)
                           : fmt::format("{:g} s", delay.delay)));
    }
  }
}

std::string Table(const ModelDescription& d) {
  Printer line;
  line(fmt::format("model {} ({}), MuJoCo {}", d.file, d.model_name, MujocoVersion()));
  for (auto section : {PrintSizes, PrintBodies, PrintJoints, PrintActuators, PrintSensors}) {
    line("");
    section(d, line);
  }
  PrintDelays(d, line);
  line("");
  line("what is what");
  for (const RoleDescription& r : d.roles) {
    line(fmt::format("  {:<10} {:<8} {}", r.role, r.where, r.examples));
    line(fmt::format("  {:<10} {:<8} written by {}", "", "", r.who_writes));
  }
  line("");
  line("units: length m, mass kg, time s, angle rad, torque N*m, force N");
  return line.out;
}

int RunInspect(const InspectOptions& o) {
  Model model = LoadModel(o.model);
  if (!o.sets.empty()) {
    Data data(model);
    ApplyAssignments(model, data, ParseAssignments(model, o.sets));
  }
  ModelDescription description = Describe(model);
  std::string text =
      o.format == "json" ? DescriptionToJson(description, MujocoVersion()) : Table(description);
  std::fwrite(text.data(), 1, text.size(), stdout);
  return kExitOk;
}

}  // namespace

void SetupInspectCommand(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<InspectOptions>();
  CLI::App* cmd = AddCommand(
      app, "inspect", "Print a model's sizes, options, bodies, joints, actuators and sensors",
      "Examples:\n"
      "  plumb inspect models/pendulum.xml\n"
      "  plumb inspect models/pendulum.xml --format json\n"
      "  plumb inspect models/pendulum.xml --set 'body_mass[link]=2'");
  AddModelOptions(cmd, &o->model, &o->sets, "applied before inspecting");
  AddFormatOption(cmd, &o->format, {"table", "json"});
  cmd->callback([o, &ctx] { ctx.action = [o] { return RunInspect(*o); }; });
}

}  // namespace plumb::cli
