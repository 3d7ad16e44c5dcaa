// Audit layer 3, actuators: whether actuators that push a free body (rotors, thrusters) can act
// independently. Each such actuator gives a wrench at the body's centre of mass; when one
// actuator's wrench is a combination of the others', a direction the design meant to command
// (a multirotor's yaw when two rotors' drag-torque signs are swapped) is lost.
//
// Judged: site transmissions on a moving body whose gear has a torque part (a rotor's drag
// torque with its thrust), by their rank against the largest rank other signs of those torques
// would give: an octocopter's eight rotors span four directions, as any signs would, and a
// model's spare body-wrench actuators add nothing others could; a quadrotor with two signs
// swapped spans three where alternating signs span four. Not judged, by design: pure forces at
// points, joints and tendons (their columns in joint space are dependent only when they share
// a joint, a choice), and the directions no actuator reaches (an underactuated base is not a
// finding).

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <vector>

#include "audit/audit_layers.h"
#include "core/mujoco_compat.h"

namespace plumb::audit {
namespace {

constexpr const char* L = "actuator";
// A column whose residual against the span of the others, both normalised, lies below this is
// their combination: exact dependence, not a weak direction.
constexpr double kDependent = 1e-6;

using Wrench = std::array<double, 6>;  // force (N), torque / arm (N)

// The root of the free-moving subtree body b belongs to: the body carrying its free joint.
int FreeRoot(const mjModel* m, int b) {
  for (; b > 0; b = m->body_parentid[b]) {
    for (int j = m->body_jntadr[b]; j >= 0 && j < m->body_jntadr[b] + m->body_jntnum[b]; ++j) {
      if (m->jnt_type[j] == mjJNT_FREE) return b;
    }
  }
  return -1;
}

double Norm(const Wrench& w) {
  double s = 0;
  for (double x : w) s += x * x;
  return std::sqrt(s);
}

// The number of independent columns (Gram-Schmidt on unit columns; a residual below
// kDependent adds nothing).
int Rank(std::vector<Wrench> columns) {
  std::vector<Wrench> basis;
  for (Wrench c : columns) {
    double n = Norm(c);
    if (!(n > 0)) continue;
    for (double& x : c) x /= n;
    for (const Wrench& q : basis) {
      double dot = 0;
      for (int k = 0; k < 6; ++k) dot += q[k] * c[k];
      for (int k = 0; k < 6; ++k) c[k] -= dot * q[k];
    }
    double r = Norm(c);
    if (r <= kDependent) continue;
    for (double& x : c) x /= r;
    basis.push_back(c);
  }
  return static_cast<int>(basis.size());
}

// An actuator's wrench at the centre of mass, split into what its force gives (f, r x f) and
// what the torque part of its gear gives; the moment scaled by 1 / arm.
struct Parts {
  Wrench force{}, torque{};
};

Parts WrenchParts(const mjModel* m, const mjData* d, int u, const mjtNum* com, double arm) {
  int site = m->actuator_trnid[2 * u];
  const mjtNum* R = d->site_xmat + 9 * site;
  const mjtNum* g = m->actuator_gear + 6 * compat::ActuatorOutputs(m, u).first;
  mjtNum f[3], t[3], r[3], rf[3];
  mju_mulMatVec(f, R, g, 3, 3);
  mju_mulMatVec(t, R, g + 3, 3, 3);
  mju_sub3(r, d->site_xpos + 3 * site, com);
  mju_cross(rf, r, f);
  return {{f[0], f[1], f[2], rf[0] / arm, rf[1] / arm, rf[2] / arm},
          {0, 0, 0, t[0] / arm, t[1] / arm, t[2] / arm}};
}

// The rank the actuators' wrenches have, and the largest rank other signs of their torque
// parts would give (every sign pattern up to 10 actuators, 1024 patterns beyond).
std::pair<int, int> Ranks(const std::vector<Parts>& parts) {
  int n = static_cast<int>(parts.size());
  auto rank = [&](unsigned long flips) {
    std::vector<Wrench> columns;
    for (int i = 0; i < n; ++i) {
      double sign = (flips >> (i % 64)) & 1 ? -1 : 1;
      Wrench w;
      for (int k = 0; k < 6; ++k) w[k] = parts[i].force[k] + sign * parts[i].torque[k];
      columns.push_back(w);
    }
    return Rank(columns);
  };
  int actual = rank(0), best = actual;
  unsigned long patterns = n <= 10 ? 1ul << n : 1024;
  unsigned long state = 0x9e3779b97f4a7c15ul;
  for (unsigned long p = 1; p < patterns && best < std::min(n, 6); ++p) {
    unsigned long flips = p;
    if (n > 10) {
      state = state * 6364136223846793005ul + 1442695040888963407ul;
      flips = state;
    }
    best = std::max(best, rank(flips));
  }
  return {actual, best};
}

void JudgeBody(const Model& model, int root, const std::vector<int>& actuators, const mjData* d,
               std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  const mjtNum* com = d->subtree_com + 3 * root;
  double arm = 0;
  for (int u : actuators) {
    const mjtNum* p = d->site_xpos + 3 * m->actuator_trnid[2 * u];
    arm = std::max(arm, std::sqrt(std::pow(p[0] - com[0], 2) + std::pow(p[1] - com[1], 2) +
                                  std::pow(p[2] - com[2], 2)));
  }
  if (!(arm > 0)) arm = 1;
  std::vector<Parts> parts;
  std::vector<std::string> names;
  for (int u : actuators) {
    parts.push_back(WrenchParts(m, d, u, com, arm));
    names.push_back(Elem(model, mjOBJ_ACTUATOR, u, "actuator"));
  }
  auto [actual, possible] = Ranks(parts);
  bool lost = actual < possible;
  std::string body = Elem(model, mjOBJ_BODY, root, "body");
  out->push_back(WithNumbers(
      Make(L, "actuator.rank", lost ? fmt::format("{}", fmt::join(names, ", ")) : body,
           fmt::format("the wrenches of {} actuators at the centre of mass of {} span {} "
                       "directions; other signs of their torques would span {}",
                       actuators.size(), body, actual, possible),
           fmt::format(">= {}", possible), lost ? CheckStatus::kWarn : CheckStatus::kPass,
           lost ? "these actuators cannot act independently: a direction they were meant to "
                  "command (a multirotor's yaw, from its rotors' drag torques) is a combination "
                  "of the others. Check the gear signs: a rotor ring alternates them"
                : "the signs of their torques lose no direction"),
      {static_cast<double>(actual), ""}, {static_cast<double>(possible), ""}));
}

}  // namespace

void ActuatorRank(const Model& model, const Data& data, std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  std::map<int, std::vector<int>> by_body;  // free root -> its rotor-like actuators
  for (int u = 0; u < compat::ActuatorCount(m); ++u) {
    if (m->actuator_trntype[u] != mjTRN_SITE || m->actuator_trnid[2 * u + 1] >= 0) continue;
    const mjtNum* g = m->actuator_gear + 6 * compat::ActuatorOutputs(m, u).first;
    if (g[3] == 0 && g[4] == 0 && g[5] == 0) continue;  // a pure force at a point
    int root = FreeRoot(m, m->site_bodyid[m->actuator_trnid[2 * u]]);
    if (root > 0) by_body[root].push_back(u);
  }
  for (const auto& [root, actuators] : by_body) {
    if (actuators.size() >= 2) JudgeBody(model, root, actuators, data.get(), out);
  }
}

}  // namespace plumb::audit
