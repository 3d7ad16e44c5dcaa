// Audit layer 3, actuators: the step response. A position servo steps within its joint's
// (tendon's) range, the joints an equality or tendon ties to its own move with it, the others
// hold the reference pose, and a response that a limit, an equality, a load or a saturated
// force decided says so instead of blaming the gains.

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "audit/audit_layers.h"
#include "core/joint_size.h"
#include "core/mujoco_compat.h"
#include "plumb/describe.h"

namespace plumb::audit {
namespace {

constexpr const char* L = "actuator";

// At most this many actuators get a step response (evenly spaced when there are more).
constexpr int kStepActuators = 12;

// A step of kStepShare of the ctrlrange (0.1 of ctrl when unlimited). A position servo's step
// is at most kRangeShare of its joint's range width, and its target stays kRangeMargin of the
// width inside either bound: a start anywhere inside the range has that much room on one side,
// so mirrored joints (mirrored ranges of one width) step by the same amount.
constexpr double kStepShare = 0.1, kRangeShare = 0.25, kRangeMargin = 0.1;

// At most this many joints are named as moving with the driven one.
constexpr int kNamedJoints = 6;

// MuJoCo 3.x: connect and weld constraints may name sites (eq_objtype), and whether an
// equality is on lives in mjData; 2.x: bodies only, and the flag is the model's.
template <class M>
auto EqualityBody(const M* m, int e, int id, int) -> decltype(m->eq_objtype, int()) {
  return m->eq_objtype[e] == mjOBJ_SITE ? m->site_bodyid[id] : id;
}
template <class M>
int EqualityBody(const M*, int, int id, long) {
  return id;
}
template <class D>
auto EqualityActive(const mjModel*, const D* d, int e, int) -> decltype(d->eq_active, bool()) {
  return d->eq_active[e];
}
template <class M, class D>
bool EqualityActive(const M* m, const D*, int e, long) {
  return m->eq_active[e];
}

// The joints of tendon t's path (a fixed tendon's; a spatial tendon has none).
void TendonJoints(const mjModel* m, int t, std::vector<int>* joints) {
  for (int w = m->tendon_adr[t]; w < m->tendon_adr[t] + m->tendon_num[t]; ++w) {
    if (m->wrap_type[w] == mjWRAP_JOINT) joints->push_back(m->wrap_objid[w]);
  }
}

// The joints of the loop a constraint between bodies a and b closes: those on the path from
// each up to their common ancestor.
void LoopJoints(const mjModel* m, int a, int b, std::vector<int>* joints) {
  std::vector<bool> above_a(m->nbody, false);
  for (int x = a; x > 0; x = m->body_parentid[x]) above_a[x] = true;
  above_a[0] = true;
  int common = b;
  while (!above_a[common]) common = m->body_parentid[common];
  for (int start : {a, b}) {
    for (int x = start; x != common; x = m->body_parentid[x]) {
      for (int k = 0; k < m->body_jntnum[x]; ++k) joints->push_back(m->body_jntadr[x] + k);
    }
  }
}

// The joints equality e ties together: a joint or tendon equality's joints, the loop of a
// connect or weld constraint; none for the other kinds.
std::vector<int> EqualityJoints(const mjModel* m, int e) {
  std::vector<int> out;
  int a = m->eq_obj1id[e], b = m->eq_obj2id[e];
  switch (m->eq_type[e]) {
    case mjEQ_JOINT:
      out.push_back(a);
      if (b >= 0) out.push_back(b);
      break;
    case mjEQ_TENDON:
      TendonJoints(m, a, &out);
      if (b >= 0) TendonJoints(m, b, &out);
      break;
    case mjEQ_CONNECT:
    case mjEQ_WELD:
      LoopJoints(m, EqualityBody(m, e, a, 0), b >= 0 ? EqualityBody(m, e, b, 0) : 0, &out);
      break;
    default:
      break;
  }
  return out;
}

// What moves with actuator u: the joints its moment reaches (a tendon's, all of them), and
// every joint an active equality ties to one of those, until none is added; and the
// equalities that tie them.
struct Coupling {
  std::vector<bool> driven;      // njnt: the joints its moment reaches
  std::vector<bool> joints;      // njnt: those and the joints tied to them
  std::vector<bool> equalities;  // neq
};

Coupling MovingWith(const mjModel* m, const mjData* d, int u) {
  Coupling c{std::vector<bool>(m->njnt, false), {}, std::vector<bool>(m->neq, false)};
  std::vector<mjtNum> row = compat::ActuatorMomentRow(m, d, ActuatorOutput(m, u));
  for (int v = 0; v < m->nv; ++v) {
    if (row[v] != 0) c.driven[m->dof_jntid[v]] = true;
  }
  c.joints = c.driven;
  for (bool grew = true; grew;) {
    grew = false;
    for (int e = 0; e < m->neq; ++e) {
      if (c.equalities[e] || !EqualityActive(m, d, e, 0)) continue;
      std::vector<int> tied = EqualityJoints(m, e);
      if (std::none_of(tied.begin(), tied.end(), [&](int j) { return c.joints[j]; })) continue;
      c.equalities[e] = grew = true;
      for (int j : tied) c.joints[j] = true;
    }
  }
  return c;
}

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

double Clamp(const mjModel* m, int i, double ctrl) {
  if (!m->actuator_ctrllimited[i]) return ctrl;
  return std::clamp(ctrl, m->actuator_ctrlrange[2 * i], m->actuator_ctrlrange[2 * i + 1]);
}

// What a position servo moves, in that thing's units (actuator length / gear): a hinge or
// slide, or a fixed tendon, and its range (a tendon without one: its joints' ranges through
// its coefficients; infinite where nothing bounds it).
struct Reach {
  int obj = mjOBJ_JOINT, id = -1;
  double lo = -INFINITY, hi = INFINITY;
  const char* unit = "rad";
};

std::optional<Reach> ReachOf(const mjModel* m, int u) {
  int trn = m->actuator_trntype[u], id = m->actuator_trnid[2 * u];
  if (ActuatorGear(m, u) == 0) return std::nullopt;
  if (trn == mjTRN_JOINT || trn == mjTRN_JOINTINPARENT) {
    int type = m->jnt_type[id];
    if (type != mjJNT_HINGE && type != mjJNT_SLIDE) return std::nullopt;
    Reach r{mjOBJ_JOINT, id, -INFINITY, INFINITY, type == mjJNT_HINGE ? "rad" : "m"};
    if (m->jnt_limited[id]) r.lo = m->jnt_range[2 * id], r.hi = m->jnt_range[2 * id + 1];
    return r;
  }
  if (trn != mjTRN_TENDON) return std::nullopt;
  Reach r{mjOBJ_TENDON, id, 0, 0, "rad"};
  for (int w = m->tendon_adr[id]; w < m->tendon_adr[id] + m->tendon_num[id]; ++w) {
    int j = m->wrap_objid[w];
    if (m->wrap_type[w] != mjWRAP_JOINT || !m->jnt_limited[j]) {
      r.lo = -INFINITY, r.hi = INFINITY;  // spatial, or a joint without a range
      if (m->wrap_type[w] != mjWRAP_JOINT) r.unit = "m";
      continue;
    }
    double c = m->wrap_prm[w], a = c * m->jnt_range[2 * j], b = c * m->jnt_range[2 * j + 1];
    r.lo += std::min(a, b), r.hi += std::max(a, b);
    if (m->jnt_type[j] != mjJNT_HINGE) r.unit = "m";
  }
  if (m->tendon_limited[id]) {
    r.lo = std::max(r.lo, m->tendon_range[2 * id]);
    r.hi = std::min(r.hi, m->tendon_range[2 * id + 1]);
  }
  return r;
}

// Where position servo u steps to from x0, in its reach's units: kStepShare of what its
// ctrlrange asks for, at most kRangeShare of its range's width, toward the side with more
// room, the target kept kRangeMargin of the width inside the range and within ctrlrange.
double StepTarget(const mjModel* m, int u, const Reach& reach, double x0) {
  double gear = ActuatorGear(m, u);
  auto reach_of = [&](double ctrl) {
    return ServoTarget(m, u, ActuatorKind::kPositionServo, ctrl) / gear;
  };
  bool limited = ActuatorCtrlLimited(m, u);
  double c0 = limited ? ActuatorCtrlRange(m, u)[0] : 0;
  double c1 = limited ? ActuatorCtrlRange(m, u)[1] : 0.1;
  double size = (limited ? kStepShare : 1) * std::fabs(reach_of(c1) - reach_of(c0));
  double lo = limited ? std::min(reach_of(c0), reach_of(c1)) : -INFINITY;
  double hi = limited ? std::max(reach_of(c0), reach_of(c1)) : INFINITY;
  double width = reach.hi - reach.lo;
  if (std::isfinite(width) && width > 0) {  // a range of no width bounds nothing
    size = std::min(size, kRangeShare * width);
    double a = std::max(lo, reach.lo + kRangeMargin * width);
    double b = std::min(hi, reach.hi - kRangeMargin * width);
    // a ctrlrange that asks only for positions outside the range (actuator.target_range says
    // so) keeps its own bounds
    if (a <= b) lo = a, hi = b;
  }
  return std::clamp(hi - x0 >= x0 - lo ? x0 + size : x0 - size, lo, hi);
}

// The ctrl step: from `before` to `after` (ctrl units), what it is measured in, and for a
// servo where it should end (`goal`, in the measured quantity's units).
struct CtrlStep {
  ActuatorKind kind = ActuatorKind::kOther;
  double before = 0, after = 0;
  double goal = NAN;
  double length0 = 0;           // the actuator length before the step
  int ctrl = 0, out = 0;        // its control and force output (ActuatorCtrl, ActuatorOutput)
  std::vector<int> held;        // joints held at the reference pose (qpos, qvel reset every step)
  std::vector<mjtNum> qpos;     // the reference pose
  Coupling moving;              // what moves with the actuator (a servo's)
  std::optional<Reach> reach;   // a position servo's joint or tendon
  double from = NAN, to = NAN;  // its step there, in the reach's units
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

// Sets every other servo to hold the pose in `data` (position servos at their length there,
// velocity servos at rest) and returns the dofs position servos move.
std::vector<bool> OtherServosHold(const mjModel* m, mjData* d) {
  std::vector<bool> moved(m->nv, false);
  for (int i = 0; i < compat::ActuatorCount(m); ++i) {
    ActuatorKind kind = ActuatorKindOf(m, i);
    if (kind != ActuatorKind::kPositionServo && kind != ActuatorKind::kVelocityServo) continue;
    double value =
        kind == ActuatorKind::kPositionServo ? d->actuator_length[ActuatorOutput(m, i)] : 0;
    d->ctrl[ActuatorCtrl(m, i)] = Clamp(m, ActuatorCtrl(m, i), HoldingCtrl(m, i, kind, value));
    if (kind != ActuatorKind::kPositionServo) continue;
    std::vector<mjtNum> row = compat::ActuatorMomentRow(m, d, ActuatorOutput(m, i));
    for (int v = 0; v < m->nv; ++v) moved[v] = moved[v] || row[v] != 0;
  }
  return moved;
}

// Chooses a servo's ctrl step: a position servo on a joint or fixed tendon steps within its
// range (StepTarget); any other actuator by kStepShare of its ctrlrange (0.1 when unlimited),
// up unless that leaves the range. Servos start holding where they are.
void ChooseStep(const mjModel* m, const mjData* d, int u, CtrlStep* step) {
  bool limited = ActuatorCtrlLimited(m, u) || m->actuator_gaintype[u] == mjGAIN_MUSCLE;
  double lo = ActuatorCtrlLimited(m, u) ? ActuatorCtrlRange(m, u)[0] : 0;
  double hi = ActuatorCtrlLimited(m, u)                  ? ActuatorCtrlRange(m, u)[1]
              : m->actuator_gaintype[u] == mjGAIN_MUSCLE ? 1
                                                         : 0;
  double size = limited ? kStepShare * (hi - lo) : 0.1;
  step->length0 = d->actuator_length[step->out];
  step->before = d->ctrl[step->ctrl];
  if (step->kind == ActuatorKind::kPositionServo) {
    step->before = HoldingCtrl(m, u, step->kind, step->length0);  // hold where it is
    step->reach = ReachOf(m, u);
  }
  if (step->kind == ActuatorKind::kVelocityServo) {
    step->before = HoldingCtrl(m, u, step->kind, 0);
  }
  step->after = step->before + size;
  if (limited && step->after > hi) step->after = step->before - size;  // stay inside ctrlrange
  if (step->reach) {
    double gear = ActuatorGear(m, u);
    step->from = step->length0 / gear;
    step->to = StepTarget(m, u, *step->reach, step->from);
    step->after = Clamp(m, step->ctrl, HoldingCtrl(m, u, step->kind, step->to * gear));
  }
  if (step->kind == ActuatorKind::kPositionServo || step->kind == ActuatorKind::kVelocityServo) {
    step->goal = ServoTarget(m, u, step->kind, step->after);
  }
}

// Resets `data` to the reference pose with every other servo holding it and other ctrls at
// the middle of their range; when u is a servo, every joint that neither a position servo nor
// u moves (with what an equality or tendon ties to u's joints) is held there kinematically
// (its qpos and qvel put back before every step). Then chooses u's step (ChooseStep).
CtrlStep PrepareStep(Model& work, Data& data, const std::vector<Assignment>& sets,
                     const ReferencePose& ref, int u) {
  const mjModel* m = work.get();
  mj_resetData(m, data.get());
  StartAtPose(work, data, ref, sets);
  CtrlStep step;
  step.kind = ActuatorKindOf(m, u);
  step.ctrl = ActuatorCtrl(m, u);
  step.out = ActuatorOutput(m, u);
  for (int i = 0; i < m->nu; ++i) {
    data->ctrl[i] = m->actuator_ctrllimited[i]
                        ? 0.5 * (m->actuator_ctrlrange[2 * i] + m->actuator_ctrlrange[2 * i + 1])
                        : 0;
  }
  data.Forward();
  std::vector<bool> moved = OtherServosHold(m, data.get());
  step.moving = MovingWith(m, data.get(), u);
  // a servo's step is judged on its own joints: the rest hold still. A motor's is not (with
  // nothing holding it, a constant torque on a held base spins its limb ever faster)
  bool servo =
      step.kind == ActuatorKind::kPositionServo || step.kind == ActuatorKind::kVelocityServo;
  for (int j = 0; j < m->njnt && servo; ++j) {
    bool any = step.moving.joints[j];
    for (int k = 0; k < JointDofSize(m->jnt_type[j]); ++k) any = any || moved[m->jnt_dofadr[j] + k];
    if (!any) step.held.push_back(j);
  }
  step.qpos.assign(data->qpos, data->qpos + m->nq);
  data.Forward();
  ChooseStep(m, data.get(), u, &step);
  data->ctrl[step.ctrl] = step.before;
  data.Forward();
  return step;
}

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
