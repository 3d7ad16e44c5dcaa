#include "plumb/run.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string_view>
#include <system_error>

#include "core/derived.h"
#include "core/mujoco_compat.h"
#include "core/strings.h"
#include "plumb/error.h"
#include "plumb/timing.h"

namespace plumb {
namespace {

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
  Schedule schedule;
  // the chapter's loop `while (d->time < until) mj_step(...)` takes ceil(until/dt) steps
  schedule.steps = RequireStepsToReach(until, timestep, "until");
  if (!std::isfinite(every) || every <= 0) {
    throw ArgumentError("every", Format("%g", every),
                        "the sampling interval must be a positive number of seconds.");
  }
  schedule.stride = RequireWholeSteps(every, timestep, "every", Format("%g", every));
  return schedule;
}

namespace {

StateSnapshot SnapshotOf(const mjModel* m, const mjData* d, long step) {
  StateSnapshot s;
  s.step = step;
  s.time = d->time;
  s.qpos.assign(d->qpos, d->qpos + m->nq);
  s.qvel.assign(d->qvel, d->qvel + m->nv);
  s.act.assign(d->act, d->act + m->na);
  s.ctrl.assign(d->ctrl, d->ctrl + m->nu);
  s.integration.resize(compat::IntegrationStateSize(m));
  compat::GetIntegrationState(m, d, s.integration.data());
  return s;
}

}  // namespace

StateSnapshot Snapshot(const Model& model, const Data& data, long step) {
  return SnapshotOf(model.get(), data.get(), step);
}

void Restore(const Model& model, Data& data, const StateSnapshot& state) {
  if (static_cast<long>(state.integration.size()) != compat::IntegrationStateSize(model.get())) {
    throw ValueError(fmt::format(
        "the saved state holds {} numbers, but '{}' needs {} ({}): it was saved from another "
        "model or MuJoCo version",
        state.integration.size(), model.file(), compat::IntegrationStateSize(model.get()),
        compat::kIntegrationStateName));
  }
  compat::SetIntegrationState(model.get(), data.get(), state.integration.data());
  mj_forward(model.get(), data.get());
}

const char* IntegrationStateLayout() { return compat::kIntegrationStateName; }

std::string FatalRunProblem(const Model& model, const std::string& what) {
  // MuJoCo's message spans lines: one line here
  std::string flat;
  for (const std::string& line : Split(what, '\n')) {
    std::string part(Trim(line));
    if (!part.empty()) flat += (flat.empty() ? "" : "; ") + part;
  }
  std::string out = "MuJoCo stopped the run with a fatal error: " + flat;
  if (what.find("stackAlloc") != std::string::npos ||
      what.find("out of memory") != std::string::npos) {
    out += fmt::format(
        ". The arena of {:.3g} MB (<size memory>) is too small for this run's contacts and "
        "constraints: raise it, e.g. <size memory=\"{}M\"/>",
        static_cast<double>(compat::ArenaBytes(model.get())) / (1 << 20),
        std::max<long>(2,
                       static_cast<long>(4.0 * compat::ArenaBytes(model.get()) / (1 << 20) + 1)));
  }
  return out;
}

namespace {

// Everything a step starts from: the state, its inputs and the solver's warm start.
// Kept before every step, so a step that MuJoCo's checks abort can be examined again.
class PreStep {
 public:
  PreStep(const mjModel* m, const mjData* d) : m_(m), state_(SnapshotOf(m, d, 0)) {}

  // Copies the state `d` holds at `step`, whose time is `time`.
  void Keep(const mjData* d, long step, double time) {
    state_.step = step;
    state_.time = time;
    Copy(d->qpos, &state_.qpos);
    Copy(d->qvel, &state_.qvel);
    Copy(d->act, &state_.act);
    Copy(d->ctrl, &state_.ctrl);
    compat::GetIntegrationState(m_, d, state_.integration.data());
  }

  const StateSnapshot& state() const { return state_; }

  // The accelerations MuJoCo computes at the kept state (on a scratch mjData).
  std::vector<double> Accelerations() const {
    std::unique_ptr<mjData, void (*)(mjData*)> scratch(mj_makeData(m_), mj_deleteData);
    mjData* d = scratch.get();
    if (!d) return {};
    compat::SetIntegrationState(m_, d, state_.integration.data());
    d->time = state_.time;
    mj_forward(m_, d);
    return std::vector<double>(d->qacc, d->qacc + m_->nv);
  }

 private:
  static void Copy(const mjtNum* from, std::vector<double>* to) {
    std::copy(from, from + to->size(), to->begin());
  }

  const mjModel* m_;
  StateSnapshot state_;
};

// "dof 3 (joint 'slider')", "qpos[7] (joint 'root')", "ctrl[2] (actuator 'elbow')".
std::string ElementLabel(const Model& model, const char* array, int index) {
  const mjModel* m = model.get();
  std::string label = std::string(array) + "[" + std::to_string(index) + "]";
  auto named = [&](mjtObj type, int id, const char* kind) {
    std::string name = model.Name(type, id);
    return label + " (" + kind + " " +
           (name.empty() ? "#" + std::to_string(id) : "'" + name + "'") + ")";
  };
  std::string a = array;
  if (a == "ctrl" && index >= 0 && index < m->nu) {
    return named(mjOBJ_ACTUATOR, compat::ControlActuator(m, index), "actuator");
  }
  if (a == "qpos" && index >= 0 && index < m->nq) {
    for (int j = m->njnt - 1; j >= 0; --j) {
      if (m->jnt_qposadr[j] <= index) return named(mjOBJ_JOINT, j, "joint");
    }
  }
  if (a != "qpos" && a != "ctrl" && a != "act" && index >= 0 && index < m->nv) {
    return named(mjOBJ_JOINT, m->dof_jntid[index], "joint");
  }
  return label;
}

// The array MuJoCo's state check of kind `warning` reports an index into.
const char* CheckedArray(int warning) {
  switch (warning) {
    case mjWARN_BADQPOS:
      return "qpos";
    case mjWARN_BADQVEL:
      return "qvel";
    case mjWARN_BADCTRL:
      return "ctrl";
    default:
      return "qacc";
  }
}

}  // namespace

DerivedRefresher::DerivedRefresher(const Model& model)
    : m_(model.get()), qpos_(model->nq), warmstart_(model->nv) {}

// MuJoCo 2.x's mj_forward renormalises quaternions in qpos and rewrites the solver's warm
// start, which would change the last bits of the trajectory: both are put back, and the
// warnings it raises again are not counted twice. What mj_forward skips without a flag
// or sensor asking for it (energy, cacc, cfrc_ext, ...) is computed too.
void DerivedRefresher::operator()(Data& data) {
  mjData* d = data.get();
  mjWarningStat warnings[mjNWARNING];
  std::copy(d->warning, d->warning + mjNWARNING, warnings);
  std::copy(d->qpos, d->qpos + m_->nq, qpos_.begin());
  std::copy(d->qacc_warmstart, d->qacc_warmstart + m_->nv, warmstart_.begin());
  mj_forward(m_, d);
  CompleteDerived(m_, d);
  std::copy(qpos_.begin(), qpos_.end(), d->qpos);
  std::copy(warmstart_.begin(), warmstart_.end(), d->qacc_warmstart);
  std::copy(warnings, warnings + mjNWARNING, d->warning);
}

void RefreshDerived(const Model& model, Data& data) {
  DerivedRefresher refresh(model);
  refresh(data);
}

namespace {

// Calls the sink's End once on every path out of a run: explicitly at the end (where a
// failure to finish is the run's error), else when the run leaves by an exception.
class SinkGuard {
 public:
  explicit SinkGuard(SampleSink& sink) : sink_(sink) {}
  ~SinkGuard() {
    if (ended_) return;
    try {
      sink_.End();
    } catch (...) {
      // already leaving with the exception that stopped the run: that one is reported
    }
  }
  void End() {
    ended_ = true;
    sink_.End();
  }

 private:
  SampleSink& sink_;
  bool ended_ = false;
};

// Which MuJoCo warnings appeared, when each kind first did, and whether a state check
// (BADQPOS, BADQVEL, BADQACC, BADCTRL) reset the data in the last step.
class WarningWatch {
 public:
  WarningWatch(const mjData* d, double start_time)
      : first_step_(mjNWARNING, 0), first_time_(mjNWARNING, start_time) {
    for (int i = 0; i < mjNWARNING; ++i) seen_[i] = d->warning[i].number;
  }

  // After step `step`, which started at `step_time`: the kind of the state check that
  // fired in it, or -1.
  int Update(const mjData* d, long step, double step_time) {
    int reset_kind = -1;
    for (const compat::EnumName& w : compat::kWarnings) {
      if (d->warning[w.value].number == seen_[w.value]) continue;
      if (seen_[w.value] == 0) {
        first_step_[w.value] = step;
        first_time_[w.value] = step_time;  // MuJoCo's "Time =": the step's start
      }
      seen_[w.value] = d->warning[w.value].number;
      if (IsStateCheck(w.value) && reset_kind < 0) reset_kind = w.value;
    }
    return reset_kind;
  }

  std::vector<WarningSummary> Summaries(const mjData* d) const {
    std::vector<WarningSummary> out;
    for (const compat::EnumName& w : compat::kWarnings) {
      const mjWarningStat& stat = d->warning[w.value];
      if (stat.number == 0) continue;
      out.push_back({w.name, stat.number, first_step_[w.value], first_time_[w.value],
                     mju_warningText(w.value, stat.lastinfo)});
    }
    return out;
  }

 private:
  int seen_[mjNWARNING];
  std::vector<long> first_step_;
  std::vector<double> first_time_;
};

// MuJoCo found the state step `step` started from bad (a state check of `kind`) and reset
// the data to qpos0 in the middle of the step. Returns the reason; fills in `divergence`.
std::string MujocoReset(const Model& model, const mjData* d, int kind, long step,
                        const PreStep& before, Divergence* divergence) {
  const mjModel* m = model.get();
  const char* name = "";
  for (const compat::EnumName& w : compat::kWarnings) {
    if (w.value == kind) name = w.name;
  }
  int index = d->warning[kind].lastinfo;
  divergence->reset_by_mujoco = true;
  divergence->element = ElementLabel(model, CheckedArray(kind), index);
  divergence->bad = before.state();
  // the state it found bad is the one step `step` started from: step - 1, as its time
  divergence->bad.step = step - 1;
  divergence->bad.qacc = before.Accelerations();
  std::string value;
  if (kind == mjWARN_BADQACC && index >= 0 && index < m->nv &&
      static_cast<int>(divergence->bad.qacc.size()) == m->nv) {
    value = Format(" = %g", divergence->bad.qacc[index]);
  }
  divergence->bad.note =
      std::string("MuJoCo's state check (") + name + ") found " + divergence->element + value +
      " bad at this state and reset the data to qpos0 in the middle of the step; qpos, "
      "qvel, act and ctrl are the state it found bad, qacc the accelerations recomputed "
      "from it.";
  return std::string("MuJoCo's state check fired (") + name + "): " + divergence->element + value +
         " is NaN, Inf or beyond 1e10. MuJoCo reset the state to qpos0 and would carry on "
         "as if nothing happened; plumb stops here.";
}

// Our own checks catch a state that went bad in step `step` (ending at `time`), before
// MuJoCo's next check. Returns the reason ("" when the state is sound).
std::string BadState(const Model& model, const mjData* d, long step, double time,
                     Divergence* divergence) {
  const mjModel* m = model.get();
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
    if (bad < 0) continue;
    divergence->element = ElementLabel(model, c.name, bad);
    divergence->bad = SnapshotOf(m, d, step);
    divergence->bad.time = time;
    return divergence->element + " = " + Format("%g", c.values[bad]) +
           " is NaN, Inf or beyond 1e10";
  }
  return "";
}

// The decimal places of the shortest text that reads back as `v` (0.002: 3, 1e-05: 5);
// 17 for what has no short decimal form.
int DecimalPlaces(double v) {
  if (v == 0 || !std::isfinite(v)) return 0;
  char buffer[400];
  std::to_chars_result r =
      std::to_chars(buffer, buffer + sizeof(buffer), std::fabs(v), std::chars_format::fixed);
  if (r.ec != std::errc()) return 17;
  std::string_view text(buffer, static_cast<std::size_t>(r.ptr - buffer));
  std::size_t point = text.find('.');
  return point == std::string_view::npos ? 0 : static_cast<int>(text.size() - point - 1);
}

// `v` rounded to `decimals` places, when that is exact in a double's 53 bits; else `v`.
double RoundToDecimals(double v, int decimals) {
  if (decimals > 15) return v;
  double scale = std::pow(10.0, decimals);
  double scaled = v * scale;
  if (!(std::fabs(scaled) < 0x1p52)) return v;
  return std::round(scaled) / scale;
}

}  // namespace

namespace {

// The number of the step that ends at `time`: steps are numbered by the data's clock, so
// every run that reaches one state (run's from t = 0, audit's step response after its hold)
// names it by the same step: step n ends at t = n * dt. 0 when `time` is no whole step.
long StepAt(double time, double dt) {
  if (double n = std::round(time / dt);
      n > 0 && std::fabs(time - n * dt) <= 1e-9 * std::max(1.0, time)) {
    return static_cast<long>(n);
  }
  return 0;
}

}  // namespace

RunResult Run(const Model& model, Data& data, const RunSpec& spec, SampleSink& sink) {
  const mjModel* m = model.get();
  mjData* d = data.get();
  Schedule schedule = MakeSchedule(m->opt.timestep, spec.until, spec.every);

  // the time column reports the exact sample time, not the accumulated d->time
  std::vector<char> is_time(spec.columns.size());
  bool derived = false;
  for (std::size_t c = 0; c < spec.columns.size(); ++c) {
    is_time[c] = spec.columns[c].field == "time";
    derived = derived || spec.columns[c].role == Role::kDerived;
  }
  std::vector<double> row(spec.columns.size());
  DerivedRefresher forward(model);
  double start_time = d->time;
  auto time_at = [&](long step) {
    return start_time + static_cast<double>(step) * m->opt.timestep;
  };
  // start + step * dt has no more decimals than dt and the start: 175 * 0.002 is
  // 0.35000000000000003 in binary, printed as 0.35
  int decimals = std::max(DecimalPlaces(m->opt.timestep), DecimalPlaces(start_time));
  auto sample_time = [&](long step) { return RoundToDecimals(time_at(step), decimals); };
  auto sample = [&](long step) {
    // after mj_step, derived quantities still describe the state before the step
    if (derived) forward(data);
    double t = sample_time(step);
    for (std::size_t c = 0; c < row.size(); ++c) {
      row[c] = is_time[c] ? t : ReadValue(model, data, spec.columns[c]);
    }
    sink.Sample(row);
  };

  long first = StepAt(start_time, m->opt.timestep);
  RunResult result;
  WarningWatch warnings(d, start_time);
  PreStep before(m, d);
  sink.Begin(spec.columns);
  SinkGuard finish(sink);
  sample(0);
  result.samples = 1;
  for (long step = 1; step <= schedule.steps; ++step) {
    long label = first + step;  // the step's number by the clock
    if (spec.stop.stop_requested()) {
      throw Interrupted("interrupted at t = " + Format("%g s", time_at(step - 1)) + " (step " +
                        std::to_string(step - 1) + " of " + std::to_string(schedule.steps) + ")");
    }
    if (spec.before_step) spec.before_step(d, step);
    before.Keep(d, label - 1, time_at(step - 1));
    data.Step();
    result.steps = step;
    int reset_kind = warnings.Update(d, label, time_at(step - 1));
    Divergence divergence;
    std::string reason = reset_kind >= 0
                             ? MujocoReset(model, d, reset_kind, label, before, &divergence)
                             : BadState(model, d, label, time_at(step), &divergence);
    if (!reason.empty()) {
      result.diverged = true;
      divergence.reason = "the simulation diverged at t = " + Format("%g s", time_at(step - 1)) +
                          " (in step " + std::to_string(label) +
                          ", to t = " + Format("%g s", time_at(step)) + "): " + reason;
      divergence.last_good = before.state();
      result.divergence = std::move(divergence);
      break;
    }
    if (spec.after_step) spec.after_step(d, step);
    if (step % schedule.stride == 0) {
      sample(step);
      ++result.samples;
    }
  }
  finish.End();
  result.warnings = warnings.Summaries(d);
  return result;
}

}  // namespace plumb
