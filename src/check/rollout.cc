#include "plumb/rollout.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <optional>

#include "check/metric_probe.h"
#include "check/worker_pool.h"
#include "core/mujoco_compat.h"
#include "plumb/strings.h"
#include "plumb/analytic.h"
#include "plumb/error.h"
#include "plumb/random.h"
#include "plumb/run.h"
#include "plumb/timing.h"

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
  d.text = std::string(Trim(raw));
  std::string_view s = Trim(raw);
  auto bad = [&](const std::string& why) {
    return ValueError("distribution '" + d.text + "': " + why +
                      ". Use U(a,b), N(mu,sigma), LogU(a,b), optionally prefixed * (scale the "
                      "nominal value) or + (offset it), e.g. *U(0.9,1.1) or +N(0,0.01).");
  };
  if (!s.empty() && (s.front() == '*' || s.front() == '+')) {
    d.mode = s.front() == '*' ? Distribution::Mode::kScale : Distribution::Mode::kOffset;
    s = Trim(s.substr(1));
  }
  std::size_t open = s.find('(');
  if (open == std::string_view::npos || s.back() != ')') throw bad("expected NAME(a,b)");
  std::string_view name = Trim(s.substr(0, open));
  if (name == "U") {
    d.kind = Distribution::Kind::kUniform;
  } else if (name == "N") {
    d.kind = Distribution::Kind::kNormal;
  } else if (name == "LogU") {
    d.kind = Distribution::Kind::kLogUniform;
  } else {
    throw bad("unknown distribution '" + std::string(name) + "'");
  }
  std::vector<std::string> args = Split(s.substr(open + 1, s.size() - open - 2), ',');
  std::optional<double> a = args.size() == 2 ? ParseNumber(args[0]) : std::nullopt;
  std::optional<double> b = args.size() == 2 ? ParseNumber(args[1]) : std::nullopt;
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
      SplitAssignment(text, "--randomize", "PATH=DIST, e.g. 'body_mass[*]=*U(0.9,1.1)'");
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

RolloutResult RunOne(const Model& nominal, WorkerPool::Worker& w, const RolloutSpec& spec, long index,
                     bool energy) {
  RolloutResult out;
  out.index = index;
  mjModel* m = w.work.get_mutable();
  mjData* d = w.data.get();

  // parameters: the user's, then this rollout's draws from the nominal values
  bool arrays_changed = WriteParameters(w.work, w.data, spec.sets);
  // every element has its own random key, its position in the expanded list
  auto draw = [&](const Distribution& dist, std::uint32_t key, double nominal_value) {
    double u = Uniform01(spec.seed, static_cast<std::uint64_t>(index), key, 0);
    double z = StandardNormal(spec.seed, static_cast<std::uint64_t>(index), key, 1);
    return dist.Apply(nominal_value, u, z);
  };
  // a drawn body_mass rescales its body's inertia (WriteValues): kept to be put back exactly
  std::vector<mjtNum> inertia(m->body_inertia, m->body_inertia + 3 * m->nbody);
  // restores what this rollout changed, so the next starts from the nominal model
  auto restore = [&] {
    for (const Randomization& r : spec.randomize) {
      for (const Path& p : r.paths) {
        if (p.role == Role::kParameter)
          WriteValues(w.work, w.data, p, {ReadValue(nominal, w.data, p)});
      }
    }
    m->opt.enableflags = nominal->opt.enableflags;
    std::copy(inertia.begin(), inertia.end(), m->body_inertia);
  };
  // a draw MuJoCo cannot take (a negative mass from N(mu, sigma), a fraction for an
  // integer field) is this rollout's problem, recorded; the batch goes on
  auto refuse = [&](const Randomization& r, const Error& e) {
    out.problem = fmt::format("rollout {}: --randomize '{}' drew a value MuJoCo cannot take: {}",
                              index, r.text, e.what());
    out.metrics.assign(spec.metrics.size(), kNaN);
    return out;
  };
  std::uint32_t key = 0;
  out.params.assign(ParameterCount(spec), kNaN);
  for (const Randomization& r : spec.randomize) {
    for (const Path& p : r.paths) {
      if (p.role == Role::kParameter) {
        out.params[key] = draw(r.dist, key, ReadValue(nominal, w.data, p));
        try {
          CheckAssignable(p, out.params[key]);
        } catch (const Error& e) {
          return refuse(r, e);  // nothing written yet
        }
      }
      ++key;
    }
  }
  key = 0;
  for (const Randomization& r : spec.randomize) {
    for (const Path& p : r.paths) {
      if (p.role == Role::kParameter) {
        WriteValues(w.work, w.data, p, {out.params[key]});
        arrays_changed = arrays_changed || ChangesModelArrays(p);
      }
      ++key;
    }
  }
  if (arrays_changed) mj_setConst(m, d);
  if (energy) m->opt.enableflags |= mjENBL_ENERGY;
  compat::ResetState(m, d);
  WriteState(w.work, w.data, spec.sets);
  // state draws start from the state the user set
  key = 0;
  for (const Randomization& r : spec.randomize) {
    for (const Path& p : r.paths) {
      if (p.role != Role::kParameter) {
        double v = draw(r.dist, key, ReadValue(w.work, w.data, p));
        out.params[key] = v;
        try {
          CheckAssignable(p, v);
        } catch (const Error& e) {
          restore();
          return refuse(r, e);
        }
        WriteValues(w.work, w.data, p, {v});
      }
      ++key;
    }
  }
  w.data.Forward();

  // the run, probing every step
  double dt = m->opt.timestep;
  MetricProbe probe(w.work, spec.metrics, /*scales=*/false);
  RunSpec run;
  run.until = spec.until;
  run.every = static_cast<double>(std::max(1L, StepsToReach(spec.until, dt))) *
              dt;  // metrics probe every step
  if (spec.ctrl_noise > 0) {
    run.before_step = [&](mjData* dd, long step) {
      for (int j = 0; j < m->nu; ++j) {
        double centre = 0, radius = 1;
        if (m->actuator_ctrllimited[j]) {
          centre = 0.5 * (m->actuator_ctrlrange[2 * j + 1] + m->actuator_ctrlrange[2 * j]);
          radius = 0.5 * (m->actuator_ctrlrange[2 * j + 1] - m->actuator_ctrlrange[2 * j]);
        }
        // keyed by (seed, rollout, actuator, step): every rollout has noise of its own,
        // the same for any thread count, shard or resume
        double u = Uniform01(spec.seed, static_cast<std::uint64_t>(index),
                             kCtrlNoiseKey + static_cast<std::uint32_t>(j),
                             static_cast<std::uint32_t>(step));
        dd->ctrl[j] = centre + spec.ctrl_noise * radius * (2 * u - 1);
      }
    };
  }
  run.after_step = [&](const mjData*, long step) { probe.Observe(w.data, step); };
  probe.Observe(w.data, 0);
  NullSink sink;
  RunResult result = Run(w.work, w.data, run, sink);
  TakeMujocoWarnings();
  for (const WarningSummary& warning : result.warnings) {
    out.warnings += (out.warnings.empty() ? "" : "; ") + warning.kind + " x" +
                    std::to_string(warning.count) + " (t = " + std::to_string(warning.first_time) +
                    " s)";
  }
  if (result.diverged) {
    out.diverged = true;
    out.diverged_time = result.divergence->bad.time;
    out.problem = result.divergence->reason;
    out.metrics.assign(spec.metrics.size(), kNaN);
  } else {
    for (std::size_t k = 0; k < spec.metrics.size(); ++k) {
      out.metrics.push_back(probe.Result(k, spec.until).value);  // NaN when unmeasurable
    }
  }
  restore();
  return out;
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

void ValidateRolloutSpec(const Model& model, const RolloutSpec& spec) {
  if (spec.count < 0) throw ValueError("--count must be >= 0");
  if (spec.threads < 1) throw ValueError("--threads must be at least 1");
  if (spec.shard_count < 1 || spec.shard_index < 0 || spec.shard_index >= spec.shard_count) {
    throw ValueError("--shard I/N needs 0 <= I < N, got " + std::to_string(spec.shard_index) + "/" +
                     std::to_string(spec.shard_count));
  }
  if (!(spec.until > 0) || !std::isfinite(spec.until)) throw ValueError("--until must be > 0 s");
  if (spec.ctrl_noise < 0 || spec.ctrl_noise > 1) {
    throw ValueError("--ctrl-noise must be in [0, 1]");
  }
  // each element drawn once: a second draw of the same element would silently win, and two
  // columns would carry one name
  std::map<std::pair<int, long>, const Randomization*> drawn;
  for (const Randomization& r : spec.randomize) {
    for (const Path& p : r.paths) {
      auto [it, fresh] = drawn.try_emplace({p.field_index, p.first}, &r);
      if (fresh) continue;
      throw ValueError("--randomize '" + r.text + "' and --randomize '" + it->second->text +
                       "' both draw " + p.text +
                       ": the later draw would silently win. Give each element one --randomize.");
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
    std::string what = "--metric '" + metric.text + "'";
    if (!random_dt.empty()) {
      throw ValueError(what +
                       ": a metric at a fixed time needs a whole number of steps, and "
                       "--randomize '" +
                       random_dt +
                       "' draws timesteps that do not divide it. "
                       "Use period(...), maxabs(...) or energy_drift, or vary the timestep over "
                       "listed values with plumb sweep --vary.");
    }
    RequireWholeSteps(metric.time, dt, what, "", 0);
    if (metric.time > spec.until + 1e-12) {
      throw ValueError(fmt::format("{}: {:g} s is after the end of the run (--until {:g} s).", what,
                                   metric.time, spec.until));
    }
  }
}

struct RolloutPool::Impl {
  const Model& model;
  const RolloutSpec& spec;
  bool energy;
  WorkerPool pool;
  Impl(const Model& m, const RolloutSpec& s)
      : model(m), spec(s), energy(NeedsEnergy(s)), pool(m, s.threads) {}
};

RolloutPool::RolloutPool(const Model& model, const RolloutSpec& spec)
    : impl_(std::make_unique<Impl>(model, spec)) {}

RolloutPool::~RolloutPool() = default;

void RolloutPool::Run(const std::vector<long>& indices,
                      const std::function<void(const RolloutResult&)>& emit,
                      const std::atomic<bool>* stop) {
  Impl& p = *impl_;
  std::atomic<long> done{0};
  WorkerPool::Job<RolloutResult> job = [&](WorkerPool::Worker& w, long index,
                                           RolloutResult* result) {
    try {
      *result = RunOne(p.model, w, p.spec, index, p.energy);
    } catch (const Interrupted&) {
      return false;  // abandoned mid-run (plumb::StopFlag)
    }
    long count = ++done;
    if (p.spec.progress) p.spec.progress(count, static_cast<long>(indices.size()));
    return true;
  };
  const std::size_t chunk = 64 * static_cast<std::size_t>(p.spec.threads);
  std::size_t first = 0;
  auto next_chunk = [&](std::vector<long>* out) {
    std::size_t n = std::min(chunk, indices.size() - first);
    out->assign(indices.begin() + first, indices.begin() + first + n);
    first += n;
    return n > 0;
  };
  auto interrupted = [&] {
    return Interrupted("interrupted after " + std::to_string(done.load()) + " rollouts");
  };
  p.pool.Stream<RolloutResult>(chunk, next_chunk, job, emit, stop ? *stop : StopFlag(),
                               interrupted);
}

void RolloutCases(const Model& model, const RolloutSpec& spec, const std::vector<long>& indices,
                  const std::function<void(const RolloutResult&)>& emit,
                  const std::atomic<bool>* stop) {
  RolloutPool pool(model, spec);
  pool.Run(indices, emit, stop);
}

void Rollout(const Model& model, const RolloutSpec& spec,
             const std::function<void(const RolloutResult&)>& emit, const std::atomic<bool>* stop) {
  ValidateRolloutSpec(model, spec);
  std::vector<long> indices;
  for (long i = spec.shard_index; i < spec.count; i += spec.shard_count) {
    if (!std::binary_search(spec.skip.begin(), spec.skip.end(), i)) indices.push_back(i);
  }
  RolloutCases(model, spec, indices, emit, stop);
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
