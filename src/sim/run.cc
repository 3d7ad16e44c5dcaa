#include "plumb/run.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/mujoco_compat.h"
#include "plumb/error.h"

namespace plumb {
namespace {

// Steps per interval when `interval` is a whole multiple of `timestep`, else -1.
long WholeSteps(double interval, double timestep) {
  double ratio = interval / timestep;
  double nearest = std::round(ratio);
  if (nearest < 1 || std::fabs(ratio - nearest) > 1e-9 * nearest) return -1;
  return static_cast<long>(nearest);
}

std::string Format(const char* fmt, double a, double b = 0, double c = 0) {
  char buffer[256];
  std::snprintf(buffer, sizeof(buffer), fmt, a, b, c);
  return buffer;
}

bool Bad(double x) { return !(std::fabs(x) <= compat::kMaxVal); }  // NaN compares false

// First element of `values` that is NaN, Inf or beyond MuJoCo's limit, or -1.
int FirstBad(const mjtNum* values, int n) {
  for (int i = 0; i < n; ++i) {
    if (Bad(values[i])) return i;
  }
  return -1;
}

bool IsStateCheck(int kind) {
  return kind == mjWARN_BADQPOS || kind == mjWARN_BADQVEL || kind == mjWARN_BADQACC ||
         kind == mjWARN_BADCTRL;
}

}  // namespace

Schedule MakeSchedule(double timestep, double until, double every) {
  if (!(timestep > 0) || !std::isfinite(timestep)) {
    throw ValueError("the model's timestep is " + Format("%g", timestep) +
                     "; it must be a positive number (set opt.timestep).");
  }
  if (!std::isfinite(until) || until < 0) {
    throw ValueError("--until " + Format("%g", until) +
                     ": the final time must be a finite number of seconds >= 0.");
  }
  Schedule schedule;
  // the chapter's loop `while (d->time < until) mj_step(...)` takes ceil(until/dt) steps
  double ratio = until / timestep;
  double nearest = std::round(ratio);
  schedule.steps = static_cast<long>(
      std::fabs(ratio - nearest) <= 1e-9 * std::max(1.0, nearest) ? nearest : std::ceil(ratio));
  if (!std::isfinite(every) || every <= 0) {
    throw ValueError("--every " + Format("%g", every) +
                     ": the sampling interval must be a positive number of seconds.");
  }
  schedule.stride = WholeSteps(every, timestep);
  if (schedule.stride < 0) {
    double below = std::max(1.0, std::floor(every / timestep)) * timestep;
    double above = std::ceil(every / timestep) * timestep;
    throw ValueError(
        Format("--every %g is not a whole multiple of the timestep %g", every, timestep) +
        Format(" (it is %.4g steps): samples must fall on exact steps. Use ", every / timestep) +
        Format("%.10g or %.10g, or change opt.timestep.", below, above));
  }
  return schedule;
}

StateSnapshot Snapshot(const mjModel* m, const mjData* d, long step) {
  StateSnapshot s;
  s.step = step;
  s.time = d->time;
  s.qpos.assign(d->qpos, d->qpos + m->nq);
  s.qvel.assign(d->qvel, d->qvel + m->nv);
  s.act.assign(d->act, d->act + m->na);
  s.ctrl.assign(d->ctrl, d->ctrl + m->nu);
  return s;
}

RunResult Run(const Model& model, Data& data, const RunSpec& spec, SampleSink& sink) {
  const mjModel* m = model.get();
  mjData* d = data.get();
  Schedule schedule = MakeSchedule(m->opt.timestep, spec.until, spec.every);

  // the time column reports the exact sample time, not the accumulated d->time
  std::vector<char> is_time(spec.columns.size());
  for (std::size_t c = 0; c < spec.columns.size(); ++c)
    is_time[c] = spec.columns[c].field == "time";
  std::vector<double> row(spec.columns.size());
  double start_time = d->time;
  auto sample = [&](long step) {
    double t = start_time + static_cast<double>(step) * m->opt.timestep;
    for (std::size_t c = 0; c < row.size(); ++c) {
      row[c] = is_time[c] ? t : ReadValue(model, data, spec.columns[c]);
    }
    sink.Sample(row);
  };

  RunResult result;
  int seen[mjNWARNING];
  for (int i = 0; i < mjNWARNING; ++i) seen[i] = d->warning[i].number;
  std::vector<long> first_step(mjNWARNING, 0);
  std::vector<double> first_time(mjNWARNING, d->time);
  StateSnapshot last_good = Snapshot(m, d, 0);

  sink.Begin(spec.columns);
  sample(0);
  result.samples = 1;
  for (long step = 1; step <= schedule.steps; ++step) {
    if (spec.stop && spec.stop->load(std::memory_order_relaxed)) {
      sink.End();
      throw Interrupted("interrupted at t = " + Format("%g s", d->time) + " (step " +
                        std::to_string(step - 1) + " of " + std::to_string(schedule.steps) + ")");
    }
    if (spec.before_step) spec.before_step(d, step);
    data.Step();
    result.steps = step;

    // warnings: note when each kind first appears; MuJoCo's state checks mean it reset
    std::string reason;
    for (const compat::EnumName& w : compat::kWarnings) {
      if (d->warning[w.value].number == seen[w.value]) continue;
      if (seen[w.value] == 0) {
        first_step[w.value] = step;
        first_time[w.value] = d->time;
      }
      seen[w.value] = d->warning[w.value].number;
      if (IsStateCheck(w.value) && reason.empty()) {
        reason = std::string("MuJoCo's state check fired (") + w.name +
                 "): " + mju_warningText(w.value, d->warning[w.value].lastinfo) +
                 " MuJoCo reset the state to qpos0 and carried on; plumb stops here.";
      }
    }
    // our own checks catch what MuJoCo has not reset yet
    if (reason.empty()) {
      struct Checked {
        const char* name;
        const mjtNum* values;
        int n;
      } checks[] = {{"qpos", d->qpos, static_cast<int>(m->nq)},
                    {"qvel", d->qvel, static_cast<int>(m->nv)},
                    {"act", d->act, static_cast<int>(m->na)},
                    {"qacc", d->qacc, static_cast<int>(m->nv)}};
      for (const Checked& c : checks) {
        int bad = FirstBad(c.values, c.n);
        if (bad >= 0) {
          reason = std::string(c.name) + "[" + std::to_string(bad) +
                   "] = " + Format("%g", c.values[bad]) + " is NaN, Inf or beyond 1e10";
          break;
        }
      }
    }
    if (!reason.empty()) {
      result.diverged = true;
      result.divergence = Divergence{"the simulation diverged at t = " + Format("%g s", d->time) +
                                         " (step " + std::to_string(step) + "): " + reason,
                                     std::move(last_good), Snapshot(m, d, step)};
      break;
    }
    last_good.step = step;
    last_good.time = d->time;
    std::copy(d->qpos, d->qpos + m->nq, last_good.qpos.begin());
    std::copy(d->qvel, d->qvel + m->nv, last_good.qvel.begin());
    std::copy(d->act, d->act + m->na, last_good.act.begin());
    std::copy(d->ctrl, d->ctrl + m->nu, last_good.ctrl.begin());

    if (spec.after_step) spec.after_step(d, step);
    if (step % schedule.stride == 0) {
      sample(step);
      ++result.samples;
    }
  }
  sink.End();

  for (const compat::EnumName& w : compat::kWarnings) {
    const mjWarningStat& stat = d->warning[w.value];
    if (stat.number == 0) continue;
    result.warnings.push_back({w.name, stat.number, first_step[w.value], first_time[w.value],
                               mju_warningText(w.value, stat.lastinfo)});
  }
  return result;
}

std::vector<std::string> StartHints(const Model& model, const Data& data) {
  const mjModel* m = model.get();
  const mjData* d = data.get();
  std::vector<std::string> hints;
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
  if (at_rest && in_equilibrium && undriven) {
    // suggest the first hinge or slide joint, the chapter's fix
    std::string example = "qpos[0]=0.7";
    for (int j = 0; j < m->njnt; ++j) {
      if (m->jnt_type[j] == mjJNT_HINGE || m->jnt_type[j] == mjJNT_SLIDE) {
        std::string name = model.Name(mjOBJ_JOINT, j);
        example = "qpos[" + (name.empty() ? std::to_string(m->jnt_qposadr[j]) : name) + "]=0.7";
        break;
      }
    }
    hints.push_back(
        "hint: the model starts at rest in equilibrium (qvel = 0, |qacc| < 1e-9) and nothing "
        "drives it (no control, no applied force): it will not move, and every sample will "
        "repeat the initial state. Start it away from equilibrium, e.g. --set '" +
        example + "'.");
  }
  return hints;
}

}  // namespace plumb
