// Audit layer 3, actuators: the step response, run and judged. Each actuator steps from the
// reference pose as step_setup.cc prepares it (a position servo within its joint's (tendon's)
// range, the joints an equality or tendon ties to its own moving with it, the others holding
// the pose); the response is described in words, and one that a limit, an equality, a load or
// a saturated force decided says so instead of blaming the gains.

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "audit/audit_layers.h"
#include "audit/step_setup.h"
#include "core/joint_size.h"
#include "core/mujoco_compat.h"
#include "plumb/describe.h"

namespace plumb::audit {
using internal::JointDofSize;

namespace {

constexpr const char* L = "actuator";

// At most this many actuators get a step response (evenly spaced when there are more).
constexpr int kStepActuators = 12;

// At most this many joints are named as moving with the driven one.
constexpr int kNamedJoints = 6;

// What decided a step response besides the servo itself.
enum class Decider { kServo, kLimit, kEquality, kLoad, kForceRange };

struct StepResponse {
  Observed run;
  std::string measured;  // in words
  double rise = NAN;     // rise time to 63% in s; NaN for a motor or when never reached
  double overshoot = NAN, settle = NAN, error = NAN;  // a servo's (shares of the step; s)
  bool moved = false;
  Decider rang_by = Decider::kServo;     // what decided the overshoot
  Decider stopped_by = Decider::kServo;  // what decided where it stopped
  std::string why_rang, why_stopped;     // the measurement that says so
  double duration = 0;
  bool within_range = false;  // a position servo's step kept within its joint's range
};

// What a servo's step met during the run: the first limit of a joint that moves with it (and
// whether it acted from the first step), and the steps its force sat at forcerange.
struct StepWatch {
  int limit_joint = -1;
  double limit_time = NAN;
  bool limit_at_start = false;
  long saturated = 0, steps = 0;

  void See(const mjModel* m, const mjData* d, int u, const CtrlStep& step) {
    ++steps;
    for (int i = 0; i < d->nefc && limit_joint < 0; ++i) {
      if (d->efc_type[i] != mjCNSTR_LIMIT_JOINT || d->efc_force[i] == 0) continue;
      if (!step.moving.joints[d->efc_id[i]]) continue;
      limit_joint = d->efc_id[i];
      limit_time = d->time;
      limit_at_start = steps == 1;
    }
    if (!m->actuator_forcelimited[u]) return;
    double f = d->actuator_force[step.out];
    double lo = m->actuator_forcerange[2 * u], hi = m->actuator_forcerange[2 * u + 1];
    double tol = 1e-9 * std::max({1.0, std::fabs(lo), std::fabs(hi)});
    if (f >= hi - tol || f <= lo + tol) ++saturated;
  }
};

// A motor has no setpoint: how far and how fast the step moved the actuator.
std::string DescribeMotor(const mjModel* m, int u, const CtrlStep& step, double moved,
                          double max_speed, double duration) {
  int trn = m->actuator_trntype[u];
  if (trn != mjTRN_JOINT && trn != mjTRN_JOINTINPARENT && trn != mjTRN_TENDON) {
    // a site or body transmission pushes a body: its length is no position to report
    return fmt::format(
        "no setpoint (motor on a {}): ctrl {:.3g} -> {:.3g} moves its site at up to {:.3g} "
        "along its gear {} in {:g} s",
        trn == mjTRN_SITE ? "site" : "body", step.before, step.after, max_speed,
        ActuatorGearText(m, u), duration);
  }
  // the actuator length is gear x the joint (tendon) position
  double gear = ActuatorGear(m, u);
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
// Fills r's rise time in s (NaN when the step never reached 63%) and a servo's shares.
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

// "joint 'x'" or "tendon 'x'", by name or number.
std::string NameOf(const Model& model, int obj, int id) {
  std::string name = model.Name(obj, id);
  return fmt::format("{} '{}'", obj == mjOBJ_TENDON ? "tendon" : "joint",
                     name.empty() ? "#" + std::to_string(id) : name);
}

// A position servo's step in its reach's units, and what moves and what is held:
// "step 0.12 rad: 0.35 -> 0.47 rad of joint 'x' [0, 1.2]; moves x, y; held: 4 other joints".
std::string DescribeStep(const Model& model, const CtrlStep& step) {
  const mjModel* m = model.get();
  std::string text;
  if (step.reach) {
    const Reach& r = *step.reach;
    text = fmt::format("step {:.3g} {}: {:.4g} -> {:.4g} {} of {}", std::fabs(step.to - step.from),
                       r.unit, step.from, step.to, r.unit, NameOf(model, r.obj, r.id));
    if (std::isfinite(r.lo) || std::isfinite(r.hi))
      text += fmt::format(" [{:.4g}, {:.4g}]", r.lo, r.hi);
    text += "; ";
  }
  std::vector<std::string> names;
  int moving = 0;
  for (int j = 0; j < m->njnt; ++j) {
    if (!step.moving.joints[j]) continue;
    if (++moving > kNamedJoints) continue;
    names.push_back(model.Name(mjOBJ_JOINT, j));
    if (names.back().empty()) names.back() = "#" + std::to_string(j);
  }
  std::string list = fmt::format("{}", fmt::join(names, ", "));
  if (moving > kNamedJoints) list += fmt::format(" and {} more", moving - kNamedJoints);
  int others = m->njnt - moving;
  return text +
         fmt::format("moves {}; held: {} other joint{}; ", list, others, others == 1 ? "" : "s");
}

// The forces along a servo's transmission at the end of its step, each as the actuator force
// that balances it (its generalized force on the moment row over the row's squared norm):
// joint and tendon limits, equality constraints, passive forces (springs, damping); the joint
// whose limit acts, and the moving joint the actuator does not drive with the largest passive
// force (a linkage's spring). `d` is put through mj_forward at its state.
struct StepLoads {
  double actuator = 0, limit = 0, equality = 0, passive = 0;
  int limit_joint = -1, spring_joint = -1;
};

StepLoads LoadsAtEnd(const mjModel* m, mjData* d, const CtrlStep& step) {
  StepLoads loads;
  mj_forward(m, d);
  std::vector<mjtNum> row = compat::ActuatorMomentRow(m, d, step.out);
  double norm = 0;
  for (int v = 0; v < m->nv; ++v) norm += row[v] * row[v];
  if (norm == 0) return loads;
  auto along = [&](const mjtNum* f) {
    double sum = 0;
    for (int v = 0; v < m->nv; ++v) sum += row[v] * f[v];
    return sum / norm;
  };
  // the generalized force of the constraint rows of one kind
  std::vector<mjtNum> masked(std::max(1, d->nefc)), force(m->nv, 0);
  auto constraint = [&](bool equality) {
    if (d->nefc == 0) return 0.0;
    for (int i = 0; i < d->nefc; ++i) {
      bool limit = d->efc_type[i] == mjCNSTR_LIMIT_JOINT || d->efc_type[i] == mjCNSTR_LIMIT_TENDON;
      bool kind = equality ? d->efc_type[i] == mjCNSTR_EQUALITY : limit;
      masked[i] = kind ? d->efc_force[i] : 0;
      bool mine = d->efc_type[i] == mjCNSTR_LIMIT_JOINT && step.moving.joints[d->efc_id[i]];
      if (!equality && mine && d->efc_force[i] != 0 && loads.limit_joint < 0) {
        loads.limit_joint = d->efc_id[i];
      }
    }
    mj_mulJacTVec(m, d, force.data(), masked.data());
    return along(force.data());
  };
  loads.actuator = d->actuator_force[step.out];
  loads.limit = constraint(false);
  loads.equality = constraint(true);
  loads.passive = along(d->qfrc_passive);
  double most = 0;
  for (int j = 0; j < m->njnt; ++j) {
    if (!step.moving.joints[j] || step.moving.driven[j] || JointDofSize(m->jnt_type[j]) != 1) {
      continue;
    }
    double f = std::fabs(d->qfrc_passive[m->jnt_dofadr[j]]);
    if (f > most) most = f, loads.spring_joint = j;
  }
  return loads;
}

// "[lo, hi]" of joint j.
std::string RangeText(const mjModel* m, int j) {
  return fmt::format("[{:.4g}, {:.4g}]", m->jnt_range[2 * j], m->jnt_range[2 * j + 1]);
}

// What decided the overshoot: a limit that acted from the first step (a start outside the
// range) or on a joint the actuator does not drive (a coupled joint's), or a force at
// forcerange; else the servo itself (a driven joint swinging into its own limit is its
// overshoot).
void JudgeOvershoot(const Model& model, int u, const CtrlStep& step, const StepWatch& watch,
                    StepResponse* r) {
  const mjModel* m = model.get();
  int j = watch.limit_joint;
  if (j >= 0 && (watch.limit_at_start || !step.moving.driven[j])) {
    r->rang_by = Decider::kLimit;
    r->why_rang =
        fmt::format("the limit of {} {} acted {}", NameOf(model, mjOBJ_JOINT, j), RangeText(m, j),
                    watch.limit_at_start ? "from the first step (the start lies outside its range)"
                                         : fmt::format("from t = {:.3g} s", watch.limit_time));
  } else if (watch.saturated > 0) {
    r->rang_by = Decider::kForceRange;
    r->why_rang = fmt::format("its force sat at forcerange [{:g}, {:g}] for {:.0f}% of the run",
                              m->actuator_forcerange[2 * u], m->actuator_forcerange[2 * u + 1],
                              100.0 * watch.saturated / std::max(1L, watch.steps));
  }
}

// What decided where it stopped: a force at forcerange, else the load against the servo that
// balances at least half its force (a limit, an equality, a spring); else the servo.
void JudgeStop(const Model& model, int u, const StepLoads& loads, StepResponse* r) {
  const mjModel* m = model.get();
  double lo = m->actuator_forcerange[2 * u], hi = m->actuator_forcerange[2 * u + 1];
  double tol = 1e-9 * std::max({1.0, std::fabs(lo), std::fabs(hi)});
  if (m->actuator_forcelimited[u] && (loads.actuator >= hi - tol || loads.actuator <= lo + tol)) {
    r->stopped_by = Decider::kForceRange;
    r->why_stopped = fmt::format("its force sits at forcerange [{:g}, {:g}]", lo, hi);
    return;
  }
  // the largest load pushing against the servo's force
  std::pair<double, Decider> against[] = {{-loads.limit, Decider::kLimit},
                                          {-loads.equality, Decider::kEquality},
                                          {-loads.passive, Decider::kLoad}};
  auto [load, by] =
      *std::max_element(std::begin(against), std::end(against), [&](const auto& a, const auto& b) {
        return a.first * loads.actuator < b.first * loads.actuator;
      });
  if (load * loads.actuator <= 0 || std::fabs(load) < 0.5 * std::fabs(loads.actuator)) return;
  r->stopped_by = by;
  std::string share =
      fmt::format("{:.3g} against its force {:.3g}", std::fabs(load), std::fabs(loads.actuator));
  if (by == Decider::kLimit) {
    int j = loads.limit_joint;
    r->why_stopped = j >= 0 ? fmt::format("the limit of {} {} holds {}",
                                          NameOf(model, mjOBJ_JOINT, j), RangeText(m, j), share)
                            : "a tendon limit holds " + share;
  } else if (by == Decider::kEquality) {
    r->why_stopped =
        "the equality constraints tying its joints to the others that move push "
        "back with " +
        share;
    if (loads.spring_joint >= 0) {
      r->why_stopped += fmt::format(" (the linkage's load: the spring of {})",
                                    NameOf(model, mjOBJ_JOINT, loads.spring_joint));
    }
  } else {
    r->why_stopped = "a spring on its joints (stiffness) pulls back with " + share;
  }
}

// A step from the reference pose (PrepareStep), gravity and contacts off so only the actuator
// acts, every other ctrl at its middle. `work` is a copy of the model with gravity and contacts
// off, `data` its data (reused from one actuator to the next: a big model's mjData costs more
// to make than to step).
StepResponse MeasureStep(Model& work, Data& data, const std::vector<Assignment>& sets,
                         const ReferencePose& ref, int u, double duration,
                         const AuditOptions& options, const std::string& element) {
  StepResponse out;
  out.duration = duration;
  const mjModel* m = work.get();
  CtrlStep step = PrepareStep(work, data, sets, ref, u);
  bool servo =
      step.kind == ActuatorKind::kPositionServo || step.kind == ActuatorKind::kVelocityServo;
  double y0 = step.Quantity(data.get());
  std::vector<double> t, y;
  double max_speed = 0;
  StepWatch watch;
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
    if (servo) watch.See(m, d, u, step);
  };
  NullSink sink;
  out.run.label = "step response of " + element;
  out.run.duration = duration;
  out.run.result = Run(work, data, spec, sink);
  TakeMujocoWarnings();  // counted in the run's result, reported in the warnings layer
  out.run.repro = KeepDiverged(work, out.run.result, options, out.run.label);
  AuditCurve curve;
  curve.label = out.run.label;
  curve.quantity = step.kind == ActuatorKind::kPositionServo   ? "actuator length"
                   : step.kind == ActuatorKind::kVelocityServo ? "actuator velocity"
                                                               : "actuator force";
  curve.t = t;
  curve.y = y;
  curve.start = y0;
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
  if (!servo || !out.moved) return out;
  out.measured = DescribeStep(work, step) + out.measured;
  out.within_range = step.reach.has_value();
  JudgeOvershoot(work, u, step, watch, &out);
  JudgeStop(work, u, LoadsAtEnd(m, data.get(), step), &out);
  return out;
}

// A servo's step response against its thresholds: overshoot beyond kOvershootFail swings past
// the target by more than the step (an oscillating or unstable servo: one arm rang at 3,300%);
// beyond kOvershootWarn, or a steady-state error beyond kErrorWarn (it misses most of the
// step), is suspect. The settling time is shown, not judged: a slow servo is a choice. Clean
// robots: overshoot 0%, errors up to 3.2% (the Robotiq 2F-85's spring-loaded linkage, moving
// with its driver as in a plain run; 32% while the harness held it); a position servo with kp
// and joint damping only (examples/model_ci's arm) overshoots 33%. An overshoot a limit
// decided is a WARN that names it, never a FAIL of the gains; one with the force at forcerange
// names the saturation beside the gains; an error names what held the servo back.
constexpr double kOvershootWarn = 0.5, kOvershootFail = 1, kErrorWarn = 0.5;

// What to do about a step response, or for a PASS what it shows.
std::string StepAdvice(const StepResponse& r, CheckStatus status) {
  bool rings = r.overshoot > kOvershootWarn;
  if (status == CheckStatus::kPass) {
    return std::string(r.within_range
                           ? "a step within its joint's range (at most 10% of ctrlrange and 25% "
                             "of the range, its target 10% of the range inside the bounds)"
                           : "a step of 10% of ctrlrange") +
           " from the reference pose, gravity and contacts off, the joints an equality or "
           "tendon ties to it moving with it, the other servos holding the pose and the other "
           "joints held there" +
           (r.why_rang.empty() ? std::string() : "; " + r.why_rang) +
           (r.why_stopped.empty() ? std::string() : "; at the end " + r.why_stopped);
  }
  if (rings && r.rang_by == Decider::kLimit) {
    return r.why_rang +
           ": the limit, not the gains, threw the joint past its target (kp is "
           "not the cause); start the joints inside their ranges, and check the ranges of the "
           "joints coupled to it";
  }
  if (rings && r.rang_by == Decider::kForceRange) {
    return r.why_rang +
           ": its gains ask for more force than that, so it cannot brake in time: lower kp "
           "or raise kv or dampratio (see actuator.stability), or raise forcerange if the "
           "motor gives more";
  }
  if (rings) {
    return "the servo overshoots: its gains are too stiff or too little damped for the link "
           "it moves (see actuator.stability): raise kv or dampratio, add armature, or lower kp";
  }
  if (r.stopped_by == Decider::kServo) {
    return fmt::format(
        "the servo has not reached its target by {:g} s and no limit, equality, spring or force "
        "bound holds it back: kp is weak for the inertia and damping it moves",
        r.duration);
  }
  const char* advice =
      r.stopped_by == Decider::kLimit
          ? "a limit, not kp, stops it short: check the ranges of the joints that move with it"
      : r.stopped_by == Decider::kEquality
          ? "the coupled linkage carries a load stronger than kp (a spring, a stiff coupled "
            "joint); raise kp or check the linkage's springs"
      : r.stopped_by == Decider::kLoad
          ? "kp against the spring sets the error; raise kp or check stiffness and springref"
          : "kp x error exceeds the force bound; raise forcerange to the motor's rating, or "
            "accept the error";
  return r.why_stopped + ": " + advice;
}

CheckRow ServoStepRow(const CheckElement& element, const StepResponse& r) {
  bool rings = r.overshoot > kOvershootWarn, misses = r.error > kErrorWarn;
  bool gains = rings && r.rang_by != Decider::kLimit;  // a saturating servo's gains still ask
  CheckStatus status = gains && r.overshoot > kOvershootFail ? CheckStatus::kFail
                       : rings || misses                     ? CheckStatus::kWarn
                                                             : CheckStatus::kPass;
  // as numbers: the overshoot (a share of the step) against its bound
  return WithNumbers(Make(L, "actuator.step_response", element, r.measured,
                          fmt::format("overshoot <= {:g}%, steady-state error <= {:g}%",
                                      100 * kOvershootWarn, 100 * kErrorWarn),
                          status, StepAdvice(r, status)),
                     {r.overshoot, ""}, {kOvershootWarn, ""});
}

}  // namespace

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

}  // namespace plumb::audit
