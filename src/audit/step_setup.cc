// Audit layer 3, actuators: preparing a step response (audit_step.cc runs and judges it).
// What moves with the driven actuator (the joints an equality or tendon ties to its own), a
// position servo's joint or tendon and a step kept within its range, and the reference pose
// with the other servos holding it and the joints that do not move with it held there.

#include "audit/step_setup.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "core/mujoco_compat.h"

namespace plumb::audit {
using internal::JointDofSize;

namespace {

// A step of kStepShare of the ctrlrange (0.1 of ctrl when unlimited). A position servo's step
// is at most kRangeShare of its joint's range width, and its target stays kRangeMargin of the
// width inside either bound: a start anywhere inside the range has that much room on one side,
// so mirrored joints (mirrored ranges of one width) step by the same amount.
constexpr double kStepShare = 0.1, kRangeShare = 0.25, kRangeMargin = 0.1;

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
      LoopJoints(m, compat::EqualityBody(m, e, a), b >= 0 ? compat::EqualityBody(m, e, b) : 0,
                 &out);
      break;
    default:
      break;
  }
  return out;
}

// What moves with actuator u in `d`'s pose (Coupling).
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
      if (c.equalities[e] || !compat::EqualityActive(m, d, e)) continue;
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

// Actuator u's joint or tendon (Reach); none when its gear is 0 or it moves a ball or free
// joint, a site or a body.
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

}  // namespace

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

}  // namespace plumb::audit
