#include "plumb/rollout.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <optional>

#include "core/mujoco_compat.h"
#include "core/strings.h"
#include "core/worker_pool.h"
#include "plumb/analytic.h"
#include "plumb/error.h"
#include "plumb/random.h"
#include "plumb/run.h"
#include "plumb/timing.h"
#include "scenario/metric_probe.h"

namespace plumb {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

double Distribution::Apply(double nominal, double u, double z) const {
  double draw = 0;
  switch (kind) {
    case Kind::kUniform:
      draw = a + (b - a) * u;
      break;
    case Kind::kNormal:
      draw = a + b * z;
      break;
    case Kind::kLogUniform:
      draw = std::exp(std::log(a) + (std::log(b) - std::log(a)) * u);
      break;
  }
  switch (mode) {
    case Mode::kAbsolute:
      return draw;
    case Mode::kScale:
      return nominal * draw;
    case Mode::kOffset:
      return nominal + draw;
  }
  return draw;
}

Distribution ParseDistribution(std::string_view raw) {
  Distribution d;
  d.text = std::string(internal::Trim(raw));
  std::string_view s = internal::Trim(raw);
  auto bad = [&](const std::string& why) {
    return ValueError("distribution '" + d.text + "': " + why +
                      ". Use U(a,b), N(mu,sigma), LogU(a,b), optionally prefixed * (scale the "
                      "nominal value) or + (offset it), e.g. *U(0.9,1.1) or +N(0,0.01).");
  };
  if (!s.empty() && (s.front() == '*' || s.front() == '+')) {
    d.mode = s.front() == '*' ? Distribution::Mode::kScale : Distribution::Mode::kOffset;
    s = internal::Trim(s.substr(1));
  }
  std::size_t open = s.find('(');
  if (open == std::string_view::npos || s.back() != ')') throw bad("expected NAME(a,b)");
  std::string_view name = internal::Trim(s.substr(0, open));
  if (name == "U") {
    d.kind = Distribution::Kind::kUniform;
  } else if (name == "N") {
    d.kind = Distribution::Kind::kNormal;
  } else if (name == "LogU") {
    d.kind = Distribution::Kind::kLogUniform;
  } else {
    throw bad("unknown distribution '" + std::string(name) + "'");
  }
  std::vector<std::string> args = internal::Split(s.substr(open + 1, s.size() - open - 2), ',');
  std::optional<double> a = args.size() == 2 ? internal::ParseNumber(args[0]) : std::nullopt;
  std::optional<double> b = args.size() == 2 ? internal::ParseNumber(args[1]) : std::nullopt;
  if (!a || !b || !std::isfinite(*a) || !std::isfinite(*b)) throw bad("two finite numbers needed");
  d.a = *a;
  d.b = *b;
  if (d.kind == Distribution::Kind::kNormal && d.b < 0) throw bad("sigma must be >= 0");
  if (d.kind != Distribution::Kind::kNormal && !(d.a <= d.b)) throw bad("needs a <= b");
  if (d.kind == Distribution::Kind::kLogUniform && !(d.a > 0)) throw bad("LogU needs a > 0");
  return d;
}

Randomization ParseRandomization(const Model& model, std::string_view text) {
  auto [path_text, dist_text] =
      SplitAssignment(text, "randomize", "PATH=DIST, e.g. 'body_mass[*]=*U(0.9,1.1)'");
  Randomization r;
  r.text = std::string(text);
  r.dist = ParseDistribution(dist_text);
  for (const Path& p : ExpandPath(model, path_text)) {
    if (!p.writable) {
      ParseAssignment(model, p.text + "=0");  // throws the reason it cannot be set
    }
    for (Path& one : ScalarPaths(p)) r.paths.push_back(std::move(one));
  }
  return r;
}

std::vector<std::string> ParameterNames(const RolloutSpec& spec) {
  std::vector<std::string> names;
  for (const Randomization& r : spec.randomize) {
    for (const Path& p : r.paths) names.push_back(p.text);
  }
  return names;
}

namespace {

std::size_t ParameterCount(const RolloutSpec& spec) {
  std::size_t n = 0;
  for (const Randomization& r : spec.randomize) n += r.paths.size();
  return n;
}

// The random key of actuator j's control noise: far above any parameter's key.
constexpr std::uint32_t kCtrlNoiseKey = 1u << 31;

// One rollout on a worker: its draws, its run, its metrics; the worker's model is put back
// to the nominal one afterwards.
class OneRollout {
 public:
  OneRollout(const Model& nominal, internal::WorkerPool::Worker& w, const RolloutSpec& spec,
             long index, const StopToken& stop)
      : nominal_(nominal),
        w_(w),
        spec_(spec),
        index_(index),
        stop_(stop),
        // a drawn body_mass rescales its body's inertia (WriteValues): kept to be put back
        inertia_(w.work->body_inertia, w.work->body_inertia + 3 * w.work->nbody) {
    out_.index = index;
    out_.params.assign(ParameterCount(spec), kNaN);
  }

  RolloutResult Run(bool energy) {
    mjModel* m = w_.work.get_mutable();
    // parameters: the user's, then this rollout's draws from the nominal values
    bool arrays_changed = WriteParameters(w_.work, w_.data, spec_.sets);
    if (const Randomization* bad = DrawParameters()) return Refuse(*bad);  // nothing written
    arrays_changed = WriteParameterDraws() || arrays_changed;
    if (arrays_changed) mj_setConst(m, w_.data.get());
    if (energy) m->opt.enableflags |= mjENBL_ENERGY;
    compat::ResetState(m, w_.data.get());
    WriteState(w_.work, w_.data, spec_.sets);
    // state draws start from the state the user set
    if (const Randomization* bad = DrawState()) {
      Restore();
      return Refuse(*bad);
    }
    w_.data.Forward();
    if (spec_.observe) spec_.observe(index_, 0, w_.work, w_.data.get());
    Simulate();
    Restore();
    return out_;
  }

 private:
  // Every element has its own random key, its position in the expanded list.
  double Draw(const Distribution& dist, std::uint32_t key, double nominal_value) const {
    double u = Uniform01(spec_.seed, static_cast<std::uint64_t>(index_), key, 0);
    double z = StandardNormal(spec_.seed, static_cast<std::uint64_t>(index_), key, 1);
    return dist.Apply(nominal_value, u, z);
  }

  // Calls visit(randomization, path, key) for every randomized element.
  template <typename Visit>
  void ForEachElement(Visit visit) const {
    std::uint32_t key = 0;
    for (const Randomization& r : spec_.randomize) {
      for (const Path& p : r.paths) visit(r, p, key++);
    }
  }

  // Draws every parameter element from its nominal value; the randomization whose draw
  // MuJoCo cannot take, or null.
  const Randomization* DrawParameters() {
    const Randomization* bad = nullptr;
    ForEachElement([&](const Randomization& r, const Path& p, std::uint32_t key) {
      if (bad || p.role != Role::kParameter) return;
      out_.params[key] = Draw(r.dist, key, ReadValue(nominal_, w_.data, p));
      if (!Assignable(p, out_.params[key])) bad = &r;
    });
    return bad;
  }

  // Writes the parameter draws; whether a model array changed.
  bool WriteParameterDraws() {
    bool arrays_changed = false;
    ForEachElement([&](const Randomization&, const Path& p, std::uint32_t key) {
      if (p.role != Role::kParameter) return;
      WriteValues(w_.work, w_.data, p, {out_.params[key]});
      arrays_changed = arrays_changed || ChangesModelArrays(p);
    });
    return arrays_changed;
  }

  // Draws and writes every state element; the randomization that failed, or null.
  const Randomization* DrawState() {
    const Randomization* bad = nullptr;
    ForEachElement([&](const Randomization& r, const Path& p, std::uint32_t key) {
      if (bad || p.role == Role::kParameter) return;
      double v = Draw(r.dist, key, ReadValue(w_.work, w_.data, p));
      out_.params[key] = v;
      if (!Assignable(p, v)) {
        bad = &r;
        return;
      }
      WriteValues(w_.work, w_.data, p, {v});
    });
    return bad;
  }

  bool Assignable(const Path& p, double v) {
    try {
      CheckAssignable(p, v);
      return true;
    } catch (const Error& e) {
      refusal_ = e.what();
      return false;
    }
  }

  // A draw MuJoCo cannot take (a negative mass from N(mu, sigma), a fraction for an integer
  // field) is this rollout's problem, recorded; the batch goes on.
  RolloutResult Refuse(const Randomization& r) {
    out_.problem = fmt::format("rollout {}: randomize '{}' drew a value MuJoCo cannot take: {}",
                               index_, r.text, refusal_);
    out_.metrics.assign(spec_.metrics.size(), kNaN);
    return out_;
  }

  // Restores what this rollout changed, so the next starts from the nominal model.
  void Restore() {
    ForEachElement([&](const Randomization&, const Path& p, std::uint32_t) {
      if (p.role == Role::kParameter) {
        WriteValues(w_.work, w_.data, p, {ReadValue(nominal_, w_.data, p)});
      }
    });
    mjModel* m = w_.work.get_mutable();
    m->opt.enableflags = nominal_->opt.enableflags;
    std::copy(inertia_.begin(), inertia_.end(), m->body_inertia);
  }

  // Control noise keyed by (seed, rollout, actuator, step): every rollout has noise of its
  // own, the same for any thread count, shard or resume.
  // The noise is centred on the start's ctrl (centre_, CtrlNoiseCentre).
  void CtrlNoise(mjData* d, long step) const {
    const mjModel* m = w_.work.get();
    for (int j = 0; j < m->nu; ++j) {
      double radius = 1;
      if (m->actuator_ctrllimited[j]) {
        radius = 0.5 * (m->actuator_ctrlrange[2 * j + 1] - m->actuator_ctrlrange[2 * j]);
      }
      double u = Uniform01(spec_.seed, static_cast<std::uint64_t>(index_),
                           kCtrlNoiseKey + static_cast<std::uint32_t>(j),
                           static_cast<std::uint32_t>(step));
      d->ctrl[j] = centre_[j] + spec_.ctrl_noise * radius * (2 * u - 1);
    }
  }

  // The run, probing every step, and what it gave.
  void Simulate() {
    double dt = w_.work->opt.timestep;
    internal::MetricProbe probe(w_.work, spec_.metrics, /*scales=*/false);
    RunSpec run;
    run.until = spec_.until;
    run.stop = stop_;
    // one sample at the end: the probe reads every step
    run.every = static_cast<double>(std::max(1L, StepsToReach(spec_.until, dt))) * dt;
    if (spec_.ctrl_noise > 0) centre_ = CtrlNoiseCentre(w_.work.get(), w_.data.get());
    if (spec_.ctrl_noise > 0 || spec_.observe) {
      run.before_step = [&](mjData* d, long step) {
        if (spec_.ctrl_noise > 0) CtrlNoise(d, step);
        if (spec_.observe) spec_.observe(index_, step, w_.work, d);
      };
    }
    run.after_step = [&](const mjData*, long step) { probe.Observe(w_.data, step); };
    probe.Observe(w_.data, 0);
    NullSink sink;
    RunResult result = plumb::Run(w_.work, w_.data, run, sink);
    TakeMujocoWarnings();
    for (const WarningSummary& warning : result.warnings) {
      out_.warnings += (out_.warnings.empty() ? "" : "; ") + warning.kind + " x" +
                       std::to_string(warning.count) +
                       " (t = " + std::to_string(warning.first_time) + " s)";
    }
    if (result.diverged) {
      out_.diverged = true;
      out_.diverged_time = result.divergence->bad.time;
      out_.problem = result.divergence->reason;
      out_.metrics.assign(spec_.metrics.size(), kNaN);
      return;
    }
    for (std::size_t k = 0; k < spec_.metrics.size(); ++k) {
      out_.metrics.push_back(probe.Result(k, spec_.until).value);  // NaN when unmeasurable
    }
  }

  const Model& nominal_;
  internal::WorkerPool::Worker& w_;
  const RolloutSpec& spec_;
  long index_;
  const StopToken& stop_;
  std::vector<mjtNum> inertia_;
  std::vector<double> centre_;  // the control noise's centre: the start's ctrl
  RolloutResult out_;
  std::string refusal_;  // why the last draw was refused
};

RolloutResult RunOne(const Model& nominal, internal::WorkerPool::Worker& w, const RolloutSpec& spec,
                     long index, bool energy, const StopToken& stop) {
  return OneRollout(nominal, w, spec, index, stop).Run(energy);
}

}  // namespace

namespace {
bool NeedsEnergy(const RolloutSpec& spec) {
  for (const Metric& metric : spec.metrics) {
    if (metric.kind == MetricKind::kEnergyDrift) return true;
  }
  return false;
}
}  // namespace

long ShardSize(const RolloutSpec& spec) {
  if (spec.count <= spec.shard_index || spec.shard_count < 1) return 0;
  return (spec.count - spec.shard_index - 1) / spec.shard_count + 1;
}

long ShardToRun(const RolloutSpec& spec) {
  long total = ShardSize(spec);
  for (long i : spec.skip) {
    if (i >= 0 && i < spec.count && i % spec.shard_count == spec.shard_index) --total;
  }
  return total;
}

std::vector<double> CtrlNoiseCentre(const mjModel* m, const mjData* d) {
  std::vector<double> centre(d->ctrl, d->ctrl + m->nu);
  for (int j = 0; j < m->nu; ++j) {
    if (!m->actuator_ctrllimited[j]) continue;
    double lo = m->actuator_ctrlrange[2 * j], hi = m->actuator_ctrlrange[2 * j + 1];
    if (lo <= hi) centre[j] = std::clamp(centre[j], lo, hi);
  }
  return centre;
}

void RequireCtrlNoise(double ctrl_noise) {
  if (!(ctrl_noise >= 0 && ctrl_noise <= 1)) {
    throw ArgumentError("ctrl_noise", fmt::format("{:g}", ctrl_noise),
                        "must be in [0, 1], a fraction of each ctrlrange.");
  }
}

void ValidateRolloutSpec(const Model& model, const RolloutSpec& spec) {
  if (spec.count < 0) throw ArgumentError("count", std::to_string(spec.count), "must be >= 0");
  if (spec.threads < 1) {
    throw ArgumentError("threads", std::to_string(spec.threads), "must be at least 1");
  }
  if (spec.shard_count < 1 || spec.shard_index < 0 || spec.shard_index >= spec.shard_count) {
    throw ArgumentError("shard",
                        std::to_string(spec.shard_index) + "/" + std::to_string(spec.shard_count),
                        "a shard I/N needs 0 <= I < N");
  }
  if (!(spec.until > 0) || !std::isfinite(spec.until)) {
    throw ArgumentError("until", fmt::format("{:g}", spec.until), "must be > 0 s");
  }
  RequireStepsToReach(spec.until, RunTimestep(model, spec.sets), "until");
  RequireCtrlNoise(spec.ctrl_noise);
  // each element drawn once: a second draw of the same element would silently win, and two
  // columns would carry one name
  std::map<std::pair<int, long>, const Randomization*> drawn;
  for (const Randomization& r : spec.randomize) {
    for (const Path& p : r.paths) {
      auto [it, fresh] = drawn.try_emplace({p.field_index, p.first}, &r);
      if (fresh) continue;
      throw ArgumentError("randomize", Quoted(r.text) + " and " + Quoted(it->second->text),
                          "both draw " + p.text +
                              ": the later draw would silently win. Give each element one "
                              "distribution.");
    }
  }
  // the one timing rule: a metric's time falls on whole steps of every timestep a rollout
  // may use, which a timestep drawn at random cannot promise
  double dt = RunTimestep(model, spec.sets);
  std::string random_dt;
  for (const Randomization& r : spec.randomize) {
    for (const Path& p : r.paths) {
      if (p.field == "opt.timestep") random_dt = r.text;
    }
  }
  for (const Metric& metric : spec.metrics) {
    if (metric.kind != MetricKind::kValueAt && metric.kind != MetricKind::kStateAt) continue;
    if (!random_dt.empty()) {
      throw ArgumentError("metric", Quoted(metric.text),
                          "a metric at a fixed time needs a whole number of steps, and the "
                          "randomization " +
                              Quoted(random_dt) +
                              " draws timesteps that do not divide it. Use period(...), "
                              "maxabs(...) or energy_drift, or vary the timestep over listed "
                              "values in a sweep.");
    }
    RequireWholeSteps(metric.time, dt, "metric", Quoted(metric.text), "", 0);
    if (metric.time > spec.until + 1e-12) {
      throw ArgumentError("metric", Quoted(metric.text),
                          fmt::format("{:g} s is after the end of the run (until {:g} s).",
                                      metric.time, spec.until));
    }
  }
}

struct RolloutPool::Impl {
  const Model& model;
  const RolloutSpec& spec;
  bool energy;
  internal::WorkerPool pool;
  Impl(const Model& m, const RolloutSpec& s)
      : model(m), spec(s), energy(NeedsEnergy(s)), pool(m, s.threads) {}
};

RolloutPool::RolloutPool(const Model& model, const RolloutSpec& spec) {
  if (spec.threads < 1) throw ValueError("threads must be at least 1");
  impl_ = std::make_unique<Impl>(model, spec);
}

RolloutPool::~RolloutPool() = default;

void RolloutPool::Run(const std::vector<long>& indices,
                      const std::function<void(const RolloutResult&)>& emit,
                      const StopToken& stop) {
  std::size_t first = 0;
  Stream(
      static_cast<long>(indices.size()),
      [&](std::vector<long>* out, std::size_t most) {
        std::size_t n = std::min(most, indices.size() - first);
        out->assign(indices.begin() + first, indices.begin() + first + n);
        first += n;
      },
      emit, stop);
}

void RolloutPool::RunShard(const std::function<void(const RolloutResult&)>& emit,
                           const StopToken& stop) {
  const RolloutSpec& spec = impl_->spec;
  // the shard's indices below count, less those skipped: counted, never held
  long total = ShardToRun(spec);
  long next = spec.shard_index;
  Stream(
      total,
      [&](std::vector<long>* out, std::size_t most) {
        while (next < spec.count && out->size() < most) {
          long i = next;
          // the last index stops at count: adding past it could overflow a long
          next = i > spec.count - spec.shard_count ? spec.count : i + spec.shard_count;
          if (!std::binary_search(spec.skip.begin(), spec.skip.end(), i)) out->push_back(i);
        }
      },
      emit, stop);
}

void RolloutPool::Stream(long total,
                         const std::function<void(std::vector<long>*, std::size_t)>& next,
                         const std::function<void(const RolloutResult&)>& emit,
                         const StopToken& stop) {
  Impl& p = *impl_;
  std::atomic<long> done{0};
  internal::WorkerPool::Job<RolloutResult> job = [&](internal::WorkerPool::Worker& w, long index,
                                                     RolloutResult* result) {
    try {
      *result = RunOne(p.model, w, p.spec, index, p.energy, stop);
    } catch (const Interrupted&) {
      return false;  // abandoned mid-run (`stop` asked)
    }
    long count = ++done;
    if (p.spec.progress) p.spec.progress(count, total);
    return true;
  };
  const std::size_t chunk = 64 * static_cast<std::size_t>(p.spec.threads);
  auto next_chunk = [&](std::vector<long>* out) { next(out, chunk); };
  auto interrupted = [&] {
    return Interrupted("interrupted after " + std::to_string(done.load()) + " rollouts");
  };
  // on a stop every finished rollout is emitted (each names its index), so a store keeps it
  p.pool.Stream<RolloutResult>(chunk, next_chunk, job, emit, stop, interrupted,
                               internal::WorkerPool::OnStop::kEveryFinished);
}

void RolloutCases(const Model& model, const RolloutSpec& spec, const std::vector<long>& indices,
                  const std::function<void(const RolloutResult&)>& emit, const StopToken& stop) {
  RolloutPool pool(model, spec);
  pool.Run(indices, emit, stop);
}

void Rollout(const Model& model, const RolloutSpec& spec,
             const std::function<void(const RolloutResult&)>& emit, const StopToken& stop) {
  ValidateRolloutSpec(model, spec);
  RolloutPool pool(model, spec);
  pool.RunShard(emit, stop);
}

namespace {
template <typename T>
void Put(std::string* out, const T& v) {
  out->append(reinterpret_cast<const char*>(&v), sizeof(T));
}
template <typename T>
T Get(const std::string& in, std::size_t* at) {
  if (*at + sizeof(T) > in.size()) throw ValueError("a rollout result message is truncated");
  T v;
  std::memcpy(&v, in.data() + *at, sizeof(T));
  *at += sizeof(T);
  return v;
}
}  // namespace

std::string EncodeResult(const RolloutResult& r) {
  std::string out;
  Put<std::int64_t>(&out, r.index);
  Put<std::int64_t>(&out, r.diverged ? 1 : 0);
  Put<double>(&out, r.diverged_time);
  Put<std::int64_t>(&out, static_cast<std::int64_t>(r.params.size()));
  for (double v : r.params) Put(&out, v);
  Put<std::int64_t>(&out, static_cast<std::int64_t>(r.metrics.size()));
  for (double v : r.metrics) Put(&out, v);
  for (const std::string* text : {&r.problem, &r.warnings}) {
    Put<std::int64_t>(&out, static_cast<std::int64_t>(text->size()));
    out += *text;
  }
  return out;
}

RolloutResult DecodeResult(const std::string& in) {
  std::size_t at = 0;
  RolloutResult r;
  r.index = Get<std::int64_t>(in, &at);
  r.diverged = Get<std::int64_t>(in, &at) != 0;
  r.diverged_time = Get<double>(in, &at);
  // every count is checked against the bytes left before anything is allocated for it
  auto count = [&](std::size_t element) {
    std::int64_t n = Get<std::int64_t>(in, &at);
    if (n < 0 || static_cast<std::uint64_t>(n) > (in.size() - at) / element) {
      throw ValueError("a rollout result message is damaged: it announces " + std::to_string(n) +
                       " entries where " + std::to_string(in.size() - at) + " bytes are left");
    }
    return static_cast<std::size_t>(n);
  };
  r.params.resize(count(sizeof(double)));
  for (double& v : r.params) v = Get<double>(in, &at);
  r.metrics.resize(count(sizeof(double)));
  for (double& v : r.metrics) v = Get<double>(in, &at);
  for (std::string* text : {&r.problem, &r.warnings}) {
    std::size_t n = count(1);
    *text = in.substr(at, n);
    at += n;
  }
  if (at != in.size()) {
    throw ValueError("a rollout result message is damaged: " + std::to_string(in.size() - at) +
                     " bytes follow its end");
  }
  return r;
}

}  // namespace plumb
