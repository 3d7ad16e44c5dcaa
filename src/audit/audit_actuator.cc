// Audit layer 3, actuators: force bounds, a servo's targets against its joint's range,
// whether each actuator can hold its limb against gravity; the step responses are in
// audit_step.cc.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include "audit/audit_layers.h"
#include "core/mujoco_compat.h"

namespace plumb::audit {

int ActuatorCtrl(const mjModel* m, int u) {
  return static_cast<int>(compat::ActuatorControls(m, u).first);
}
int ActuatorOutput(const mjModel* m, int u) {
  return static_cast<int>(compat::ActuatorOutputs(m, u).first);
}
bool ActuatorCtrlLimited(const mjModel* m, int u) {
  return compat::ActuatorControls(m, u).second > 0 && m->actuator_ctrllimited[ActuatorCtrl(m, u)];
}
const mjtNum* ActuatorCtrlRange(const mjModel* m, int u) {
  return m->actuator_ctrlrange + 2 * ActuatorCtrl(m, u);
}
double ActuatorGear(const mjModel* m, int u) { return m->actuator_gear[6 * ActuatorOutput(m, u)]; }

std::string ActuatorGearText(const mjModel* m, int u) {
  const mjtNum* g = m->actuator_gear + 6 * ActuatorOutput(m, u);
  if (g[1] == 0 && g[2] == 0 && g[3] == 0 && g[4] == 0 && g[5] == 0)
    return fmt::format("{:g}", g[0]);
  return fmt::format("({:g} {:g} {:g} {:g} {:g} {:g})", g[0], g[1], g[2], g[3], g[4], g[5]);
}

namespace {

constexpr const char* L = "actuator";

// The bound MuJoCo puts on the total actuator force at actuator u's joint (actuatorfrcrange),
// as a bound on u's own force (divided by its gear); nullopt when there is none.
std::optional<std::pair<double, double>> TransmissionBound(const mjModel* m, int u) {
  int trn = m->actuator_trntype[u];
  double gear = ActuatorGear(m, u);
  if ((trn != mjTRN_JOINT && trn != mjTRN_JOINTINPARENT) || gear == 0) return std::nullopt;
  auto range = compat::JointActuatorForceRange(m, m->actuator_trnid[2 * u]);
  if (!range) return std::nullopt;
  double a = range->first / gear, b = range->second / gear;
  return std::make_pair(std::min(a, b), std::max(a, b));
}

}  // namespace

std::pair<double, double> ActuatorForceInterval(const mjModel* m, int u) {
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
  } else if (ActuatorCtrlLimited(m, u) && m->actuator_gaintype[u] == mjGAIN_FIXED &&
             m->actuator_biastype[u] == mjBIAS_NONE && m->actuator_dyntype[u] == mjDYN_NONE) {
    // a fixed-gain, bias-free actuator: force = gain * ctrl
    double a = gain[0] * ActuatorCtrlRange(m, u)[0], b = gain[0] * ActuatorCtrlRange(m, u)[1];
    lo = std::max(lo, std::min(a, b));
    hi = std::min(hi, std::max(a, b));
  }
  return {lo, hi};
}

ActuatorKind ActuatorKindOf(const mjModel* m, int u) {
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

namespace {

// An actuator nothing bounds: a real motor saturates.
void Limits(const mjModel* m, int u, const CheckElement& element, std::vector<CheckRow>* out) {
  auto [flo, fhi] = ActuatorForceInterval(m, u);
  if (std::isfinite(flo) && std::isfinite(fhi)) return;
  CheckRow& row = out->emplace_back(Make(
      L, "actuator.limits", element,
      fmt::format("ctrl {}, force {}, gear {}", ActuatorCtrlLimited(m, u) ? "limited" : "unlimited",
                  m->actuator_forcelimited[u] ? "limited" : "unlimited", ActuatorGearText(m, u)),
      "a force bound", CheckStatus::kWarn,
      "a real motor saturates: set ctrllimited/ctrlrange (and forcerange) "
      "from the motor's datasheet, torque = gear x force"));
  // the same finding: the same of ctrl and force bounded (the gears may differ)
  row.finding =
      fmt::format("ctrl {}, force {}", ActuatorCtrlLimited(m, u) ? "limited" : "unlimited",
                  m->actuator_forcelimited[u] ? "limited" : "unlimited");
}

// A position servo's targets (ctrl / gear, in joint units) should lie within reach.
void TargetRange(const mjModel* m, int u, const CheckElement& element, std::vector<CheckRow>* out) {
  int trn = m->actuator_trntype[u];
  int joint = m->actuator_trnid[2 * u];
  double gear = ActuatorGear(m, u);
  bool joint_trn = trn == mjTRN_JOINT || trn == mjTRN_JOINTINPARENT;
  if (ActuatorKindOf(m, u) != ActuatorKind::kPositionServo || !joint_trn ||
      !m->jnt_limited[joint] || !ActuatorCtrlLimited(m, u) || gear == 0) {
    return;
  }
  double lo = ActuatorCtrlRange(m, u)[0] / gear, hi = ActuatorCtrlRange(m, u)[1] / gear;
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
  double gear = ActuatorGear(m, u);
  auto [flo, fhi] = ActuatorForceInterval(m, u);
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

}  // namespace

void ActuatorLayer(const Model& original, const Model& model, Data& data,
                   const std::vector<Assignment>& sets, const ReferencePose& ref,
                   const AuditOptions& options, std::vector<Observed>* runs,
                   std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  // the generalized force each joint needs to hold the reference pose (qvel = 0)
  mju_zero(data->qvel, m->nv);
  data.Forward();
  if (compat::ActuatorCount(m) == 0) {
    out->push_back(Make(L, "actuator.none", "", "no actuators", "", CheckStatus::kSkip,
                        "a passive model: nothing to check in this layer but its springs"));
    ServoTimescales(model, data, out);
    return;
  }
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
  ServoTimescales(model, data, out);
  ActuatorRank(model, data, out);
  MirrorActuators(model, data, out);
  StepResponses(original, model, sets, ref, options, runs, out);
}

}  // namespace plumb::audit
