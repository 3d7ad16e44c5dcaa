// Audit layer 3, actuators: whether actuators that push a free body (rotors, thrusters) can act
// independently. Each such actuator gives a wrench at the body's centre of mass; when one
// actuator's wrench is a combination of the others', a direction the design meant to command
// (a multirotor's yaw when two rotors' drag-torque signs are swapped) is lost.
//
// Judged: site transmissions on a moving body whose gear has a torque part (a rotor's drag
// torque with its thrust). Not judged, by design: pure forces at points (four parallel thrusts
// always span only lift, roll and pitch), actuators on one direction (grouped as one), joints and
// tendons (their columns in joint space are dependent only when they share a joint, a choice),
// and the directions no actuator reaches (an underactuated base is not a finding).

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <vector>

#include "check/audit_layers.h"
#include "core/mujoco_compat.h"

namespace plumb::audit {
namespace {

constexpr const char* L = "actuator";
// A wrench whose residual against the span of the others, both normalised, lies below this is
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

// The residual of `c` after least squares against `basis` (unit columns) and the coefficients.
double Residual(const std::vector<Wrench>& basis, const Wrench& c, std::vector<double>* coef) {
  int n = static_cast<int>(basis.size());
  std::vector<mjtNum> gram(n * n), rhs(n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      double s = 0;
      for (int k = 0; k < 6; ++k) s += basis[i][k] * basis[j][k];
      gram[i * n + j] = s;
    }
    double s = 0;
    for (int k = 0; k < 6; ++k) s += basis[i][k] * c[k];
    rhs[i] = s;
  }
  coef->assign(n, 0);
  if (n > 0) {
    mju_cholFactor(gram.data(), n, 1e-12);
    mju_cholSolve(coef->data(), gram.data(), rhs.data(), n);
  }
  Wrench r = c;
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < 6; ++k) r[k] -= (*coef)[i] * basis[i][k];
  }
  return Norm(r);
}

struct Column {
  std::vector<int> actuators;  // one direction: actuators whose wrenches are parallel
  Wrench w;                    // unit
};

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
  std::vector<Column> columns;
  for (int u : actuators) {
    int site = m->actuator_trnid[2 * u];
    const mjtNum* R = d->site_xmat + 9 * site;
    const mjtNum* g = m->actuator_gear + 6 * compat::ActuatorOutputs(m, u).first;
    mjtNum f[3], t[3], r[3], rf[3];
    mju_mulMatVec(f, R, g, 3, 3);
    mju_mulMatVec(t, R, g + 3, 3, 3);
    mju_sub3(r, d->site_xpos + 3 * site, com);
    mju_cross(rf, r, f);
    Wrench w{f[0], f[1], f[2], (t[0] + rf[0]) / arm, (t[1] + rf[1]) / arm, (t[2] + rf[2]) / arm};
    double n = Norm(w);
    if (!(n > 0)) continue;
    for (double& x : w) x /= n;
    auto same = std::find_if(columns.begin(), columns.end(), [&](const Column& c) {
      double dot = 0;
      for (int k = 0; k < 6; ++k) dot += c.w[k] * w[k];
      return std::fabs(dot) > 1 - 1e-9;
    });
    if (same != columns.end()) {
      same->actuators.push_back(u);
    } else {
      columns.push_back({{u}, w});
    }
  }
  std::vector<Wrench> basis;
  std::vector<int> owner;  // the column each basis vector is
  for (int j = 0; j < static_cast<int>(columns.size()); ++j) {
    std::vector<double> coef;
    double residual = Residual(basis, columns[j].w, &coef);
    if (residual > kDependent) {
      basis.push_back(columns[j].w);
      owner.push_back(j);
      continue;
    }
    std::vector<std::string> names;
    for (int i = 0; i < static_cast<int>(coef.size()); ++i) {
      if (std::fabs(coef[i]) > 1e-6) {
        names.push_back(Elem(model, mjOBJ_ACTUATOR, columns[owner[i]].actuators[0], "actuator"));
      }
    }
    names.push_back(Elem(model, mjOBJ_ACTUATOR, columns[j].actuators[0], "actuator"));
    out->push_back(WithNumbers(
        Make(L, "actuator.rank", fmt::format("{}", fmt::join(names, ", ")),
             fmt::format("the wrench of {} at the centre of mass of {} is a combination of the "
                         "others' (residual {:.2g})",
                         names.back(), Elem(model, mjOBJ_BODY, root, "body"), residual),
             fmt::format("residual > {:g}", kDependent), CheckStatus::kWarn,
             "these actuators cannot act independently: a direction they were meant to command "
             "(a multirotor's yaw, from the signs of its rotors' drag torques) is lost. Check "
             "the gear signs: a rotor ring alternates them"),
        {residual, ""}, {kDependent, ""}));
  }
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
    if (actuators.size() < 2) continue;
    size_t before = out->size();
    JudgeBody(model, root, actuators, data.get(), out);
    if (out->size() == before) {
      out->push_back(WithNumbers(
          Make(L, "actuator.rank", Elem(model, mjOBJ_BODY, root, "body"),
               fmt::format("{} actuators' wrenches at its centre of mass are independent",
                           actuators.size()),
               fmt::format("residual > {:g}", kDependent), CheckStatus::kPass,
               "each site actuator with a torque part adds a direction of its own"),
          {static_cast<double>(actuators.size()), ""}));
    }
  }
}

}  // namespace plumb::audit
