#include "plumb/run.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
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

// Whether any element of `values` is NaN, Inf or beyond MuJoCo's limit: the check after every
// step, which FirstBad repeats to name the element only when it fails.
bool AnyBad(const mjtNum* values, int n) {
  bool bad = false;
  for (int i = 0; i < n; ++i) bad |= Bad(values[i]);
  return bad;
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
  for (const std::string& line : internal::Split(what, '\n')) {
    std::string part(internal::Trim(line));
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

// Steps between two states PreStep keeps when the run can be re-simulated: a copy of the whole
// state costs about 1 500 instructions for the humanoid (half a percent of its mj_step), one in
// 64 steps costs 25, and naming a divergence re-steps at most 63 steps.
constexpr long kCheckpointSteps = 64;

// Whether anything but the state decides what the next step does, so that re-stepping from an
// earlier state could not repeat the run: a before_step callback (it may write inputs each
// step), MuJoCo's global callbacks, plugins (their instance data is not in the state) and
// sleeping trees (which ones sleep is not in the state either).
bool OnlyTheStateDecides(const mjModel* m, const RunSpec& spec) {
  bool callbacks = mjcb_control || mjcb_passive || mjcb_contactfilter || mjcb_sensor ||
                   mjcb_act_dyn || mjcb_act_gain || mjcb_act_bias;
  return !spec.before_step && !callbacks && compat::PluginCount(m) == 0 &&
         !compat::SleepEnabled(m);
}

// The state each step starts from (mj_getState's mjSTATE_INTEGRATION: the state, its inputs
// and the solver's warm start), so a divergence can name the state the failing step started
// from even when MuJoCo's checks reset the data. When only the state decides the trajectory,
// it keeps every kCheckpointSteps-th state and re-steps from the last one on a scratch Data
// when asked: stepping is deterministic within one MuJoCo version, and the scratch goes
// through the states the run went through. Otherwise it keeps the state before every step.
class PreStep {
 public:
  PreStep(const Model& model, bool every_step)
      : model_(model), interval_(every_step ? 1 : kCheckpointSteps) {
    kept_.integration.resize(compat::IntegrationStateSize(model.get()));
  }

  // Before the step that starts from the state after step `step` (by the clock) at `time`.
  void Keep(const mjData* d, long step, double time) {
    if (step < next_) return;
    next_ = step + interval_;
    kept_.step = step;
    kept_.time = time;
    compat::GetIntegrationState(model_.get(), d, kept_.integration.data());
  }

  // The state after step `step` at `time`: the step after it failed, leaving `d` behind (the
  // bad state, or the data MuJoCo reset when its state check of kind `reset_kind` fired, else
  // -1). Re-steps from the last kept state, then takes the failing step once more to check
  // that it fails the same way; says so in the state's note when it does not.
  StateSnapshot Before(long step, double time, const mjData* d, int reset_kind) const {
    const mjModel* m = model_.get();
    Data scratch(model_);
    mjData* s = scratch.get();
    compat::SetIntegrationState(m, s, kept_.integration.data());
    // the run has told its warnings: re-stepping tells no one again
    for (mjWarningStat& w : s->warning) w.number = 1;
    for (long n = kept_.step; n < step; ++n) mj_step(m, s);
    StateSnapshot state = SnapshotOf(m, s, step);
    state.time = time;
    // a state check that fires resets the data and its warnings, then records itself
    if (reset_kind >= 0) s->warning[reset_kind].lastinfo = -1;
    mj_step(m, s);
    bool repeated = reset_kind >= 0 ? s->warning[reset_kind].number > 0 &&
                                          s->warning[reset_kind].lastinfo ==
                                              d->warning[reset_kind].lastinfo
                                    : SameState(m, s, d);
    if (!repeated) {
      state.note = fmt::format(
          "re-stepped from the state after step {}; stepping it again did not repeat the "
          "failing step exactly, so this state may differ from the run's",
          kept_.step);
    }
    return state;
  }

  // The accelerations MuJoCo computes at `state` (on a scratch Data).
  std::vector<double> Accelerations(const StateSnapshot& state) const {
    const mjModel* m = model_.get();
    std::unique_ptr<mjData, void (*)(mjData*)> scratch(mj_makeData(m), mj_deleteData);
    mjData* d = scratch.get();
    if (!d) return {};
    compat::SetIntegrationState(m, d, state.integration.data());
    d->time = state.time;
    mj_forward(m, d);
    return std::vector<double>(d->qacc, d->qacc + m->nv);
  }

 private:
  // Bit for bit, NaN payloads included.
  bool SameState(const mjModel* m, const mjData* a, const mjData* b) const {
    std::vector<double> x(kept_.integration.size()), y(x.size());
    compat::GetIntegrationState(m, a, x.data());
    compat::GetIntegrationState(m, b, y.data());
    return std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0;
  }

  const Model& model_;
  long interval_;
  long next_ = std::numeric_limits<long>::min();
  StateSnapshot kept_;
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
  internal::CompleteDerived(m_, d);
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

// MuJoCo found `start`, the state a step started from, bad (a state check of `kind`) and reset
// the data to qpos0 in the middle of the step. Returns the reason; fills in `divergence`.
std::string MujocoReset(const Model& model, const mjData* d, int kind, const StateSnapshot& start,
                        const PreStep& before, Divergence* divergence) {
  const mjModel* m = model.get();
  const char* name = "";
  for (const compat::EnumName& w : compat::kWarnings) {
    if (w.value == kind) name = w.name;
  }
  int index = d->warning[kind].lastinfo;
  divergence->reset_by_mujoco = true;
  divergence->element = ElementLabel(model, CheckedArray(kind), index);
  divergence->bad = start;
  divergence->bad.qacc = before.Accelerations(start);
  std::string value;
  if (kind == mjWARN_BADQACC && index >= 0 && index < m->nv &&
      static_cast<int>(divergence->bad.qacc.size()) == m->nv) {
    value = Format(" = %g", divergence->bad.qacc[index]);
  }
  divergence->bad.note =
      std::string("MuJoCo's state check (") + name + ") found " + divergence->element + value +
      " bad at this state and reset the data to qpos0 in the middle of the step; qpos, "
      "qvel, act and ctrl are the state it found bad, qacc the accelerations recomputed "
      "from it." +
      (start.note.empty() ? "" : " It was " + start.note + ".");
  return std::string("MuJoCo's state check fired (") + name + "): " + divergence->element + value +
         " is NaN, Inf or beyond 1e10. MuJoCo reset the state to qpos0 and would carry on "
         "as if nothing happened; plumb stops here.";
}

// The first element of qpos, qvel, act or qacc that is NaN, Inf or beyond MuJoCo's limit
// (index -1 when the state is sound).
struct BadElement {
  const char* array = "";
  int index = -1;
  double value = 0;
};

BadElement FindBad(const mjModel* m, const mjData* d) {
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
    if (bad >= 0) return {c.name, bad, c.values[bad]};
  }
  return {};
}

// Our own checks caught `bad`, an element of the state that went bad in step `step` (ending at
// `time`), before MuJoCo's next check. Returns the reason; fills in `divergence`.
std::string BadState(const Model& model, const mjData* d, const BadElement& bad, long step,
                     double time, Divergence* divergence) {
  divergence->element = ElementLabel(model, bad.array, bad.index);
  divergence->bad = SnapshotOf(model.get(), d, step);
  divergence->bad.time = time;
  return divergence->element + " = " + Format("%g", bad.value) + " is NaN, Inf or beyond 1e10";
}

// Why step `step` (by the clock, from `start` to `end` s) failed, with the state it started
// from and the bad state. `reset_kind` is the kind of MuJoCo's state check that reset the
// data in that step, or -1 when plumb's checks found `d` bad.
Divergence Diverged(const Model& model, const mjData* d, int reset_kind, long step, double start,
                    double end, const PreStep& before) {
  Divergence divergence;
  divergence.last_good = before.Before(step - 1, start, d, reset_kind);
  std::string reason =
      reset_kind >= 0
          ? MujocoReset(model, d, reset_kind, divergence.last_good, before, &divergence)
          : BadState(model, d, FindBad(model.get(), d), step, end, &divergence);
  divergence.reason = "the simulation diverged at t = " + Format("%g s", start) + " (in step " +
                      std::to_string(step) + ", to t = " + Format("%g s", end) + "): " + reason;
  return divergence;
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

  // the time column reports the exact sample time, not the accumulated d->time, unless the
  // spec asks for the clock
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
    double t = spec.clock_time ? d->time : sample_time(step);
    for (std::size_t c = 0; c < row.size(); ++c) {
      row[c] = is_time[c] ? t : ReadValue(model, data, spec.columns[c]);
    }
    sink.Sample(row);
  };

  long first = StepAt(start_time, m->opt.timestep);
  RunResult result;
  WarningWatch warnings(d, start_time);
  PreStep before(model, !OnlyTheStateDecides(m, spec));
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
    if (reset_kind >= 0 || AnyBad(d->qpos, m->nq) || AnyBad(d->qvel, m->nv) ||
        AnyBad(d->act, m->na) || AnyBad(d->qacc, m->nv)) {
      result.diverged = true;
      result.divergence =
          Diverged(model, d, reset_kind, label, time_at(step - 1), time_at(step), before);
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
