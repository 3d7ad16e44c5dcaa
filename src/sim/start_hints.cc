// The chapter's common-error table as advice before a run: today, a system at rest in
// equilibrium with nothing driving it, and bodies that start asleep.

#include "sim/start_hints.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>

#include "core/mujoco_compat.h"
#include "plumb/path.h"
#include "plumb/run.h"
#include "plumb/sleep.h"

namespace plumb::internal {
namespace {

// An assignment that takes the model out of the equilibrium `data` holds, found by trying
// it: the first hinge or slide coordinate whose offset (0.7 rad, 0.1 m, kept inside the
// joint's range) makes some |qacc| exceed 1e-3, so following the advice always moves
// the model (a slider under a balanced pole does not, the pole's hinge does). When no
// offset does (no gravity, no springs), a velocity.
void EquilibriumBreaker(const Model& model, const Data& data, StartHint* hint) {
  const mjModel* m = model.get();
  Data probe = data.Clone();
  auto label = [&](int j, int adr) {
    std::string name = model.Name(mjOBJ_JOINT, j);
    return name.empty() ? std::to_string(adr) : name;
  };
  int first_joint = -1;
  for (int j = 0; j < m->njnt; ++j) {
    int type = m->jnt_type[j];
    if (type != mjJNT_HINGE && type != mjJNT_SLIDE) continue;
    if (first_joint < 0) first_joint = j;
    int adr = m->jnt_qposadr[j];
    double now = data->qpos[adr];
    double value = now + (type == mjJNT_HINGE ? 0.7 : 0.1);
    if (m->jnt_limited[j]) {
      const mjtNum* range = m->jnt_range + 2 * j;
      if (value > range[1]) {
        value = range[1] > now ? now + 0.5 * (range[1] - now) : now - 0.5 * (now - range[0]);
      }
    }
    if (value == now) continue;
    mj_copyData(probe.get(), m, data.get());
    probe->qpos[adr] = value;
    mj_forward(m, probe.get());
    double largest = 0;
    for (int i = 0; i < m->nv; ++i) largest = std::max(largest, std::fabs(probe->qacc[i]));
    if (largest > 1e-3) {
      char text[64];
      std::snprintf(text, sizeof(text), "%.6g", value);
      hint->advice = "Start it away from equilibrium";
      hint->assignment = "qpos[" + label(j, adr) + "]=" + text;
      hint->evidence = "plumb tried it: it gives |qacc| up to " + fmt::format("{:.3g}", largest);
      return;
    }
  }
  // a velocity of the first joint's first dof (an element, also of a free or ball joint)
  int j = first_joint >= 0 ? first_joint : 0;
  std::string dof = label(j, m->jnt_dofadr[j]);
  bool block = m->jnt_type[j] == mjJNT_FREE || m->jnt_type[j] == mjJNT_BALL;
  if (block && !model.Name(mjOBJ_JOINT, j).empty()) dof += "][0";
  hint->advice =
      "No single offset of a hinge or slide makes it accelerate (no gravity or springs act on "
      "it): give it a velocity instead";
  hint->assignment = "qvel[" + dof + "]=1";
}

}  // namespace

std::vector<StartHint> StartHints(const Model& model, const Data& data) {
  const mjModel* m = model.get();
  const mjData* d = data.get();
  std::vector<StartHint> hints;
  if (m->nv == 0) return hints;
  auto all_below = [](const mjtNum* v, int n, double limit) {
    for (int i = 0; i < n; ++i) {
      if (!(std::fabs(v[i]) <= limit)) return false;
    }
    return true;
  };
  bool at_rest = all_below(d->qvel, m->nv, 0.0);
  bool in_equilibrium = all_below(d->qacc, m->nv, 1e-9);
  bool undriven = all_below(d->ctrl, m->nu, 0.0) && all_below(d->qfrc_applied, m->nv, 0.0) &&
                  all_below(d->xfrc_applied, 6 * m->nbody, 0.0) &&
                  all_below(d->qfrc_actuator, m->nv, 0.0);
  SleepingStart asleep = FindSleepingStart(model, data);
  if (!asleep.empty()) {
    StartHint hint;
    bool one = asleep.bodies.size() == 1;
    hint.problem = asleep.Describe() + fmt::format(
                                           ": {} still, whatever drives {}, until something "
                                           "touches {}.",
                                           one ? "it stays" : "they stay", one ? "it" : "them",
                                           one ? "it" : "them");
    hint.advice = "To see them move from the start, turn sleep off";
    hint.assignment = "opt.enableflags.sleep=0";  // the other flags kept
    hints.push_back(hint);
  } else if (at_rest && in_equilibrium && undriven) {
    StartHint hint;
    hint.problem =
        "the model starts at rest in equilibrium (qvel = 0, |qacc| < 1e-9) and nothing drives "
        "it (no control, no applied force): it will not move, and every sample will repeat the "
        "initial state.";
    EquilibriumBreaker(model, data, &hint);
    hints.push_back(hint);
  }
  return hints;
}

void AddStartHints(const Model& model, const Data& data, const std::string& argument,
                   Notices* notices) {
  if (notices == nullptr) return;
  for (const StartHint& hint : StartHints(model, data)) {
    std::string evidence = hint.evidence.empty() ? "" : " (" + hint.evidence + ")";
    notices->Hint(NoticeTopic::kStart, "",
                  fmt::format("{} {}, e.g. {} '{}'{}.", hint.problem, hint.advice, argument,
                              hint.assignment, evidence));
  }
}

}  // namespace plumb::internal
