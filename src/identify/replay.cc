// Replaying a log (plumb/replay.h).

#include "plumb/replay.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "core/fields.h"
#include "plumb/error.h"
#include "plumb/run.h"

namespace plumb {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

// The index of the first sample at or after `t` (times within a millionth of a step count
// as equal: a log's times went through decimal text).
std::size_t FirstAtOrAfter(const std::vector<double>& times, double t, double tolerance) {
  return std::lower_bound(times.begin(), times.end(), t - tolerance) - times.begin();
}

// An input held from sample to sample, written straight into the model's array.
class HeldInput {
 public:
  HeldInput(const LogSignal& signal, const mjModel* m, mjData* d, double tolerance)
      : signal_(signal), tolerance_(tolerance) {
    const internal::FieldInfo& field = internal::Fields()[signal.path.field_index];
    target_ = static_cast<mjtNum*>(const_cast<void*>(internal::FieldBase(field, m, d))) +
              signal.path.first;
  }
  // Writes the value logged last at or before `t` (the first value before the first sample).
  void Apply(double t) {
    const std::vector<double>& times = signal_.time;
    if (next_ > 0 && times[next_ - 1] > t + tolerance_) next_ = 0;  // went back: a new window
    while (next_ < times.size() && times[next_] <= t + tolerance_) ++next_;
    *target_ = signal_.value[next_ == 0 ? 0 : next_ - 1];
  }

 private:
  const LogSignal& signal_;
  double tolerance_;
  mjtNum* target_;
  std::size_t next_ = 0;
};

// For each ball or free joint whose four quaternion elements are all among `state`, their
// indices in `state` (w, x, y, z).
std::vector<std::array<std::size_t, 4>> LoggedQuaternions(
    const mjModel* m, const std::vector<const LogSignal*>& state) {
  std::vector<std::array<std::size_t, 4>> groups;
  for (int j = 0; j < m->njnt; ++j) {
    int type = m->jnt_type[j];
    if (type != mjJNT_FREE && type != mjJNT_BALL) continue;
    int adr = m->jnt_qposadr[j] + (type == mjJNT_FREE ? 3 : 0);
    std::array<std::size_t, 4> group{};
    int found = 0;
    for (std::size_t k = 0; k < state.size(); ++k) {
      const Path& p = state[k]->path;
      if (p.field == "qpos" && p.first >= adr && p.first < adr + 4) {
        group[p.first - adr] = k;
        ++found;
      }
    }
    if (found == 4) groups.push_back(group);
  }
  return groups;
}

class Replayer {
 public:
  Replayer(const Model& model, Data& data, const RobotLog& log, const ReplayOptions& options,
           const std::vector<double>* offsets)
      : model_(model),
        m_(model.get()),
        data_(data),
        log_(log),
        options_(options),
        offsets_(offsets),
        dt_(m_->opt.timestep),
        tolerance_(1e-6 * dt_),
        refresh_(model),
        state_(StateSignals(log)),
        quaternions_(LoggedQuaternions(m_, state_)) {
    for (const LogSignal& s : log.measured) {
      if (s.path.role == Role::kDerived) needs_refresh_ = true;
    }
    for (const LogSignal& s : log.inputs) inputs_.emplace_back(s, m_, data.get(), tolerance_);
  }

  Simulated Run() {
    out_.values.resize(log_.measured.size());
    for (std::size_t i = 0; i < log_.measured.size(); ++i) {
      out_.values[i].assign(log_.measured[i].time.size(), kNan);
    }
    std::vector<double> starts = WindowStarts(model_, log_, options_);
    for (std::size_t w = 0; w < starts.size(); ++w) {
      double until = w + 1 < starts.size() ? starts[w + 1] : INFINITY;
      window_ = w;
      RunWindow(starts[w], until, w + 1 == starts.size());
    }
    return std::move(out_);
  }

 private:
  void StartState(double t) {
    mjData* d = data_.get();
    mj_resetData(m_, d);
    std::vector<std::size_t> at(state_.size());
    for (std::size_t j = 0; j < state_.size(); ++j) {
      const LogSignal* s = state_[j];
      at[j] = FirstAtOrAfter(s->time, t, tolerance_);
      if (at[j] >= s->time.size()) continue;
      mjtNum* array = s->path.field == "qpos" ? d->qpos : d->qvel;
      array[s->path.first] = s->value[at[j]];
    }
    if (offsets_ != nullptr) {
      // each quaternion's largest component at this start takes no offset
      std::vector<bool> fixed(state_.size(), false);
      for (const auto& group : quaternions_) {
        std::size_t largest = group[0];
        for (std::size_t k : group) {
          if (std::fabs(d->qpos[state_[k]->path.first]) >
              std::fabs(d->qpos[state_[largest]->path.first])) {
            largest = k;
          }
        }
        fixed[largest] = true;
      }
      std::size_t per_window = state_.size() - quaternions_.size(), next = 0;
      for (std::size_t j = 0; j < state_.size(); ++j) {
        if (fixed[j]) continue;
        double offset = (*offsets_)[window_ * per_window + next++];
        if (at[j] >= state_[j]->time.size()) continue;
        (state_[j]->path.field == "qpos" ? d->qpos : d->qvel)[state_[j]->path.first] += offset;
      }
      if (!quaternions_.empty()) mj_normalizeQuat(m_, d->qpos);
    }
    d->time = t - log_.start;
  }

  // The simulated value of every measured signal at the state `data_` holds now.
  void Read(std::vector<double>* values) {
    if (needs_refresh_) refresh_(data_);
    for (std::size_t i = 0; i < log_.measured.size(); ++i) {
      (*values)[i] = ReadValue(model_, data_, log_.measured[i].path);
    }
  }

  bool Diverged() const {
    const mjData* d = data_.get();
    if (d->warning[mjWARN_BADQACC].number > 0) return true;
    for (int i = 0; i < m_->nq; ++i) {
      if (!std::isfinite(d->qpos[i])) return true;
    }
    for (int i = 0; i < m_->nv; ++i) {
      if (!std::isfinite(d->qvel[i])) return true;
    }
    return false;
  }

  // Simulates from `start` and fills every measured sample in [start, until) (the last window
  // also takes samples at the log's end).
  void RunWindow(double start, double until, bool last) {
    StartState(start);
    std::size_t n = log_.measured.size();
    std::vector<std::size_t> next(n), stop(n);
    double latest = start;  // the last time (in simulation terms) any sample asks for
    for (std::size_t i = 0; i < n; ++i) {
      const std::vector<double>& times = log_.measured[i].time;
      next[i] = FirstAtOrAfter(times, start, tolerance_);
      stop[i] = last ? times.size() : FirstAtOrAfter(times, until, tolerance_);
      if (stop[i] > next[i]) latest = std::max(latest, times[stop[i] - 1] - options_.sensor_delay);
    }
    std::vector<double> cur(n), prev(n);  // the state at t0, and at the step before
    Read(&cur);
    mjData* d = data_.get();
    for (long k = 0;; ++k) {
      double t0 = start + k * dt_, t1 = start + (k + 1) * dt_;
      // samples up to t0 are settled by the state at t0 (and the one before it)
      for (std::size_t i = 0; i < n; ++i) {
        const LogSignal& s = log_.measured[i];
        while (next[i] < stop[i]) {
          double at = std::max(start, s.time[next[i]] - options_.sensor_delay);
          if (at > t0 + tolerance_) break;
          double w = k == 0 ? 0 : std::clamp((at - (t0 - dt_)) / dt_, 0.0, 1.0);
          out_.values[i][next[i]] =
              k == 0 || w >= 1 - 1e-12 ? cur[i] : prev[i] * (1 - w) + cur[i] * w;
          ++next[i];
        }
      }
      if (t0 > latest + tolerance_) break;
      for (HeldInput& input : inputs_) input.Apply(t0 - options_.input_delay);
      prev.swap(cur);
      if (options_.stop.stop_requested()) {
        throw Interrupted(fmt::format("the replay stopped at t = {:.6g} s of the log", t0));
      }
      mj_step(m_, d);
      d->time = t1 - log_.start;
      if (Diverged()) {
        if (!out_.diverged) {
          out_.diverged = true;
          out_.problem = fmt::format("the simulation diverged at t = {:.6g} s of the log", t1);
        }
        return;  // this window's remaining samples stay NaN
      }
      Read(&cur);
    }
  }

  const Model& model_;
  const mjModel* m_;
  Data& data_;
  const RobotLog& log_;
  const ReplayOptions& options_;
  const std::vector<double>* offsets_;
  double dt_, tolerance_;
  DerivedRefresher refresh_;
  bool needs_refresh_ = false;
  std::vector<const LogSignal*> state_;
  std::vector<std::array<std::size_t, 4>> quaternions_;  // logged whole, indices in state_
  std::size_t window_ = 0;
  std::vector<HeldInput> inputs_;
  Simulated out_;
};

}  // namespace

std::vector<const LogSignal*> StateSignals(const RobotLog& log) {
  std::vector<const LogSignal*> state;
  for (const LogSignal& s : log.measured) {
    if (s.path.field == "qpos" || s.path.field == "qvel") state.push_back(&s);
  }
  return state;
}

std::vector<std::vector<std::size_t>> SampleWindows(const Model& model, const RobotLog& log,
                                                    const ReplayOptions& options) {
  std::vector<double> starts = WindowStarts(model, log, options);
  double tolerance = 1e-6 * model->opt.timestep;
  std::vector<std::vector<std::size_t>> windows;
  for (const LogSignal& s : log.measured) {
    windows.emplace_back(s.time.size(), 0);
    // as Replayer::RunWindow takes them: window w from its start up to the next one's
    for (std::size_t w = 1; w < starts.size(); ++w) {
      for (std::size_t k = FirstAtOrAfter(s.time, starts[w], tolerance); k < s.time.size(); ++k) {
        windows.back()[k] = w;
      }
    }
  }
  return windows;
}

std::size_t StartOffsetsPerWindow(const Model& model, const RobotLog& log) {
  std::vector<const LogSignal*> state = StateSignals(log);
  return state.size() - LoggedQuaternions(model.get(), state).size();
}

std::vector<double> WindowStarts(const Model& model, const RobotLog& log,
                                 const ReplayOptions& options) {
  const mjModel* m = model.get();
  double tolerance = 1e-6 * m->opt.timestep;
  std::vector<double> starts = {log.start};
  if (options.window <= 0) return starts;
  std::vector<const LogSignal*> state = StateSignals(log);
  if (static_cast<int>(state.size()) < m->nq + m->nv) {
    throw ArgumentError(
        "window", fmt::format("{:g}", options.window),
        fmt::format("a window restarts the simulation from the logged state, but {} holds {} of "
                    "the model's {} qpos and qvel elements: log them all, or replay without "
                    "windows",
                    log.source, state.size(), m->nq + m->nv));
  }
  if (options.window < m->opt.timestep - tolerance) {
    // shorter windows would each restart before a step: and there would be no end to them
    throw ArgumentError("window", fmt::format("{:g}", options.window),
                        fmt::format("a window must be at least one timestep of the model ({:g} "
                                    "s) long",
                                    m->opt.timestep));
  }
  const std::vector<double>& times = state.front()->time;
  for (long j = 1;; ++j) {
    double at = log.start + j * options.window;
    std::size_t i = FirstAtOrAfter(times, at, tolerance);
    if (i >= times.size() || times[i] >= log.end - tolerance) break;
    if (times[i] > starts.back() + tolerance) starts.push_back(times[i]);
  }
  return starts;
}

Simulated Simulate(const Model& model, Data& data, const RobotLog& log,
                   const ReplayOptions& options, const std::vector<double>* start_offsets) {
  return Replayer(model, data, log, options, start_offsets).Run();
}

double NoiseFromDifferences(const std::vector<double>& v) {
  std::vector<double> d;
  for (std::size_t k = 3; k < v.size(); ++k) {
    d.push_back(std::fabs(v[k] - 3 * v[k - 1] + 3 * v[k - 2] - v[k - 3]));
  }
  if (d.size() >= 8) {
    std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
    double sigma = d[d.size() / 2] / 0.6744897501960817 / std::sqrt(20.0);
    if (sigma > 0 && std::isfinite(sigma)) return sigma;
  }
  double mean = 0, spread = 0;
  for (double x : v) mean += x / v.size();
  for (double x : v) spread += (x - mean) * (x - mean) / v.size();
  return spread > 0 ? std::sqrt(spread) : 1.0;
}

std::vector<SignalFit> CompareWithLog(const RobotLog& log, const Simulated& simulated) {
  std::vector<SignalFit> fits;
  for (std::size_t i = 0; i < log.measured.size(); ++i) {
    const LogSignal& s = log.measured[i];
    SignalFit f;
    f.column = s.column;
    f.path = s.path.text;
    f.samples = static_cast<long>(s.value.size());
    double mean = 0;
    for (double v : s.value) mean += v / f.samples;
    double error2 = 0, spread2 = 0;
    for (std::size_t k = 0; k < s.value.size(); ++k) {
      double e = simulated.values[i][k] - s.value[k];
      if (std::isnan(e)) e = INFINITY;
      error2 += e * e;
      spread2 += (s.value[k] - mean) * (s.value[k] - mean);
      if (!(std::fabs(e) <= f.max_abs)) {
        f.max_abs = std::fabs(e);
        f.worst_time = s.time[k];
      }
    }
    f.rms = std::sqrt(error2 / f.samples);
    f.fit = spread2 > 0 ? 100 * (1 - std::sqrt(error2 / spread2)) : (error2 == 0 ? 100 : -INFINITY);
    f.noise = NoiseFromDifferences(s.value);
    f.noise_fit = spread2 > 0 ? 100 * (1 - f.noise / std::sqrt(spread2 / f.samples)) : 100;
    f.spread = std::sqrt(spread2 / f.samples);
    double margin = kFitNoiseMargin * f.noise;
    double beyond = std::sqrt(std::max(0.0, f.rms * f.rms - margin * margin));
    f.fit_beyond_noise =
        f.spread > 0 ? 100 * (1 - beyond / f.spread) : (beyond == 0 ? 100 : -INFINITY);
    fits.push_back(f);
  }
  return fits;
}

double OverallFit(const std::vector<SignalFit>& signals) {
  double beyond = 0, spread = 0;
  for (const SignalFit& f : signals) {
    double noise2 = f.noise * f.noise;
    if (!(noise2 > 0)) noise2 = 1;  // NoiseFromDifferences gives none: the signal's own units
    double margin2 = kFitNoiseMargin * kFitNoiseMargin * noise2;
    beyond += f.samples * std::max(0.0, f.rms * f.rms - margin2) / noise2;
    spread += f.samples * f.spread * f.spread / noise2;
  }
  if (std::isnan(beyond)) return -INFINITY;  // a diverged replay
  if (!(spread > 0)) return beyond == 0 ? 100 : -INFINITY;
  return 100 * (1 - std::sqrt(beyond / spread));
}

ReplayResult Replay(const Model& model, const RobotLog& log, const ReplayOptions& options) {
  Data data(model);
  ReplayResult r;
  r.simulated = Simulate(model, data, log, options);
  r.signals = CompareWithLog(log, r.simulated);
  r.fit = OverallFit(r.signals);
  const mjModel* m = model.get();
  int held = 0;
  for (const LogSignal& s : log.measured) held += s.path.field == "qpos" || s.path.field == "qvel";
  if (held < m->nq + m->nv) {
    r.notes.push_back(fmt::format(
        "the log holds {} of the model's {} qpos and qvel elements: the others start from "
        "the model's qpos0 and zero velocity",
        held, m->nq + m->nv));
  }
  if (m->nu > 0 && log.inputs.empty()) {
    r.notes.push_back(fmt::format(
        "the model has {} control(s) but the log holds no inputs (ctrl columns): every ctrl "
        "stays 0, so the fit measures an unactuated model; log the commands the robot got "
        "(plumb run writes ctrl columns by default)",
        m->nu));
  }
  return r;
}

void CheckReplayOptions(const ReplayOptions& options) {
  if (!(options.window >= 0 && std::isfinite(options.window))) {
    throw ArgumentError("window", fmt::format("{:g}", options.window),
                        "give a positive number of seconds (or leave it out for one run from "
                        "the start)");
  }
  for (const auto& [name, delay] :
       {std::pair<const char*, double>{"input_delay", options.input_delay},
        {"sensor_delay", options.sensor_delay}}) {
    if (!std::isfinite(delay)) {
      throw ArgumentError(name, fmt::format("{:g}", delay), "give a finite number of seconds");
    }
  }
}

void ApplyParameterAssignments(Model& model, const std::vector<std::string>& sets) {
  std::vector<Assignment> edits;
  for (const std::string& text : sets) {
    Assignment a = ParseAssignment(model, text);
    if (a.path.role != Role::kParameter) {
      throw ArgumentError(
          "set", Quoted(text),
          fmt::format("{} is {} {}; here the state and the inputs come from the log, and "
                      "assignments take model parameters (dof_damping[...], body_mass[...], "
                      "opt.timestep, ...)",
                      a.path.text, a.path.role == Role::kInput ? "an" : "a",
                      RoleName(a.path.role)));
    }
    edits.push_back(std::move(a));
  }
  Data scratch(model);
  if (WriteParameters(model, scratch, edits)) mj_setConst(model.get_mutable(), scratch.get());
}

}  // namespace plumb
