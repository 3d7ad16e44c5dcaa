// Audit layer 3, actuators: the time scales the timestep must resolve. Every servo (position,
// velocity, general with an affine bias, the native pid, the mujoco.pid plugin) and every joint
// and tendon spring is, along its direction, a linear element I x'' + c x' + k x = 0 at the
// inertia it moves (audit_servo.cc reads it). Its period 2 pi sqrt(I / k) and damping time
// I / c are what the timestep must resolve; the verdict is how far the integrator's unit step
// response departs from the exact one (linear_step.h), not a bare count of steps: an
// overdamped servo whose fast mode the implicit integrators collapse correctly is fine, an
// underdamped one whose period spans a few steps is not, even where it stays stable.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>

#include "audit/audit_layers.h"
#include "audit/clamped_step.h"
#include "audit/linear_step.h"
#include "audit/servo_model.h"
#include "core/mujoco_compat.h"

namespace plumb::audit {
namespace {

constexpr const char* L = "actuator";
constexpr const char* kCheck = "actuator.timescale";
// The largest step-response error, relative to the step, accepted as the model's own motion
// (docs/audit.md: a period of about 20 steps under implicitfast at critical damping).
constexpr double kErrorWarn = 0.10;

// One element the check judges.
struct Element {
  CheckElement element;
  std::string where;  // "joint 'elbow'", "tendon 'cable'", "its transmission"
  std::string what;   // "servo", "joint spring", "tendon spring"
  std::string gains;  // how its k and c read in the row: "kp 100, kv 10"
  std::string lower;  // what lowering it means: "kp/kv"
  LinearElement linear;
  double scale = 1;  // the inertia at `where` per unit of `linear.inertia` (gear^2)
  int dof = -1;      // the dof whose armature resolves it, -1 when none does alone
  // A position servo with a force clamp: the step its response is judged at and the clamps
  // (clamped_step.h); its row is the worse of the linear and the clamped judgement.
  std::optional<ClampedServo> clamped;
  std::string step_source;  // "10 % of ctrlrange", ...
};

std::string Seconds(double t) {
  if (!std::isfinite(t)) return "none";
  if (t < 1e-3) return fmt::format("{:.3g} us", t * 1e6);
  return t < 1 ? fmt::format("{:.3g} ms", t * 1e3) : fmt::format("{:.3g} s", t);
}

std::string Steps(double t, double h) {
  return std::isfinite(t) ? fmt::format(" ({:.3g} steps)", t / h) : "";
}

// What the row judges: the linear element's step response or, for a servo whose force
// saturates on its step, the clamped one when that is worse.
struct Verdict {
  double error = 0, linear_error = 0;
  bool diverges = false, clamped = false;
  bool saturates = false;  // a clamped servo whose step saturates its force, judged both ways
  CheckStatus status = CheckStatus::kPass;
};

Verdict Judge(const Element& e, double h, int integrator) {
  Verdict v;
  v.diverges = Diverges(e.linear, h, integrator);
  v.error = v.linear_error = v.diverges ? INFINITY : StepError(e.linear, h, integrator);
  v.saturates = !v.diverges && e.clamped && Saturates(*e.clamped);
  if (v.saturates) {
    double clamped = ClampedStepError(*e.clamped, h, integrator);
    if (clamped > v.error) v.error = clamped, v.clamped = true;
  }
  v.status = v.diverges             ? CheckStatus::kFail
             : v.error > kErrorWarn ? CheckStatus::kWarn
                                    : CheckStatus::kPass;
  return v;
}

std::string Percent(double error) {
  return std::isfinite(error) ? fmt::format("{:.3g} %", 100 * error) : "all";
}

// The saturation part of a clamped servo's measured text.
std::string SaturationText(const Element& e, const Verdict& v, double h) {
  const ClampedServo& c = *e.clamped;
  bool actuator = std::min(c.force_hi, -c.force_lo) <= std::min(c.joint_hi, -c.joint_lo);
  double limit = std::min({c.force_hi, -c.force_lo, c.joint_hi, -c.joint_lo});
  double damping_time = e.linear.DampingTime();  // I / (kv + d)
  return fmt::format(
      "; its force saturates at {} {:.3g} for steps beyond {:.3g}, and a step of {:.3g} ({}) "
      "is off by {} of the step ({}; the linear small-signal response {}): {}, and the "
      "damping time I/(kv+d) = {} is {:.3g} steps",
      actuator ? "forcerange +-" : "the joint's actuatorfrcrange +-", limit, limit / c.kp, c.step,
      e.step_source, Percent(v.error), v.clamped ? "the worse, judged" : "the linear one is worse",
      Percent(v.linear_error),
      actuator ? "while saturated MuJoCo integrates kv explicitly (mjd_actuator_vel in "
                 "engine_derivative.c drops the velocity derivative of a force at forcerange)"
      : c.joint_clamp_drops_kv
          ? "while saturated MuJoCo integrates kv explicitly (MuJoCo 4 drops the velocity "
            "derivative under the joint's clamp too)"
          : "MuJoCo 3 keeps kv implicit under the joint's clamp, so the velocity ramps by F/kv a "
            "step",
      Seconds(damping_time), damping_time / h);
}

std::string FixText(const Model& model, const Element& e, const Verdict& v) {
  const mjModel* m = model.get();
  double h = m->opt.timestep;
  int integrator = m->opt.integrator;
  const LinearElement& lin = e.linear;
  double inertia = v.clamped ? ClampedInertiaFor(*e.clamped, h, integrator, kErrorWarn)
                             : InertiaFor(lin, h, integrator, kErrorWarn);
  double step = v.clamped ? ClampedTimestepFor(*e.clamped, h, integrator, kErrorWarn)
                          : TimestepFor(lin, h, integrator, kErrorWarn);
  std::string heavier =
      !std::isfinite(inertia) ? ""
      : e.dof >= 0 ? fmt::format("armature >= {:.3g} on {}{}, ",
                                 m->dof_armature[e.dof] + (inertia - lin.inertia) * e.scale,
                                 e.where, e.what == "servo" ? " (the motor's reflected inertia)" : "")
                   : fmt::format("{:.3g} more inertia along {} (armature), ",
                                 (inertia - lin.inertia) * e.scale, e.where);
  auto count = [h](double t) {
    return std::isfinite(t) ? fmt::format("{:.3g} steps", t / h) : std::string("none");
  };
  return fmt::format(
      "the {} at {} {}: its motion is the integrator's, not the model's (period {}, damping "
      "time {}{}). Give it {}{}or lower {}",
      e.what, e.where,
      v.diverges ? "diverges at this timestep"
      : v.clamped ? "chatters when its force saturates"
                  : "is faster than the timestep resolves",
      count(lin.Period()), count(lin.DampingTime()),
      v.clamped ? fmt::format(", judged on a saturating step of {:.3g}", e.clamped->step) : "",
      heavier, step > 0 ? fmt::format("a timestep <= {:.3g} s, ", step) : "", e.lower);
}

CheckRow Row(const Model& model, const Element& e) {
  const mjModel* m = model.get();
  double h = m->opt.timestep;
  int integrator = m->opt.integrator;
  const LinearElement& lin = e.linear;
  double period = lin.Period(), damping_time = lin.DampingTime();
  Verdict v = Judge(e, h, integrator);
  std::string armature =
      e.dof >= 0 ? fmt::format(" (armature {:.3g})", m->dof_armature[e.dof]) : "";
  std::string name = compat::NameOf(compat::kIntegrators, integrator);
  std::string measured = fmt::format(
      "period {}{}, damping time {}{} ({}) on an effective inertia of {:.3g} at {}{}; step "
      "response off by {} of the step under {} at h = {:g} s{}",
      Seconds(period), Steps(period, h), Seconds(damping_time), Steps(damping_time, h), e.gains,
      lin.inertia * e.scale, e.where, armature, Percent(v.error), name, h,
      v.saturates ? SaturationText(e, v, h) : "");
  std::string fix = v.status == CheckStatus::kPass
                        ? "the integrator's step response of the " + e.what +
                              "'s linear model against the exact one" +
                              (v.saturates ? ", and of its clamped model on a saturating step"
                                           : "")
                        : FixText(model, e, v);
  return WithNumbers(Make(L, kCheck, e.element, measured,
                          fmt::format("step response off by <= {:g} %", 100 * kErrorWarn),
                          v.status, fix),
                     {std::isfinite(v.error) ? 100 * v.error : NAN, "%"},
                     {100 * kErrorWarn, "%"});
}

// The step a position servo's clamped model is judged at, in actuator units: kStepShare of
// what its ctrlrange asks for, at most kRangeShare of its joint's range (the step responses'
// own sizes, step_setup.cc), or kStepShare when neither is limited; 0 when none applies.
double ServoStep(const mjModel* m, int u, int joint, double kp, std::string* source) {
  constexpr double kStepShare = 0.1, kRangeShare = 0.25;
  double gain = m->actuator_gainprm[mjNGAIN * u];  // target length = gain * ctrl / kp
  double step = INFINITY;
  *source = "";
  if (ActuatorCtrlLimited(m, u) && gain != 0) {
    const mjtNum* range = ActuatorCtrlRange(m, u);
    step = kStepShare * std::fabs(range[1] - range[0]) * std::fabs(gain) / kp;
    *source = "10 % of its ctrlrange";
  }
  if (joint >= 0 && m->jnt_limited[joint]) {
    double width = kRangeShare * std::fabs(ActuatorGear(m, u)) *
                   (m->jnt_range[2 * joint + 1] - m->jnt_range[2 * joint]);
    if (width < step) step = width, *source = "25 % of its joint's range";
  }
  if (!std::isfinite(step)) step = kStepShare, *source = "0.1 of its length";
  return step > 0 ? step : 0;
}

// Servo s (kp > 0, fixed gain) of actuator u as a clamped servo when a forcerange or its
// joint's actuatorfrcrange bounds its force.
std::optional<ClampedServo> Clamped(const mjModel* m, int u, int joint, const Servo& s,
                                    std::string* source) {
  if (!(s.kp > 0)) return std::nullopt;
  ClampedServo c;
  if (m->actuator_forcelimited[u]) {
    c.force_lo = m->actuator_forcerange[2 * u];
    c.force_hi = m->actuator_forcerange[2 * u + 1];
  }
  if (joint >= 0) {
    if (auto range = compat::JointActuatorForceRange(m, joint)) {
      double gear = ActuatorGear(m, u);
      if (gear != 0) {
        double a = range->first / gear, b = range->second / gear;
        c.joint_lo = std::min(a, b), c.joint_hi = std::max(a, b);
      }
    }
  }
  if (!(c.force_lo < 0 && c.force_hi > 0 && c.joint_lo < 0 && c.joint_hi > 0)) return std::nullopt;
  if (std::isinf(std::min({c.force_hi, -c.force_lo, c.joint_hi, -c.joint_lo}))) return std::nullopt;
  c.joint_clamp_drops_kv = compat::kJointClampDropsActuatorDerivative;
  c.inertia = s.inertia, c.kp = s.kp, c.kv = s.kv, c.damping = s.damping;
  c.implicit_damping = s.ImplicitDamping();
  c.step = ServoStep(m, u, joint, s.kp, source);
  if (!(c.step > 0)) return std::nullopt;
  return c;
}

// Actuator u as a servo: kp and kv (or a mujoco.pid plugin's kp and kd) along its
// transmission; nullopt for other actuators, for those coupled to other joints (tendons,
// joint equalities: actuator.stability skips them too) and for those actuator.stability
// already finds unstable.
std::optional<Element> ServoElement(const Model& model, const mjData* d, int u) {
  const mjModel* m = model.get();
  std::optional<Servo> s;
  bool plugin = compat::ActuatorPlugin(m, u) >= 0;
  if (plugin) {
    int instance = compat::ActuatorPlugin(m, u);
    if (compat::PluginName(m, instance) != "mujoco.pid") return std::nullopt;
    auto config = [&](const char* key) {
      std::string value = compat::PluginConfig(m, instance, key);
      return value.empty() ? 0.0 : std::max(0.0, std::atof(value.c_str()));
    };
    Servo pid{config("kp"), config("kd")};
    int out = static_cast<int>(compat::ActuatorOutputs(m, u).first);
    if ((pid.kp > 0 || pid.kv > 0) &&
        AlongTransmission(m, d, compat::ActuatorMomentRow(m, d, out), &pid)) {
      s = pid;
    }
  } else {
    s = ServoGains(m, d, u);
  }
  if (!s) return std::nullopt;
  int joint = DrivenJoint(m, u);
  bool coupled = joint < 0 ? m->actuator_trntype[u] == mjTRN_TENDON : Coupled(m, joint);
  Scheme scheme = SchemeOf(m->opt.integrator);
  if (coupled || (!plugin && Margin(*s, m->opt.timestep, scheme) < 1)) return std::nullopt;
  Element e;
  e.element = ElementOf(model, mjOBJ_ACTUATOR, u, "actuator");
  e.what = "servo";
  double gear = ActuatorGear(m, u);
  if (joint >= 0) {
    e.where = Elem(model, mjOBJ_JOINT, joint, "joint");
    e.scale = gear * gear;
    e.dof = m->jnt_type[joint] == mjJNT_HINGE || m->jnt_type[joint] == mjJNT_SLIDE
                ? m->jnt_dofadr[joint]
                : -1;
  } else {
    e.where = "its transmission";
  }
  // the plugin's kd is an explicit force under every integrator; a kv in the affine bias is
  // implicit under implicit and implicitfast
  bool kv_implicit = !plugin && scheme == Scheme::kImplicit;
  e.linear = {s->inertia, s->kp, s->kv + s->damping,
              (kv_implicit ? s->kv : 0) + s->ImplicitDamping()};
  e.gains = fmt::format("{} {:.4g}, {} {:.4g}{}", plugin ? "mujoco.pid kp" : "kp", s->kp,
                        plugin ? "kd" : "kv", s->kv,
                        s->damping > 0 ? fmt::format(", joint damping {:.4g}", s->damping) : "");
  e.lower = plugin ? "the plugin's kp/kd" : "kp/kv";
  if (!plugin) e.clamped = Clamped(m, u, joint, *s, &e.step_source);
  return e;
}

// Joint j's spring (jnt_stiffness) with its dof's damping; nullopt without one, for ball and
// free joints, and for joints an equality couples to others.
std::optional<Element> JointSpring(const Model& model, const mjData* d, int j) {
  const mjModel* m = model.get();
  bool line = m->jnt_type[j] == mjJNT_HINGE || m->jnt_type[j] == mjJNT_SLIDE;
  if (!line || !(m->jnt_stiffness[j] > 0) || Coupled(m, j)) return std::nullopt;
  int dof = m->jnt_dofadr[j];
  std::vector<mjtNum> moment(m->nv, 0.0);
  moment[dof] = 1;
  Servo s;
  if (!AlongTransmission(m, d, moment, &s)) return std::nullopt;
  Element e;
  e.element = ElementOf(model, mjOBJ_JOINT, j, "joint");
  e.where = Elem(model, mjOBJ_JOINT, j, "joint");
  e.what = "joint spring";
  e.dof = dof;
  e.linear = {s.inertia, m->jnt_stiffness[j], s.damping, s.ImplicitDamping()};
  e.gains = fmt::format("stiffness {:.4g}, damping {:.4g}", m->jnt_stiffness[j], s.damping);
  e.lower = "its stiffness";
  return e;
}

// Tendon t's spring (tendon_stiffness) with the tendon's damping, which the implicit
// integrators take implicitly (Euler's eulerdamp covers dof damping only).
std::optional<Element> TendonSpring(const Model& model, const mjData* d, int t) {
  const mjModel* m = model.get();
  if (!(m->tendon_stiffness[t] > 0)) return std::nullopt;
  Servo s;
  if (!AlongTransmission(m, d, compat::TendonJacobianRow(m, d, t), &s)) return std::nullopt;
  double damping = m->tendon_damping[t];
  bool implicit = SchemeOf(m->opt.integrator) == Scheme::kImplicit;
  Element e;
  e.element = ElementOf(model, mjOBJ_TENDON, t, "tendon");
  e.where = Elem(model, mjOBJ_TENDON, t, "tendon");
  e.what = "tendon spring";
  e.linear = {s.inertia, m->tendon_stiffness[t], damping, implicit ? damping : 0};
  e.gains = fmt::format("stiffness {:.4g}, damping {:.4g}", m->tendon_stiffness[t], damping);
  e.lower = "its stiffness";
  return e;
}

}  // namespace

void ServoTimescales(const Model& model, const Data& data, std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  std::vector<Element> elements;
  for (int u = 0; u < compat::ActuatorCount(m); ++u) {
    if (auto e = ServoElement(model, data.get(), u)) elements.push_back(std::move(*e));
  }
  if (!compat::SpringsDisabled(m)) {
    for (int j = 0; j < m->njnt; ++j) {
      if (auto e = JointSpring(model, data.get(), j)) elements.push_back(std::move(*e));
    }
    for (int t = 0; t < m->ntendon; ++t) {
      if (auto e = TendonSpring(model, data.get(), t)) elements.push_back(std::move(*e));
    }
  }
  int listed = 0;
  for (const Element& e : elements) {
    CheckRow row = Row(model, e);
    if (row.status == CheckStatus::kPass && listed >= kMaxListed) continue;
    listed += row.status == CheckStatus::kPass;
    out->push_back(std::move(row));
  }
  int total = static_cast<int>(elements.size());
  ListedNote(L, kCheck, "servos and springs", total, out, std::min(total, kMaxListed));
}

}  // namespace plumb::audit
