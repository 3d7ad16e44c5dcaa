#include "plumb/analytic.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/mujoco_compat.h"
#include "plumb/error.h"

namespace plumb {

double EllipticK(double k) {
  if (!(k >= 0 && k < 1)) {
    throw ValueError("EllipticK: the modulus must be in [0, 1), got " + std::to_string(k));
  }
  // K(k) = pi / (2 * AGM(1, sqrt(1 - k^2)))
  double a = 1, b = std::sqrt((1 - k) * (1 + k));
  for (int i = 0; i < 64 && std::fabs(a - b) > 1e-16 * a; ++i) {
    double mean = 0.5 * (a + b);
    b = std::sqrt(a * b);
    a = mean;
  }
  return M_PI / (a + b);
}

namespace {

// The first geom the bodies from `body` down can collide with, as "geom 'wall' (id 0)",
// or "" when none is within reach of a full turn about the hinge (positions from `d`).
std::string ReachableContact(const Model& model, const mjData* d, int body) {
  const mjModel* m = model.get();
  if (m->opt.disableflags & mjDSBL_CONTACT) return "";
  auto moving = [&](int geom) {
    for (int b = m->geom_bodyid[geom]; b > 0; b = m->body_parentid[b]) {
      if (b == body) return true;
    }
    return false;
  };
  // everything the hinge moves stays within `reach` of the anchor
  const mjtNum* anchor = d->xanchor;
  double reach = 0;
  for (int g = 0; g < m->ngeom; ++g) {
    if (!moving(g)) continue;
    mjtNum r[3];
    mju_sub3(r, d->geom_xpos + 3 * g, anchor);
    reach = std::max(reach, mju_norm3(r) + m->geom_rbound[g] + m->geom_margin[g]);
  }
  for (int g = 0; g < m->ngeom; ++g) {
    if (moving(g)) continue;
    bool pairs = false;
    for (int k = 0; k < m->npair; ++k) {
      int a = m->pair_geom1[k], b = m->pair_geom2[k];
      pairs = pairs || (a == g && moving(b)) || (b == g && moving(a));
    }
    bool filtered = true;
    for (int h = 0; h < m->ngeom && filtered; ++h) {
      if (!moving(h)) continue;
      filtered = !((m->geom_contype[g] & m->geom_conaffinity[h]) ||
                   (m->geom_contype[h] & m->geom_conaffinity[g]));
    }
    if (filtered && !pairs) continue;
    mjtNum r[3];
    mju_sub3(r, anchor, d->geom_xpos + 3 * g);
    double distance = m->geom_type[g] == mjGEOM_PLANE ? std::fabs(r[0] * d->geom_xmat[9 * g + 2] +
                                                                  r[1] * d->geom_xmat[9 * g + 5] +
                                                                  r[2] * d->geom_xmat[9 * g + 8])
                                                      : mju_norm3(r) - m->geom_rbound[g];
    if (distance < reach + m->geom_margin[g]) {
      std::string name = model.Name(mjOBJ_GEOM, g);
      return fmt::format("geom '{}' (id {})", name.empty() ? "unnamed" : name, g);
    }
  }
  return "";
}

}  // namespace

std::string ActuatorPushingAtZeroControl(const Model& model) {
  const mjModel* m = model.get();
  for (int u = 0; u < compat::ActuatorCount(m); ++u) {
    std::string name = model.Name(mjOBJ_ACTUATOR, u);
    name = name.empty() ? "actuator #" + std::to_string(u) : "actuator '" + name + "'";
    if (int plugin = compat::ActuatorPlugin(m, u); plugin >= 0) {
      std::string kind = compat::PluginName(m, plugin);
      return fmt::format("the force of {} comes from a plugin{}, which may push at any ctrl", name,
                         kind.empty() ? "" : " (" + kind + ")");
    }
    const mjtNum* bias = m->actuator_biasprm + mjNBIAS * u;
    bool biased = m->actuator_biastype[u] != mjBIAS_NONE &&
                  std::any_of(bias, bias + mjNBIAS, [](mjtNum b) { return b != 0; });
    if (m->actuator_gaintype[u] != mjGAIN_FIXED || biased) {
      return name + " pushes even at ctrl = 0 (a servo's bias or a muscle's passive force)";
    }
  }
  return "";
}

std::optional<PendulumParams> DetectPendulum(const Model& model, std::string* why_not) {
  const mjModel* m = model.get();
  auto no = [&](const std::string& reason) -> std::optional<PendulumParams> {
    if (why_not) *why_not = reason;
    return std::nullopt;
  };
  if (m->njnt != 1)
    return no("the model has " + std::to_string(m->njnt) + " joints, not one hinge");
  if (m->jnt_type[0] != mjJNT_HINGE) return no("its only joint is not a hinge");
  if (m->opt.disableflags & mjDSBL_GRAVITY) {
    return no("gravity is disabled (<flag gravity=\"disable\"/>): nothing pulls the pendulum");
  }
  if (std::string pushing = ActuatorPushingAtZeroControl(model); !pushing.empty()) {
    return no(pushing);
  }
  if (m->jnt_limited[0]) {
    return no(fmt::format(
        "the hinge is limited to [{:g}, {:g}] rad: a swing that reaches the limit is stopped by "
        "a constraint force no pendulum formula describes",
        m->jnt_range[0], m->jnt_range[1]));
  }
  if (m->jnt_stiffness[0] != 0) return no("the hinge has a spring (stiffness)");
  if (m->dof_frictionloss[0] != 0) return no("the hinge has dry friction (frictionloss)");
  if (m->neq > 0 || m->ntendon > 0) return no("it has equality constraints or tendons");
  if (m->opt.density != 0 || m->opt.viscosity != 0) return no("it has fluid forces");

  Data data(model);
  mjData* d = data.get();
  int body = m->jnt_bodyid[0];
  int adr = m->jnt_qposadr[0];
  d->qpos[adr] = 0;
  mj_forward(m, d);
  const mjtNum* a = d->xaxis;
  const mjtNum* anchor = d->xanchor;
  const mjtNum* g = m->opt.gravity;
  mjtNum r[3], r_perp[3], g_perp[3];
  for (int i = 0; i < 3; ++i) r[i] = d->subtree_com[3 * body + i] - anchor[i];
  mjtNum ra = mju_dot3(r, a), ga = mju_dot3(g, a);
  for (int i = 0; i < 3; ++i) {
    r_perp[i] = r[i] - ra * a[i];
    g_perp[i] = g[i] - ga * a[i];
  }
  if (std::string touch = ReachableContact(model, d, body); !touch.empty()) {
    return no("its geoms can touch " + touch + ": contacts would stop or deflect the swing");
  }
  PendulumParams p;
  p.joint = 0;
  p.mass = m->body_subtreemass[body];
  p.distance = mju_norm3(r_perp);
  p.gravity = mju_norm3(g_perp);
  if (p.gravity < 1e-12) return no("gravity has no component perpendicular to the hinge axis");
  if (p.distance < 1e-12) return no("the centre of mass lies on the hinge axis");
  if (p.mass <= 0) return no("the hinge moves no mass");

  // the angle that turns the centre of mass to hang along gravity
  mjtNum cross[3];
  mju_cross(cross, r_perp, g_perp);
  p.equilibrium = std::atan2(mju_dot3(cross, a), mju_dot3(r_perp, g_perp));

  // moment of inertia about the axis, armature included, from the mass matrix
  d->qpos[adr] = p.equilibrium;
  mj_forward(m, d);
  mjtNum inertia = 0;
  compat::FullInertia(m, d, &inertia);
  p.inertia = inertia;
  p.stiffness = p.mass * p.gravity * p.distance;
  p.damping = m->dof_damping[m->jnt_dofadr[0]];
  return p;
}

double SmallAnglePeriod(const PendulumParams& p) {
  return 2 * M_PI * std::sqrt(p.inertia / p.stiffness);
}

double LargeAnglePeriod(const PendulumParams& p, double theta0) {
  if (!(std::fabs(theta0) < M_PI)) {
    throw ValueError("LargeAnglePeriod: the amplitude must be below pi rad, got " +
                     std::to_string(theta0));
  }
  return SmallAnglePeriod(p) * (2 / M_PI) * EllipticK(std::fabs(std::sin(theta0 / 2)));
}

const char* DampingClassName(DampingClass c) {
  switch (c) {
    case DampingClass::kUndamped:
      return "undamped";
    case DampingClass::kUnderdamped:
      return "underdamped";
    case DampingClass::kCritical:
      return "critically damped";
    case DampingClass::kOverdamped:
      return "overdamped";
  }
  return "?";
}

DampingAnalysis AnalyseDamping(double inertia, double stiffness, double damping,
                               double critical_band) {
  DampingAnalysis out;
  out.omega0 = std::sqrt(stiffness / inertia);
  out.zeta = damping / (2 * std::sqrt(inertia * stiffness));
  if (damping == 0) {
    out.kind = DampingClass::kUndamped;
  } else if (std::fabs(out.zeta - 1) <= critical_band) {
    out.kind = DampingClass::kCritical;
  } else if (out.zeta < 1) {
    out.kind = DampingClass::kUnderdamped;
  } else {
    out.kind = DampingClass::kOverdamped;
  }
  if (out.zeta < 1 && out.kind != DampingClass::kCritical) {
    out.omega_d = out.omega0 * std::sqrt(1 - out.zeta * out.zeta);
    out.damped_period = 2 * M_PI / out.omega_d;
  }
  return out;
}

std::optional<double> PeriodFromCrossings(const std::vector<double>& t,
                                          const std::vector<double>& x, double level,
                                          int max_periods) {
  std::vector<double> crossings;
  for (std::size_t i = 1; i < x.size() && i < t.size(); ++i) {
    double a = x[i - 1] - level, b = x[i] - level;
    if (a < 0 && b >= 0) {
      crossings.push_back(t[i - 1] + (t[i] - t[i - 1]) * (-a) / (b - a));
      if (max_periods > 0 && static_cast<int>(crossings.size()) == max_periods + 1) break;
    }
  }
  if (crossings.size() < 2) return std::nullopt;
  return (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
}

std::vector<double> Peaks(const std::vector<double>& x) {
  std::vector<double> peaks;
  for (std::size_t i = 1; i + 1 < x.size(); ++i) {
    if (x[i] > x[i - 1] && x[i] >= x[i + 1]) peaks.push_back(x[i]);
  }
  return peaks;
}

}  // namespace plumb
