// Audit layer 3, actuators: force bounds, a servo's targets against its joint's range,
// whether each actuator can hold its limb against gravity, and a step response.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include "audit/audit_layers.h"
#include "core/joint_size.h"
#include "core/mujoco_compat.h"
#include "plumb/describe.h"
#include "plumb/timing.h"

namespace plumb::audit {
namespace {

constexpr const char* L = "actuator";

// Where actuator u's first control sits in ctrl and the nu-row arrays (ctrlrange), and its
// first force output in the nout-row arrays (gear, length, force): MuJoCo 3.12+ actuators may
// take several controls (a pid takes two), so these are not u.
int Ctrl(const mjModel* m, int u) { return static_cast<int>(compat::ActuatorControls(m, u).first); }
int Out(const mjModel* m, int u) { return static_cast<int>(compat::ActuatorOutputs(m, u).first); }
bool CtrlLimited(const mjModel* m, int u) {
  return compat::ActuatorControls(m, u).second > 0 && m->actuator_ctrllimited[Ctrl(m, u)];
}
const mjtNum* CtrlRange(const mjModel* m, int u) { return m->actuator_ctrlrange + 2 * Ctrl(m, u); }
double Gear(const mjModel* m, int u) { return m->actuator_gear[6 * Out(m, u)]; }

// The gear as a row prints it: one number for a joint or tendon, the wrench for a site.
std::string GearText(const mjModel* m, int u) {
  const mjtNum* g = m->actuator_gear + 6 * Out(m, u);
  if (g[1] == 0 && g[2] == 0 && g[3] == 0 && g[4] == 0 && g[5] == 0)
    return fmt::format("{:g}", g[0]);
  return fmt::format("({:g} {:g} {:g} {:g} {:g} {:g})", g[0], g[1], g[2], g[3], g[4], g[5]);
}

// The bound MuJoCo puts on the total actuator force at actuator u's joint (actuatorfrcrange),
// as a bound on u's own force (divided by its gear); nullopt when there is none.
std::optional<std::pair<double, double>> TransmissionBound(const mjModel* m, int u) {
  int trn = m->actuator_trntype[u];
  double gear = Gear(m, u);
  if ((trn != mjTRN_JOINT && trn != mjTRN_JOINTINPARENT) || gear == 0) return std::nullopt;
  auto range = compat::JointActuatorForceRange(m, m->actuator_trnid[2 * u]);
  if (!range) return std::nullopt;
  double a = range->first / gear, b = range->second / gear;
  return std::make_pair(std::min(a, b), std::max(a, b));
}

// The force interval [lo, hi] actuator u can produce; infinite where nothing bounds it.
std::pair<double, double> ForceRange(const mjModel* m, int u) {
  double lo = -INFINITY, hi = INFINITY;
  if (m->actuator_forcelimited[u]) {
    lo = m->actuator_forcerange[2 * u];
    hi = m->actuator_forcerange[2 * u + 1];
  }
  if (auto bound = TransmissionBound(m, u)) {
    lo = std::max(lo, bound->first);
    hi = std::min(hi, bound->second);
  }
  const mjtNum* gain = m->actuator_gainprm + mjNGAIN * u;
  if (m->actuator_gaintype[u] == mjGAIN_MUSCLE) {
    // a muscle only pulls, at most its peak force F0 (gainprm[2], which mj_setConst
    // derives from scale) times the larger of the force-velocity and passive factors;
    // its control is implicitly 0..1
    double f0 = std::fabs(gain[2]);
    if (f0 > 0) {
      lo = std::max(lo, -f0 * (gain[8] + gain[7]));
      hi = std::min(hi, 0.0);
    }
  } else if (CtrlLimited(m, u) && m->actuator_gaintype[u] == mjGAIN_FIXED &&
             m->actuator_biastype[u] == mjBIAS_NONE && m->actuator_dyntype[u] == mjDYN_NONE) {
    // a fixed-gain, bias-free actuator: force = gain * ctrl
    double a = gain[0] * CtrlRange(m, u)[0], b = gain[0] * CtrlRange(m, u)[1];
    lo = std::max(lo, std::min(a, b));
    hi = std::min(hi, std::max(a, b));
  }
  return {lo, hi};
}

// What kind of response a ctrl step gives.
enum class ActuatorKind { kPositionServo, kVelocityServo, kMotor, kOther };

ActuatorKind KindOf(const mjModel* m, int u) {
  // a pid's first control is its position setpoint
  if (m->actuator_gaintype[u] == compat::kGainPid) return ActuatorKind::kPositionServo;
  const mjtNum* bias = m->actuator_biasprm + mjNBIAS * u;
  bool fixed = m->actuator_gaintype[u] == mjGAIN_FIXED;
  if (fixed && m->actuator_biastype[u] == mjBIAS_AFFINE && bias[1] != 0) {
    return ActuatorKind::kPositionServo;
  }
  if (fixed && m->actuator_biastype[u] == mjBIAS_AFFINE && bias[2] != 0) {
    return ActuatorKind::kVelocityServo;
  }
  if (fixed && m->actuator_biastype[u] == mjBIAS_NONE && m->actuator_dyntype[u] == mjDYN_NONE) {
    return ActuatorKind::kMotor;
  }
  return ActuatorKind::kOther;
}

struct StepResponse {
  Observed run;
  std::string measured;  // in words
  double rise = NAN;     // rise time to 63% in s; NaN for a motor or when never reached
  double overshoot = NAN, settle = NAN, error = NAN;  // a servo's (shares of the step; s)
  bool moved = false;
};

// The ctrl a servo needs to hold its actuator at `value` (a position servo's length, a
// velocity servo's velocity): force = gain * ctrl + b0 + b1 * length + b2 * velocity = 0.
double HoldingCtrl(const mjModel* m, int u, ActuatorKind kind, double value) {
  if (m->actuator_gaintype[u] == compat::kGainPid) return value;  // its setpoint
  const mjtNum* bias = m->actuator_biasprm + mjNBIAS * u;
  double gain = m->actuator_gainprm[mjNGAIN * u];
  if (gain == 0) return 0;
  double b = kind == ActuatorKind::kPositionServo ? bias[1] : bias[2];
  double b0 = kind == ActuatorKind::kPositionServo ? bias[0] : 0;
  return -(b0 + b * value) / gain;
}

// The inverse: where a servo's ctrl holds its actuator.
double ServoTarget(const mjModel* m, int u, ActuatorKind kind, double ctrl) {
  if (m->actuator_gaintype[u] == compat::kGainPid) return ctrl;
  const mjtNum* bias = m->actuator_biasprm + mjNBIAS * u;
  double gain = m->actuator_gainprm[mjNGAIN * u];
  double b = kind == ActuatorKind::kPositionServo ? bias[1] : bias[2];
  double b0 = kind == ActuatorKind::kPositionServo ? bias[0] : 0;
  return b == 0 ? NAN : -(gain * ctrl + b0) / b;
}

// The ctrl step: from `before` to `after` (ctrl units), what it is measured in, and for a
// servo where it should end (`goal`, in the measured quantity's units).
struct CtrlStep {
  ActuatorKind kind = ActuatorKind::kOther;
  double before = 0, after = 0;
  double goal = NAN;
  double length0 = 0;        // the actuator length before the step
  int ctrl = 0, out = 0;     // its control and force output (Ctrl, Out)
  std::vector<int> held;     // joints held at the reference pose (qpos, qvel reset every step)
  std::vector<mjtNum> qpos;  // the reference pose
  double Quantity(const mjData* d) const {
    switch (kind) {
      case ActuatorKind::kPositionServo:
        return d->actuator_length[out];
      case ActuatorKind::kVelocityServo:
        return d->actuator_velocity[out];
      default:
        return d->actuator_force[out];
    }
  }
  // Puts the held joints back at the reference pose, at rest.
  void Hold(const mjModel* m, mjData* d) const {
    for (int j : held) {
      int q = m->jnt_qposadr[j], v = m->jnt_dofadr[j];
      for (int k = 0; k < JointQposSize(m->jnt_type[j]); ++k) d->qpos[q + k] = qpos[q + k];
      for (int k = 0; k < JointDofSize(m->jnt_type[j]); ++k) d->qvel[v + k] = 0;
    }
  }
};

double Clamp(const mjModel* m, int i, double ctrl) {
  if (!m->actuator_ctrllimited[i]) return ctrl;
  return std::clamp(ctrl, m->actuator_ctrlrange[2 * i], m->actuator_ctrlrange[2 * i + 1]);
}

// Resets `data` to the reference pose with every other servo holding it (position servos at
// their length there, velocity servos at rest, other ctrls at the middle of their range),
// and, when u is a servo, every joint that no position servo and not u moves held there
// kinematically (its qpos and qvel put back before every step), and
// chooses the step of actuator u: 10% of its range (0.1 when unlimited), servos from where
// they are.
CtrlStep PrepareStep(Model& work, Data& data, const std::vector<Assignment>& sets,
                     const ReferencePose& ref, int u) {
  const mjModel* m = work.get();
  mj_resetData(m, data.get());
  StartAtPose(work, data, ref, sets);
  CtrlStep step;
  step.kind = KindOf(m, u);
  step.ctrl = Ctrl(m, u);
  step.out = Out(m, u);
  bool limited = CtrlLimited(m, u) || m->actuator_gaintype[u] == mjGAIN_MUSCLE;
  double lo = CtrlLimited(m, u) ? CtrlRange(m, u)[0] : 0;
  double hi = CtrlLimited(m, u)                          ? CtrlRange(m, u)[1]
              : m->actuator_gaintype[u] == mjGAIN_MUSCLE ? 1
                                                         : 0;
  for (int i = 0; i < m->nu; ++i) {
    data->ctrl[i] = m->actuator_ctrllimited[i]
                        ? 0.5 * (m->actuator_ctrlrange[2 * i] + m->actuator_ctrlrange[2 * i + 1])
                        : 0;
  }
  data.Forward();
  std::vector<bool> moved(m->nv, false);
  for (int i = 0; i < compat::ActuatorCount(m); ++i) {
    ActuatorKind kind = KindOf(m, i);
    if (kind == ActuatorKind::kPositionServo || kind == ActuatorKind::kVelocityServo) {
      double value = kind == ActuatorKind::kPositionServo ? data->actuator_length[Out(m, i)] : 0;
      data->ctrl[Ctrl(m, i)] = Clamp(m, Ctrl(m, i), HoldingCtrl(m, i, kind, value));
    }
    if (kind != ActuatorKind::kPositionServo && i != u) continue;
    std::vector<mjtNum> row = compat::ActuatorMomentRow(m, data.get(), Out(m, i));
    for (int v = 0; v < m->nv; ++v) moved[v] = moved[v] || row[v] != 0;
  }
  // a servo's step is judged on its own joint: the rest hold still. A motor's is not (with
  // nothing holding it, a constant torque on a held base spins its limb ever faster)
  bool servo =
      step.kind == ActuatorKind::kPositionServo || step.kind == ActuatorKind::kVelocityServo;
  for (int j = 0; j < m->njnt && servo; ++j) {
    int dofs = m->jnt_type[j] == mjJNT_FREE ? 6 : m->jnt_type[j] == mjJNT_BALL ? 3 : 1;
    bool any = false;
    for (int k = 0; k < dofs; ++k) any = any || moved[m->jnt_dofadr[j] + k];
    if (!any) step.held.push_back(j);
  }
  step.qpos.assign(data->qpos, data->qpos + m->nq);
  data.Forward();
  double size = limited ? 0.1 * (hi - lo) : 0.1;
  step.length0 = data->actuator_length[step.out];
  step.before = data->ctrl[step.ctrl];
  if (step.kind == ActuatorKind::kPositionServo) {
    step.before = HoldingCtrl(m, u, step.kind, step.length0);  // hold where it is
  }
  if (step.kind == ActuatorKind::kVelocityServo) step.before = HoldingCtrl(m, u, step.kind, 0);
  step.after = step.before + size;
  if (limited && step.after > hi) step.after = step.before - size;  // stay inside ctrlrange
  if (step.kind == ActuatorKind::kPositionServo || step.kind == ActuatorKind::kVelocityServo) {
    step.goal = ServoTarget(m, u, step.kind, step.after);
  }
  data->ctrl[step.ctrl] = step.before;
  data.Forward();
  return step;
}

// A motor has no setpoint: how far and how fast the step moved the actuator.
std::string DescribeMotor(const mjModel* m, int u, const CtrlStep& step, double moved,
                          double max_speed, double duration) {
  int trn = m->actuator_trntype[u];
  if (trn != mjTRN_JOINT && trn != mjTRN_JOINTINPARENT && trn != mjTRN_TENDON) {
    // a site or body transmission pushes a body: its length is no position to report
    return fmt::format(
        "no setpoint (motor on a {}): ctrl {:.3g} -> {:.3g} moves its site at up to {:.3g} "
        "along its gear {} in {:g} s",
        trn == mjTRN_SITE ? "site" : "body", step.before, step.after, max_speed, GearText(m, u),
        duration);
  }
  // the actuator length is gear x the joint (tendon) position
  double gear = Gear(m, u);
  std::string unit = ActuatorPositionUnit(m, u);
  std::string by = gear == 1 ? fmt::format("{:.3g} {}", moved, unit)
                             : fmt::format("{:.3g} (gear {:g} x {:.3g} {} at the joint)", moved,
                                           gear, moved / gear, unit);
  return fmt::format(
      "no setpoint (motor): ctrl {:.3g} -> {:.3g} moves the actuator length by {} in {:g} s "
      "(peak speed {:.3g} {}/s{})",
      step.before, step.after, by, duration, max_speed / std::fabs(gear), unit,
      gear == 1 ? "" : " at the joint");
}

// Servos reach for their setpoint: rise time to 63%, overshoot, steady-state error. Other
// actuators' force settles where it settles: how fast it follows. "" when nothing changed.
// `*rise_time` is the rise time in s (NaN when the step never reached 63%).
std::string DescribeResponse(const mjModel* m, int u, const CtrlStep& step,
                             const std::vector<double>& t, const std::vector<double>& y, double y0,
                             double duration, StepResponse* r) {
  bool servo = !std::isnan(step.goal);
  double goal = servo ? step.goal : y.back();
  double change = goal - y0;
  if (std::fabs(change) < 1e-12) return "";
  double rise = NAN, peak = 0, settle = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    double share = (y[i] - y0) / change;
    if (std::isnan(rise) && share >= 0.63) rise = t[i] - t.front() + m->opt.timestep;
    peak = std::max(peak, share);
    // settled: within 5% of the step from here on
    if (std::fabs(share - 1) > 0.05) settle = t[i] - t.front() + m->opt.timestep;
  }
  r->rise = rise;
  if (servo) {
    r->overshoot = std::max(0.0, peak - 1);
    r->error = std::fabs(goal - y.back()) / std::fabs(change);
    r->settle = settle;
  }
  std::string rise_text =
      std::isfinite(rise) ? fmt::format("{:.3g} s", rise) : fmt::format("> {:g} s", duration);
  if (servo) {
    std::string settle_text = settle >= duration - m->opt.timestep / 2
                                  ? fmt::format("not within 5% by {:g} s", duration)
                                  : fmt::format("settles (5%) in {:.3g} s", settle);
    return fmt::format("{} servo: rise {}, overshoot {:.1f}%, {}, steady-state error {:.1f}%",
                       step.kind == ActuatorKind::kPositionServo ? "position" : "velocity",
                       rise_text, 100 * r->overshoot, settle_text, 100 * r->error);
  }
  return fmt::format("no setpoint ({}): force {:.3g} -> {:.3g}, rise {}",
                     m->actuator_gaintype[u] == mjGAIN_MUSCLE ? "muscle" : "actuator", y0, y.back(),
                     rise_text);
}

// A step of ctrl by 10% of its range (0.1 when unlimited) from the reference pose,
// gravity and contacts off so only the actuator acts, every other ctrl at its middle.
// `work` is a copy of the model with gravity and contacts off, `data` its data (reused
// from one actuator to the next: a big model's mjData costs more to make than to step).
StepResponse MeasureStep(Model& work, Data& data, const std::vector<Assignment>& sets,
                         const ReferencePose& ref, int u, double duration,
                         const AuditOptions& options, const std::string& element) {
  StepResponse out;
  const mjModel* m = work.get();
  CtrlStep step = PrepareStep(work, data, sets, ref, u);
  double y0 = step.Quantity(data.get());
  std::vector<double> t, y;
  double max_speed = 0;
  RunSpec spec;
  spec.stop = options.stop;
  spec.until = duration;
  spec.every = m->opt.timestep;
  spec.before_step = [&](mjData* d, long) {
    d->ctrl[step.ctrl] = step.after;
    step.Hold(m, d);
  };
  spec.after_step = [&](const mjData* d, long) {
    t.push_back(d->time);
    y.push_back(step.Quantity(d));
    max_speed = std::max(max_speed, std::fabs(d->actuator_velocity[step.out]));
  };
  NullSink sink;
  out.run.label = "step response of " + element;
  out.run.duration = duration;
  out.run.result = Run(work, data, spec, sink);
  TakeMujocoWarnings();  // counted in the run's result, reported in the warnings layer
  out.run.repro = KeepDiverged(work, out.run.result, options, out.run.label);
  const char* quantity = step.kind == ActuatorKind::kPositionServo   ? "actuator length"
                         : step.kind == ActuatorKind::kVelocityServo ? "actuator velocity"
                                                                     : "actuator force";
  AuditCurve curve;
  curve.label = out.run.label;
  curve.quantity = quantity;
  curve.t = t;
  curve.y = y;
  curve.start = y0;
  bool servo =
      step.kind == ActuatorKind::kPositionServo || step.kind == ActuatorKind::kVelocityServo;
  curve.target = servo ? step.goal : NAN;
  out.run.curves.push_back(std::move(curve));
  if (out.run.result.diverged || y.size() < 2) return out;
  if (step.kind == ActuatorKind::kMotor) {
    double moved = data->actuator_length[step.out] - step.length0;
    out.moved = std::fabs(moved) > 1e-9 || max_speed > 1e-9;
    out.measured = DescribeMotor(m, u, step, moved, max_speed, duration);
    return out;
  }
  out.measured = DescribeResponse(m, u, step, t, y, y0, duration, &out);
  out.moved = !out.measured.empty();
  return out;
}

// At most this many actuators get a step response (evenly spaced when there are more).
constexpr int kStepActuators = 12;

// An actuator nothing bounds: a real motor saturates.
void Limits(const mjModel* m, int u, const CheckElement& element, std::vector<CheckRow>* out) {
  auto [flo, fhi] = ForceRange(m, u);
  if (std::isfinite(flo) && std::isfinite(fhi)) return;
  CheckRow& row = out->emplace_back(
      Make(L, "actuator.limits", element,
           fmt::format("ctrl {}, force {}, gear {}", CtrlLimited(m, u) ? "limited" : "unlimited",
                       m->actuator_forcelimited[u] ? "limited" : "unlimited", GearText(m, u)),
           "a force bound", CheckStatus::kWarn,
           "a real motor saturates: set ctrllimited/ctrlrange (and forcerange) "
           "from the motor's datasheet, torque = gear x force"));
  // the same finding: the same of ctrl and force bounded (the gears may differ)
  row.finding = fmt::format("ctrl {}, force {}", CtrlLimited(m, u) ? "limited" : "unlimited",
                            m->actuator_forcelimited[u] ? "limited" : "unlimited");
}

// A position servo's targets (ctrl / gear, in joint units) should lie within reach.
void TargetRange(const mjModel* m, int u, const CheckElement& element, std::vector<CheckRow>* out) {
  int trn = m->actuator_trntype[u];
  int joint = m->actuator_trnid[2 * u];
  double gear = Gear(m, u);
  bool joint_trn = trn == mjTRN_JOINT || trn == mjTRN_JOINTINPARENT;
  if (KindOf(m, u) != ActuatorKind::kPositionServo || !joint_trn || !m->jnt_limited[joint] ||
      !CtrlLimited(m, u) || gear == 0) {
    return;
  }
  double lo = CtrlRange(m, u)[0] / gear, hi = CtrlRange(m, u)[1] / gear;
  double jlo = m->jnt_range[2 * joint], jhi = m->jnt_range[2 * joint + 1];
  double margin = 0.5 * (jhi - jlo);
  if (std::min(lo, hi) >= jlo - margin && std::max(lo, hi) <= jhi + margin) return;
  out->push_back(Make(
      L, "actuator.target_range", element,
      fmt::format("targets [{:.4g}, {:.4g}] vs joint range [{:.4g}, {:.4g}]", lo, hi, jlo, jhi),
      "within the joint range", CheckStatus::kWarn,
      "the servo asks for positions its joint can never reach: make "
      "ctrlrange match the joint range (and check the compiler's angle "
      "units)"));
}

// Whether actuator u on a hinge or slide can hold its limb against gravity at the reference
// pose: the actuator adds gear * force to its dof, enough when the needed generalized force
// (qfrc_bias at qvel = 0) lies within gear * [flo, fhi], sign included. False when the row
// does not apply or is not listed.
bool Holding(const Model& model, const Data& data, int u, const CheckElement& element, bool listed,
             std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  int trn = m->actuator_trntype[u];
  int joint = m->actuator_trnid[2 * u];
  bool joint_trn = trn == mjTRN_JOINT || trn == mjTRN_JOINTINPARENT;
  if (!joint_trn || (m->jnt_type[joint] != mjJNT_HINGE && m->jnt_type[joint] != mjJNT_SLIDE)) {
    return false;
  }
  double gear = Gear(m, u);
  auto [flo, fhi] = ForceRange(m, u);
  double need = data->qfrc_bias[m->jnt_dofadr[joint]];
  double tlo = std::min(gear * flo, gear * fhi), thi = std::max(gear * flo, gear * fhi);
  if (gear == 0) tlo = thi = 0;
  double bound = need >= 0 ? thi : tlo;
  if (!std::isfinite(bound)) return false;
  if (!listed) return true;
  bool weak = need > thi || need < tlo;
  // as numbers: what it delivers on the side gravity needs, against that need
  const char* unit = m->jnt_type[joint] == mjJNT_HINGE ? "N*m" : "N";
  out->push_back(
      WithNumbers(Make(L, "actuator.holding", element,
                       fmt::format("delivers {:.4g} .. {:.4g}, gravity needs {:.4g} at {}", tlo,
                                   thi, need, Elem(model, mjOBJ_JOINT, joint, "joint")),
                       fmt::format("{} {:.4g}", need >= 0 ? ">=" : "<=", need),
                       weak ? CheckStatus::kWarn : CheckStatus::kPass,
                       weak ? "it cannot hold its limb against gravity at the reference pose (in "
                              "this direction): raise the gear or the force/ctrl range on that "
                              "side, or lighten the limb"
                            : "gear x force range covers the gravity torque at the reference "
                              "pose"),
                  {bound, unit}, {need, unit}));
  return true;
}

// A servo's step response against its thresholds: overshoot beyond kOvershootFail swings past
// the target by more than the step (an oscillating or unstable servo: one arm rang at 3,300%);
// beyond kOvershootWarn, or a steady-state error beyond kErrorWarn (it misses most of the
// step), is suspect. The settling time is shown, not judged: a slow servo is a choice. Clean
// robots: overshoot 0%, errors up to 32% (the Robotiq 2F-85's spring-loaded linkage); a
// position servo with kp and joint damping only (examples/model_ci's arm) overshoots 33%.
constexpr double kOvershootWarn = 0.5, kOvershootFail = 1, kErrorWarn = 0.5;

CheckRow ServoStepRow(const CheckElement& element, const StepResponse& r) {
  CheckStatus status = r.overshoot > kOvershootFail                           ? CheckStatus::kFail
                       : r.overshoot > kOvershootWarn || r.error > kErrorWarn ? CheckStatus::kWarn
                                                                              : CheckStatus::kPass;
  bool rings = r.overshoot > kOvershootWarn;
  std::string fix =
      status == CheckStatus::kPass
          ? "a step of 10% of ctrlrange from the reference pose, gravity and contacts off, the "
            "other servos holding the pose and the other joints held there"
      : rings ? "the servo overshoots: its gains are too stiff or too little damped for the "
                "link it moves (see actuator.stability): raise kv or dampratio, add armature, "
                "or lower kp"
              : "the servo stops far from its target: a load (a spring, a coupled joint, a "
                "limit) stronger than kp, or a forcerange that saturates";
  // as numbers: the overshoot (a share of the step) against its bound
  return WithNumbers(Make(L, "actuator.step_response", element, r.measured,
                          fmt::format("overshoot <= {:g}%, steady-state error <= {:g}%",
                                      100 * kOvershootWarn, 100 * kErrorWarn),
                          status, fix),
                     {r.overshoot, ""}, {kOvershootWarn, ""});
}

// Step responses of up to kStepActuators actuators, within one dof-step budget for all.
void StepResponses(const Model& original, const Model& model, const std::vector<Assignment>& sets,
                   const ReferencePose& ref, const AuditOptions& options,
                   std::vector<Observed>* runs, std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  int count = std::min(compat::ActuatorCount(m), kStepActuators);
  double duration = Duration(m, 1.0, kDofStepBudget / count);
  Model work = original.Clone();
  work.get_mutable()->opt.disableflags |= mjDSBL_GRAVITY | mjDSBL_CONTACT;
  Data step_data(work);
  for (int i = 0; i < count; ++i) {
    int u = static_cast<int>(static_cast<long>(i) * compat::ActuatorCount(m) / count);
    CheckElement element = ElementOf(model, mjOBJ_ACTUATOR, u, "actuator");
    if (compat::ActuatorPlugin(m, u) >= 0) continue;  // actuator.plugin says why
    StepResponse r =
        MeasureStep(work, step_data, sets, ref, u, duration, options, ElementLabel(element));
    runs->push_back(r.run);
    if (r.run.result.diverged) {
      out->push_back(Make(L, "actuator.step_response", element, "diverged", "stays finite",
                          CheckStatus::kFail, DivergedFix(r.run)));
    } else if (!r.moved) {
      out->push_back(Make(L, "actuator.step_response", element, "no response", "",
                          CheckStatus::kWarn,
                          fmt::format("a step in ctrl moved nothing in {:g} s (gravity and "
                                      "contacts off): check the transmission, gain and ctrl "
                                      "range",
                                      duration)));
    } else if (!std::isnan(r.overshoot)) {
      out->push_back(ServoStepRow(element, r));
    } else {
      // as a number: the rise time (none for a motor, which has no setpoint)
      out->push_back(
          WithNumbers(Make(L, "actuator.step_response", element, r.measured, "", CheckStatus::kPass,
                           "a step of 10% of ctrlrange from the reference pose, gravity and "
                           "contacts off"),
                      {r.rise, std::isnan(r.rise) ? "" : "s"}));
    }
  }
  ListedNote(L, "actuator.step_response", "actuators", compat::ActuatorCount(m), out, count);
}

}  // namespace

void ActuatorLayer(const Model& original, const Model& model, Data& data,
                   const std::vector<Assignment>& sets, const ReferencePose& ref,
                   const AuditOptions& options, std::vector<Observed>* runs,
                   std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  if (compat::ActuatorCount(m) == 0) {
    out->push_back(Make(L, "actuator.none", "", "no actuators", "", CheckStatus::kSkip,
                        "a passive model: nothing to check in this layer"));
    return;
  }
  // the generalized force each joint needs to hold the reference pose (qvel = 0)
  mju_zero(data->qvel, m->nv);
  data.Forward();
  int holding_rows = 0;
  for (int u = 0; u < compat::ActuatorCount(m); ++u) {
    CheckElement element = ElementOf(model, mjOBJ_ACTUATOR, u, "actuator");
    if (compat::ActuatorPlugin(m, u) >= 0) {
      out->push_back(Make(L, "actuator.plugin", element, "force from a plugin", "",
                          CheckStatus::kSkip,
                          "a plugin computes this actuator's force (a mujoco.pid controller, "
                          "...): its bounds, holding and step response are the plugin's, which "
                          "audit does not model"));
      continue;
    }
    Limits(m, u, element, out);
    TargetRange(m, u, element, out);
    if (Holding(model, data, u, element, holding_rows < kMaxListed, out)) ++holding_rows;
  }
  ListedNote(L, "actuator.holding", "holding rows", holding_rows, out);
  DelayRows(model, "actuator", L, "actuator.delay", out);
  ServoStability(model, data, out);
  ActuatorRank(model, data, out);
  MirrorActuators(model, data, out);
  StepResponses(original, model, sets, ref, options, runs, out);
}

}  // namespace plumb::audit
