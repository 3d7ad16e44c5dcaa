// Audit layer 3, actuators: the stability margin of every position and velocity servo under
// the model's integrator and timestep.
//
// Along its transmission a servo is a spring (kp) and a damper (kv) on the inertia it moves,
// 1 / (m^T M^-1 m) for its moment m (for a joint with gear g: 1 / (g^2 (M^-1)_ii), the
// inertia the joint sees with every other joint free; M includes dof_armature). With
// a = kp h^2 / inertia and b = kv h / inertia, MuJoCo's semi-implicit Euler (kv explicit) is
// stable while a + 2b < 4 and b < 2; the implicit integrators (kv implicit) while a < 4 + 2b;
// RK4 while a < 2.785^2 and b < 2.785. Joint damping d (dof_damping, in actuator space) is
// implicit in Euler (unless eulerdamp is disabled): it solves (I + h d) v' = ... with the damper
// kv + d, so a + 2b < 4 becomes kp h^2 + 2 kv h < 4 I + 2 h d, and b < 2 becomes
// kv h < 2 I + h d; the implicit integrators add d to kv. RK4 is judged without it (damping only
// helps it). The margin is how many times the limit exceeds the servo's side: below 1 the servo
// diverges, below kMarginWarn it rings for many steps.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "audit/audit_layers.h"
#include "audit/servo_model.h"
#include "core/mujoco_compat.h"

namespace plumb::audit {
namespace {

constexpr const char* L = "actuator";
constexpr double kMarginWarn = 2;
constexpr double kRk4Limit = 2.785;  // RK4's stability limit of omega*h for an oscillator

}  // namespace

Scheme SchemeOf(int integrator) {
  if (integrator == mjINT_EULER) return Scheme::kEuler;
  if (integrator == mjINT_RK4) return Scheme::kRk4;
  return Scheme::kImplicit;
}

double Margin(const Servo& s, double h, Scheme scheme) {
  double a = s.kp * h * h / s.inertia, b = s.kv * h / s.inertia;
  double d = s.ImplicitDamping();
  switch (scheme) {
    case Scheme::kEuler: {
      double room = 4 + 2 * d * h / s.inertia;  // 4 I + 2 h d, over I
      // (kv + d) h / (I + h d) < 2, over I
      return std::min(a + 2 * b > 0 ? room / (a + 2 * b) : INFINITY,
                      b > 0 ? (2 + d * h / s.inertia) / b : INFINITY);
    }
    case Scheme::kRk4:
      return std::min(a > 0 ? kRk4Limit * kRk4Limit / a : INFINITY,
                      b > 0 ? kRk4Limit / b : INFINITY);
    case Scheme::kImplicit:
      return a > 0 ? (4 + 2 * (s.kv + d) * h / s.inertia) / a : INFINITY;
  }
  return INFINITY;
}

bool AlongTransmission(const mjModel* m, const mjData* d, const std::vector<mjtNum>& moment,
                       Servo* s) {
  std::vector<mjtNum> solved(m->nv);
  mj_solveM(m, const_cast<mjData*>(d), solved.data(), moment.data(), 1);
  double s_inv = mju_dot(moment.data(), solved.data(), m->nv);
  if (!(s_inv > 0)) return false;
  s->inertia = 1 / s_inv;
  // joint damping along the transmission, 1 / sum(m_i^2 / d_i): none when a dof it moves has
  // none; Euler integrates it implicitly unless eulerdamp is off
  s->damping_implicit = m->opt.integrator != mjINT_RK4 &&
                        (m->opt.integrator != mjINT_EULER || compat::EulerDampsImplicitly(m));
  double inverse = 0;
  for (int i = 0; i < m->nv; ++i) {
    if (moment[i] == 0) continue;
    if (!(m->dof_damping[i] > 0)) {
      inverse = INFINITY;
      break;
    }
    inverse += moment[i] * moment[i] / m->dof_damping[i];
  }
  s->damping = inverse > 0 && std::isfinite(inverse) ? 1 / inverse : 0;
  return true;
}

std::optional<Servo> ServoGains(const mjModel* m, const mjData* d, int u) {
  bool gain = m->actuator_gaintype[u] == mjGAIN_FIXED || m->actuator_gaintype[u] == compat::kGainPid;
  if (!gain || m->actuator_biastype[u] != mjBIAS_AFFINE) return std::nullopt;
  // a pid keeps its kp and kv in the affine bias too
  const mjtNum* bias = m->actuator_biasprm + mjNBIAS * u;
  Servo s{std::max(0.0, -bias[1]), std::max(0.0, -bias[2])};
  if (s.kp <= 0 && s.kv <= 0) return std::nullopt;
  int out = static_cast<int>(compat::ActuatorOutputs(m, u).first);
  if (!AlongTransmission(m, d, compat::ActuatorMomentRow(m, d, out), &s)) return std::nullopt;
  return s;
}

bool Coupled(const mjModel* m, int j) {
  for (int e = 0; e < m->neq; ++e) {
    if (m->eq_type[e] == mjEQ_JOINT && (m->eq_obj1id[e] == j || m->eq_obj2id[e] == j)) return true;
  }
  return false;
}

namespace {

const char* SchemeName(Scheme s) {
  return s == Scheme::kEuler ? "Euler" : s == Scheme::kRk4 ? "RK4" : "an implicit integrator";
}

// The inertia (actuator space) at which the margin reaches `target`.
double InertiaFor(const Servo& s, double h, Scheme scheme, double target) {
  switch (scheme) {
    case Scheme::kEuler:
      return std::max((target * (s.kp * h * h + 2 * s.kv * h) - 2 * h * s.ImplicitDamping()) / 4,
                      (target * s.kv * h - s.ImplicitDamping() * h) / 2);
    case Scheme::kRk4:
      return std::max(target * s.kp * h * h / (kRk4Limit * kRk4Limit),
                      target * s.kv * h / kRk4Limit);
    case Scheme::kImplicit:
      return std::max(0.0, (target * s.kp * h * h - 2 * (s.kv + s.ImplicitDamping()) * h) / 4);
  }
  return 0;
}

// The largest timestep at which the margin reaches `target` (Euler's bound; the others'
// are no smaller): kp h^2 + 2 (kv - d / target) h <= 4 I / target.
double TimestepFor(const Servo& s, double target) {
  double m = s.inertia * 4 / target;
  double kv = s.kv - s.ImplicitDamping() / target;
  if (s.kp <= 0) return kv > 0 ? m / (2 * kv) : INFINITY;
  return (-2 * kv + std::sqrt(4 * kv * kv + 4 * s.kp * m)) / (2 * s.kp);
}

CheckRow StabilityRow(const Model& model, int u, const Servo& s) {
  const mjModel* m = model.get();
  double h = m->opt.timestep;
  Scheme scheme = SchemeOf(m->opt.integrator);
  double margin = Margin(s, h, scheme);
  int joint = DrivenJoint(m, u);
  // a tendon, or a joint an equality constraint couples to others, moves more than the inertia
  // along its own direction: coupled by design, not judged
  bool coupled = joint < 0 ? m->actuator_trntype[u] == mjTRN_TENDON : Coupled(m, joint);
  CheckStatus status = coupled                ? CheckStatus::kSkip
                       : margin < 1           ? CheckStatus::kFail
                       : margin < kMarginWarn ? CheckStatus::kWarn
                                              : CheckStatus::kPass;
  double gear = m->actuator_gear[6 * compat::ActuatorOutputs(m, u).first];
  std::string inertia = joint >= 0
                            ? fmt::format("{:.3g} at {} (armature {:.3g})", s.inertia * gear * gear,
                                          Elem(model, mjOBJ_JOINT, joint, "joint"),
                                          m->dof_armature[m->jnt_dofadr[joint]])
                            : fmt::format("{:.3g} along its transmission", s.inertia);
  std::string measured = fmt::format(
      "margin {:.3g} under {} at h = {:g} s (kp {:.4g}, kv {:.4g}{} on an effective inertia of {})",
      margin, SchemeName(scheme), h, s.kp, s.kv,
      s.ImplicitDamping() > 0 ? fmt::format(", joint damping {:.4g} (implicit)", s.ImplicitDamping())
                              : "",
      inertia);
  if (scheme != Scheme::kEuler) {
    measured += fmt::format("; under Euler: {:.3g}", Margin(s, h, Scheme::kEuler));
  }
  std::string fix;
  if (status == CheckStatus::kPass) {
    fix = "servo gains against the inertia they move and the timestep";
  } else if (status == CheckStatus::kSkip) {
    fix =
        "its transmission is coupled to other joints (a tendon or an equality constraint), "
        "which move with it: the margin along its own direction alone is not judged";
  } else {
    double need = InertiaFor(s, h, scheme, kMarginWarn);
    std::string armature =
        joint >= 0
            ? fmt::format("armature >= {:.3g} on {}, ",
                          m->dof_armature[m->jnt_dofadr[joint]] + (need - s.inertia) * gear * gear,
                          Elem(model, mjOBJ_JOINT, joint, "joint"))
            : "";
    fix = fmt::format(
        "the servo {} at this timestep: its gains are too stiff for the light link it moves. "
        "Give it {}a timestep <= {:.3g} s{}, or lower kp/kv (a margin of {:g} is the goal)",
        margin < 1 ? "is unstable (it diverges, or chatters at its force limits)"
                   : "rings for many steps",
        armature, TimestepFor(s, kMarginWarn),
        scheme == Scheme::kEuler ? fmt::format(", the implicitfast integrator (margin {:.3g})",
                                               Margin(s, h, Scheme::kImplicit))
                                 : "",
        kMarginWarn);
  }
  return WithNumbers(Make(L, "actuator.stability", ElementOf(model, mjOBJ_ACTUATOR, u, "actuator"),
                          measured, fmt::format(">= {:g}", kMarginWarn), status, fix),
                     {margin, ""}, {kMarginWarn, ""});
}

}  // namespace

void ServoStability(const Model& model, const Data& data, std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  int listed = 0, servos = 0;
  for (int u = 0; u < compat::ActuatorCount(m); ++u) {
    std::optional<Servo> s = ServoGains(m, data.get(), u);
    if (!s) continue;
    ++servos;
    CheckRow row = StabilityRow(model, u, *s);
    if (row.status == CheckStatus::kPass && listed >= kMaxListed) continue;
    listed += row.status == CheckStatus::kPass;
    out->push_back(std::move(row));
  }
  ListedNote(L, "actuator.stability", "servos", servos, out, std::min(servos, kMaxListed));
}

}  // namespace plumb::audit
