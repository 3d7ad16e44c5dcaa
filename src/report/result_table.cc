// The tables of inspect, converge, diff, replay and identify (include/plumb/result_table.h).

#include "plumb/result_table.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/strings.h"
#include "plumb/error.h"
#include "plumb/model.h"

namespace plumb {
using internal::Join;

namespace {

// `v` with `spec`, or "-" when it is not finite.
std::string Num(double v, const char* spec) {
  return std::isfinite(v) ? fmt::format(fmt::runtime(spec), v) : std::string("-");
}

std::string ConvergeVerdict(const ConvergenceResult& r) {
  if (!r.ok) return (r.diverged ? "diverged " : "cannot measure ") + r.problem + "\n";
  std::string out = r.estimate.resolved
                        ? fmt::format("observed order  {:.2f} (the integrator's is {:g})\n",
                                      r.estimate.order, r.expected_order)
                        : fmt::format("observed order  unresolved (the integrator's is {:g})\n",
                                      r.expected_order);
  bool measured = r.estimate.extrapolated == r.levels.back().value;
  out += fmt::format("value           {:.15g} ({}: {})\n", r.estimate.extrapolated,
                     measured ? "measured at the finest level" : "an estimate", r.estimate.note);
  out += r.recommended_dt > 0
             ? fmt::format(
                   "recommended dt  {:g} s: the largest tested level that, with every finer "
                   "level, meets tol {:g} x scale {:.3g}\n",
                   r.recommended_dt, r.tol, r.scale)
             : std::string(
                   "recommended dt  none (no tested level is shown to meet the tolerance; "
                   "start from a smaller timestep or halve it more times)\n");
  if (!r.caveat.empty()) out += "caveat          " + r.caveat + "\n";
  if (!SolrefNote(r).empty()) out += "solref          " + SolrefNote(r) + "\n";
  return out;
}

// Under another MuJoCo than the snapshot's: the upgrade's question, answered in one line.
std::string UpgradeLine(const SnapshotDiff& diff) {
  if (diff.snapshot_mujoco_version == MujocoVersion()) return "";
  bool trajectory = std::any_of(diff.changes.begin(), diff.changes.end(),
                                [](const SnapshotChange& c) { return c.kind == "trajectory"; });
  if (diff.changed()) {
    return fmt::format(
        "upgrade {} -> {}: behaviour changed ({}); see the changes above\n",
        diff.snapshot_mujoco_version, MujocoVersion(),
        trajectory ? "the golden trajectory departs" : "structure or parameters differ");
  }
  return fmt::format(
      "upgrade {} -> {}: same structure and parameters, trajectory within cross-version "
      "round-off (tol {:g})\n",
      diff.snapshot_mujoco_version, MujocoVersion(), diff.tol);
}

std::string EstimatesTable(const IdentifyResult& r, DelayKind delay, std::size_t width) {
  std::string out = fmt::format("{:<{}} {:>12} {:>12} {:>11} {:>25}\n", "parameter", width,
                                "nominal", "estimate", "std error", "95 % interval");
  for (const Estimate& e : r.estimates) {
    std::string interval = std::isfinite(e.std_error)
                               ? fmt::format("[{:.5g}, {:.5g}]", e.value - 1.96 * e.std_error,
                                             e.value + 1.96 * e.std_error)
                               : std::string("-");
    std::string se = r.std_errors.kind == StdErrorKind::kWithheld ? std::string("withheld")
                                                                  : Num(e.std_error, "{:.3g}");
    out += fmt::format("{:<{}} {:>12.6g} {:>12.6g} {:>11} {:>25}{}\n", e.path, width, e.nominal,
                       e.value, se, interval, e.at_bound ? "  (on its bound)" : "");
  }
  if (delay != DelayKind::kNone) {
    out += fmt::format(
        "{:<{}} {:>12} {:>12.6g} {:>11} {:>25}\n",
        delay == DelayKind::kInput ? "input delay [s]" : "sensor delay [s]", width, "0", r.delay,
        "-",
        fmt::format("(resolution {:g} s)", r.delay_scan.size() > 1 ? r.delay_scan[1].first : 0.0));
  }
  if (r.estimates.size() > 1) {
    out += "\ncorrelation\n";
    for (std::size_t i = 0; i < r.estimates.size(); ++i) {
      out += fmt::format("  {:<{}}", r.estimates[i].path, width);
      for (std::size_t j = 0; j <= i; ++j) out += fmt::format(" {:>7.3f}", r.correlation[i][j]);
      out += "\n";
    }
  }
  return out;
}

// What the fit changed, parameter by parameter.
std::string Changes(const IdentifyResult& r) {
  std::string out;
  for (const Estimate& e : r.estimates) {
    if (e.value == e.nominal) continue;
    out += fmt::format("  {}: {:.6g} -> {:.6g}", e.path, e.nominal, e.value);
    if (e.nominal != 0) out += fmt::format(" ({:+.1f} %)", 100 * (e.value / e.nominal - 1));
    out += "\n";
  }
  return out.empty() ? "  (nothing)\n" : out;
}

}  // namespace

std::string ConvergeTable(const ConvergenceResult& r) {
  std::string out = fmt::format("metric {} on {}, over {:g} s\n\n", r.metric, r.model, r.until);
  out += fmt::format("{:>12} {:>22} {:>12} {:>8} {:>12}\n", "dt [s]", "value", "diff", "order",
                     "est. error");
  for (const ConvergenceLevel& l : r.levels) {
    out += fmt::format("{:>12g} {:>22} {:>12} {:>8} {:>12}{}{}\n", l.dt, Num(l.value, "{:.15g}"),
                       Num(l.diff, "{:.3e}"), Num(l.order, "{:.2f}"), Num(l.error, "{:.3e}"),
                       l.roundoff ? "  (diff is round-off)" : "",
                       l.error_is_richardson ? "  (Richardson estimate: no finer level)" : "");
  }
  return out + "\n" + ConvergeVerdict(r);
}

std::string DiffTable(const SnapshotDiff& diff, const std::string& snapshot,
                      const std::string& set_prefix) {
  std::string out;
  if (!diff.sets.empty()) {
    std::vector<std::string> sets;
    for (const std::string& t : diff.sets) sets.push_back(set_prefix + Quoted(t));
    out += "note: the model is simulated with the snapshot's " +
           Join(sets, set_prefix.empty() ? ", " : " ") + "\n";
  }
  for (const std::string& n : diff.notes) out += "note: " + n + "\n";
  if (!diff.compiler.empty()) {
    out += fmt::format(
        "note: {} value(s) that MuJoCo's compiler derives from mesh files (fitted geom size, "
        "frame, bounds) came out differently under {} than under {}; the model did not "
        "change them (the JSON lists them all):\n",
        diff.compiler.size(), MujocoVersion(), diff.snapshot_mujoco_version);
    for (std::size_t i = 0; i < diff.compiler.size() && i < 3; ++i) {
      out += "  " + diff.compiler[i].what + "\n";
    }
    if (diff.compiler.size() > 3) {
      out += fmt::format("  ... and {} more\n", diff.compiler.size() - 3);
    }
  }
  for (const SnapshotChange& c : diff.changes) out += c.what + "\n";
  out += diff.changed()
             ? fmt::format("{} change(s) beyond tol {:g}\n", diff.changes.size(), diff.tol)
             : fmt::format("identical to {} within tol {:g}\n", snapshot, diff.tol);
  return out + UpgradeLine(diff);
}

std::string FitTable(const std::vector<SignalFit>& fits) {
  std::size_t width = 16;
  for (const SignalFit& f : fits) width = std::max(width, f.column.size());
  std::string out =
      fmt::format("{:<{}} {:>8} {:>12} {:>12} {:>10} {:>8} {:>12}\n", "signal", width, "samples",
                  "rms error", "max error", "at t [s]", "fit %", "> noise %");
  for (const SignalFit& f : fits) {
    out += fmt::format("{:<{}} {:>8} {:>12.4g} {:>12.4g} {:>10.4f} {:>8.2f} {:>12.2f}\n",
                       f.column, width, f.samples, f.rms, f.max_abs, f.worst_time, f.fit,
                       f.fit_beyond_noise);
  }
  return out;
}

std::string ReplayTable(const std::string& model, const RobotLog& log, const ReplayOptions& options,
                        const ReplayResult& r) {
  std::string inputs;
  for (const LogSignal& s : log.inputs) inputs += (inputs.empty() ? "" : ", ") + s.column;
  std::string out =
      fmt::format("replay of {} on {}: {:g} s from t = {:g} s; inputs: {}\n", log.source, model,
                  log.end - log.start, log.start, inputs.empty() ? "none" : inputs);
  if (options.window > 0) {
    out += fmt::format("restarted from the logged state every {:g} s\n", options.window);
  }
  if (options.input_delay != 0 || options.sensor_delay != 0) {
    out += fmt::format("input delay {:g} s, sensor delay {:g} s\n", options.input_delay,
                       options.sensor_delay);
  }
  out += "\n" + FitTable(r.signals) + "\n";
  out += fmt::format(
      "overall fit {:.2f} % (the signals pooled in units of their noise, the error beyond it; "
      "100: the log up to its noise, 0: no better than each signal's mean)\n",
      r.fit);
  for (const std::string& note : r.notes) out += "note: " + note + "\n";
  if (r.simulated.diverged) out += r.simulated.problem + "\n";
  return out;
}

std::string IdentifyTable(const std::string& model, const IdentifyResult& r,
                          const std::vector<RobotLog>& logs, DelayKind delay,
                          const HeldOutLog* validation) {
  long samples = 0;
  for (const RobotLog& log : logs) {
    for (const LogSignal& s : log.measured) samples += static_cast<long>(s.value.size());
  }
  std::string out = fmt::format("identify on {} from {} log(s), {} measured samples\n\n", model,
                                logs.size(), samples);
  std::size_t width = 10;
  for (const Estimate& e : r.estimates) width = std::max(width, e.path.size());
  out += EstimatesTable(r, delay, width);
  out += fmt::format("\nsolver: {}\n{}\n", DescribeSolves(r), DescribeResidualVariance(r));
  if (r.misspecification.detected) out += "WARN misspecified: " + r.misspecification.reason + "\n";
  out += "standard errors: " + r.std_errors.why + "\n";
  out += "\nnoise per signal (rms of the residuals):\n";
  for (std::size_t l = 0; l < logs.size(); ++l) {
    for (std::size_t i = 0; i < logs[l].measured.size(); ++i) {
      out += fmt::format("  {}  {}: {:.4g}\n", logs[l].source, logs[l].measured[i].column,
                         r.noise[l][i]);
    }
  }
  out += "\nfit per log (%): nominal -> fitted\n";
  for (std::size_t l = 0; l < logs.size(); ++l) {
    out += fmt::format("  {}: {:.2f} -> {:.2f}\n", logs[l].source, r.before[l].fit, r.after[l].fit);
  }
  if (validation != nullptr) {
    out +=
        fmt::format("validation on {} (not used for the fit): nominal {:.2f} %, fitted {:.2f} %\n",
                    validation->log->source, validation->nominal.fit, validation->fitted.fit);
  }
  out += "\nchanged:\n" + Changes(r);
  for (const std::string& w : r.warnings) out += "warning: " + w + "\n";
  return out;
}

namespace {

// plumb inspect's table (DescriptionTable), a section at a time.

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

}  // namespace

std::string DescriptionTable(const ModelDescription& d, const std::string& mujoco) {
  Printer line;
  line(fmt::format("model {} ({}), MuJoCo {}", d.file, d.model_name, mujoco));
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

}  // namespace plumb
