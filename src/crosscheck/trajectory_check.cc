#include "crosscheck/trajectory_check.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/geometry.h"
#include "core/joint_size.h"
#include "plumb/error.h"
#include "plumb/timing.h"

namespace plumb::internal {
namespace {

// A joint's signal: its coordinate (hinge, slide), or its position or rotation (free, ball).
struct Signal {
  int joint = 0;
  bool rotation = false;
  std::string name;
  std::string unit;
};

std::vector<Signal> JointSignals(const Model& model) {
  std::vector<Signal> out;
  for (int j = 0; j < model->njnt; ++j) {
    const std::string name = model.Name(mjOBJ_JOINT, j);
    const std::string label = name.empty() ? "#" + std::to_string(j) : name;
    const int type = model->jnt_type[j];
    if (type == mjJNT_FREE) out.push_back({j, false, "position of " + label, "m"});
    if (type == mjJNT_FREE || type == mjJNT_BALL) {
      out.push_back({j, true, "rotation of " + label, "rad"});
    } else {
      out.push_back({j, false, "qpos[" + label + "]", type == mjJNT_SLIDE ? "m" : "rad"});
    }
  }
  return out;
}

// How far apart two configurations are in one signal.
double SignalDistance(const mjModel* m, const Signal& s, const double* a, const double* b) {
  const int adr = m->jnt_qposadr[s.joint];
  const int type = m->jnt_type[s.joint];
  if (type == mjJNT_HINGE || type == mjJNT_SLIDE) return std::abs(a[adr] - b[adr]);
  if (!s.rotation)
    return std::hypot(a[adr] - b[adr], a[adr + 1] - b[adr + 1], a[adr + 2] - b[adr + 2]);
  const int q = type == mjJNT_FREE ? adr + 3 : adr;
  return RotationAngle(a + q, b + q);
}

// qpos of K runs, [rows][K * nq].
struct Runs {
  long rows = 0;
  std::vector<double> qpos;
  const double* At(const mjModel* m, long row, int k, int worlds) const {
    return &qpos[(static_cast<std::size_t>(row) * worlds + k) * m->nq];
  }
};

void RoundToFloat(mjtNum* x, int n) {
  for (int i = 0; i < n; ++i) x[i] = static_cast<float>(x[i]);
}

// CPU MuJoCo from each start with its ctrl held; `chaos` rounds the state to float32 after
// every step, as an engine that keeps it in float32 does.
Runs CpuRuns(const Model& model, const std::vector<const mjData*>& starts, long steps, bool chaos,
             const StopToken& stop) {
  const mjModel* m = model.get();
  const int worlds = static_cast<int>(starts.size());
  Runs runs;
  runs.rows = steps + 1;
  runs.qpos.assign(static_cast<std::size_t>(runs.rows) * worlds * m->nq, NAN);
  Data data(model);
  for (int k = 0; k < worlds; ++k) {
    mjData* d = data.get();
    mj_copyData(d, m, starts[k]);
    for (long row = 0; row <= steps; ++row) {
      if (row > 0) {
        if (stop.stop_requested()) throw Interrupted("plumb crosscheck: interrupted");
        mj_step(m, d);
        if (chaos) {
          RoundToFloat(d->qpos, m->nq);
          RoundToFloat(d->qvel, m->nv);
          RoundToFloat(d->act, m->na);
          RoundToFloat(d->qacc_warmstart, m->nv);
        }
      }
      std::copy(d->qpos, d->qpos + m->nq, runs.qpos.begin() + (row * worlds + k) * m->nq);
    }
  }
  return runs;
}

// The largest distance of a signal from its start over a run: its swing.
double Swing(const mjModel* m, const Signal& s, const Runs& cpu, int k, int worlds) {
  double swing = 0;
  for (long row = 1; row < cpu.rows; ++row) {
    const double d = SignalDistance(m, s, cpu.At(m, row, k, worlds), cpu.At(m, 0, k, worlds));
    if (std::isfinite(d)) swing = std::max(swing, d);
  }
  return swing;
}

// Time at which `other` first parts from `cpu` by more than `threshold`; NaN: never.
double PartingTime(const mjModel* m, const Signal& s, const Runs& cpu, const Runs& other, int k,
                   int worlds, double threshold) {
  for (long row = 1; row < cpu.rows; ++row) {
    const double d = SignalDistance(m, s, cpu.At(m, row, k, worlds), other.At(m, row, k, worlds));
    if (!(d <= threshold)) return row * m->opt.timestep;  // NaN parts too
  }
  return NAN;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? NAN : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The time each start parts at (the earliest of its signals, the run's end when none does).
std::vector<double> FirstParting(const std::vector<DivergenceTrack>& tracks, bool engine,
                                 double horizon, int worlds) {
  std::vector<double> first(worlds, horizon);
  for (const DivergenceTrack& t : tracks) {
    const std::vector<double>& times = engine ? t.engine : t.chaos;
    for (int k = 0; k < worlds; ++k) {
      if (std::isfinite(times[k])) first[k] = std::min(first[k], times[k]);
    }
  }
  return first;
}

// The signal that parts first in the engine most often (the one to name).
const DivergenceTrack* Culprit(const std::vector<DivergenceTrack>& tracks,
                               const std::vector<double>& first) {
  const DivergenceTrack* best = nullptr;
  int best_count = 0;
  for (const DivergenceTrack& t : tracks) {
    int count = 0;
    for (std::size_t k = 0; k < first.size(); ++k) count += t.engine[k] == first[k];
    if (count > best_count) best = &t, best_count = count;
  }
  return best;
}

CheckRow Verdict(const std::vector<DivergenceTrack>& tracks, const CrosscheckOptions& o,
                 double horizon, int worlds) {
  const std::vector<double> engine = FirstParting(tracks, true, horizon, worlds);
  const std::vector<double> chaos = FirstParting(tracks, false, horizon, worlds);
  const double te = Median(engine), tc = Median(chaos);
  CheckRow row;
  row.id = "trajectory";
  row.section = "trajectory";
  row.title = "open-loop runs: when the engine parts from CPU MuJoCo, against the chaos baseline";
  row.measured = {te, "s"};
  row.reference = {o.chaos_ratio * tc, "s"};
  row.threshold = true;
  row.measured_text = te >= horizon ? fmt::format("never parts within {:g} s", horizon)
                                    : fmt::format("median time to part {:.4g} s", te);
  row.reference_text = fmt::format(
      ">= {:g} x baseline's median {}", o.chaos_ratio,
      tc >= horizon ? fmt::format("(never within {:g} s)", horizon) : fmt::format("{:.4g} s", tc));
  const std::string over = fmt::format(
      "over K = {} starts, a signal parting when the runs differ "
      "by more than {:g} x max(its swing, 1 m or rad)",
      worlds, o.tol);
  if (te >= o.chaos_ratio * tc) {
    row.status = CheckStatus::kPass;
    row.explanation =
        "the engine stays with CPU MuJoCo as long as float32 rounding alone "
        "allows, " +
        over;
    return row;
  }
  row.status = CheckStatus::kFail;
  if (const DivergenceTrack* t = Culprit(tracks, engine)) {
    row.element = t->element;
    row.subject = t->signal;
  }
  row.explanation = fmt::format(
      "the engine parts from CPU MuJoCo before {:g} x the time float32 rounding alone takes ({}): "
      "a difference in the physics, not chaos; the stage check names where it starts",
      o.chaos_ratio, over);
  row.fix = "read the stages rows: the first stage that disagrees is the cause";
  return row;
}

}  // namespace

std::vector<CheckRow> TrajectoryCheck(const Model& model, const std::vector<const mjData*>& starts,
                                      EngineSession& engine, const CrosscheckOptions& options,
                                      std::vector<DivergenceTrack>* tracks) {
  const mjModel* m = model.get();
  const int worlds = static_cast<int>(starts.size());
  const long steps = StepsToReach(options.until, m->opt.timestep);
  std::vector<double> ctrl;
  ctrl.reserve(static_cast<std::size_t>(steps) * worlds * m->nu);
  for (long s = 0; s < steps; ++s) {
    for (const mjData* d : starts) ctrl.insert(ctrl.end(), d->ctrl, d->ctrl + m->nu);
  }
  const Runs cpu = CpuRuns(model, starts, steps, false, options.stop);
  const Runs chaos = CpuRuns(model, starts, steps, true, options.stop);
  EngineRollout run = engine.Rollout(model, starts, ctrl, steps, 1, {});
  Runs other;
  other.rows = run.rows;
  other.qpos = std::move(run.qpos);
  const double horizon = steps * m->opt.timestep;
  for (const Signal& s : JointSignals(model)) {
    DivergenceTrack t;
    t.signal = s.name;
    t.element = {"joint", model.Name(mjOBJ_JOINT, s.joint), s.joint};
    double swing = 0;
    for (int k = 0; k < worlds; ++k) swing = std::max(swing, Swing(m, s, cpu, k, worlds));
    t.threshold = options.tol * std::max(swing, 1.0);
    for (int k = 0; k < worlds; ++k) {
      t.engine.push_back(PartingTime(m, s, cpu, other, k, worlds, t.threshold));
      t.chaos.push_back(PartingTime(m, s, cpu, chaos, k, worlds, t.threshold));
    }
    tracks->push_back(std::move(t));
  }
  return {Verdict(*tracks, options, horizon, worlds)};
}

}  // namespace plumb::internal
