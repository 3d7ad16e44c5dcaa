#include "plumb/sweep.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <optional>

#include "core/strings.h"
#include "core/worker_pool.h"
#include "plumb/error.h"
#include "plumb/run.h"
#include "plumb/timing.h"

namespace plumb {

namespace {
// Ranges up to this many values are checked value by value when parsed.
constexpr long kCheckedRange = 100000;
}  // namespace

SweepAxis ParseSweepAxis(const Model& model, std::string_view text) {
  auto [path_view, values_view] =
      SplitAssignment(text, "vary",
                      "PATH=V1,V2,... or PATH=START:STOP:COUNT, e.g. "
                      "dof_damping[hinge]=0,0.05,1 or qpos[hinge]=0.1:2.8:10");
  SweepAxis axis;
  axis.text = std::string(text);
  std::string path_text(path_view);
  // what the path and value parsers say is about this axis: an assignment's problem as it
  // is, anything else whole
  auto as_vary = [&](const Error& e) {
    const auto* bad = dynamic_cast<const ArgumentError*>(&e);
    return ArgumentError("vary", Quoted(axis.text), bad ? bad->problem() : e.what());
  };
  try {
    axis.path = ResolvePath(model, path_text);
  } catch (const PathError& e) {
    throw as_vary(e);
  }
  if (axis.path.count != 1) {
    throw ArgumentError("vary", Quoted(axis.text),
                        "'" + axis.path.text + "' has " + std::to_string(axis.path.count) +
                            " elements; vary one, e.g. " + axis.path.text + "[0].");
  }
  std::string values(values_view);
  std::vector<std::string> range = internal::Split(values, ':');
  if (range.size() == 3) {
    std::optional<double> start = internal::ParseNumber(range[0]),
                          stop = internal::ParseNumber(range[1]);
    std::optional<long> count = internal::ParseIndex(range[2]);
    if (!start || !stop || !count || *count < 1 || !std::isfinite(*start) ||
        !std::isfinite(*stop)) {
      throw ArgumentError("vary", Quoted(axis.text),
                          "START:STOP:COUNT needs two numbers and a whole count >= 1.");
    }
    axis.start = *start;
    axis.stop = *stop;
    axis.count = *count;
    // the ends carry the parser's warnings (a ctrl beyond ctrlrange) for the values between
    // them; every value is checked (an integer field takes whole numbers only) while that
    // is cheap, and a longer range's values are checked as each case starts
    try {
      axis.prototype = ParseAssignment(model, path_text + "=" + axis.Label(0));
      Assignment last = ParseAssignment(model, path_text + "=" + axis.Label(axis.size() - 1));
      for (std::string& w : last.warnings) axis.prototype.warnings.push_back(std::move(w));
      for (long i = 1; i + 1 < std::min(axis.count, kCheckedRange); ++i) {
        CheckAssignable(axis.path, axis.Value(static_cast<std::size_t>(i)).values[0]);
      }
    } catch (const Error& e) {
      throw as_vary(e);
    }
    return axis;
  }
  if (range.size() != 1)
    throw ArgumentError("vary", Quoted(axis.text), "a range is START:STOP:COUNT.");
  for (const std::string& label : internal::Split(values, ',')) {
    try {
      axis.listed.push_back(ParseAssignment(model, path_text + "=" + label));
      axis.listed_labels.push_back(label);
    } catch (const Error& e) {
      throw as_vary(e);
    }
  }
  return axis;
}

std::size_t SweepAxis::size() const {
  return count > 0 ? static_cast<std::size_t>(count) : listed.size();
}

namespace {
// The i-th of `count` evenly spaced values from start to stop, the ends exactly as written
// (start + (stop - start) can round away from stop).
double RangeValue(double start, double stop, long count, std::size_t i) {
  long k = static_cast<long>(i);
  if (k == 0) return start;
  if (k == count - 1) return stop;
  return start + (stop - start) * static_cast<double>(k) / static_cast<double>(count - 1);
}
}  // namespace

Assignment SweepAxis::Value(std::size_t i) const {
  if (count == 0) return listed.at(i);
  Assignment a = prototype;
  a.values = {RangeValue(start, stop, count, i)};
  a.text = path.text + "=" + Label(i);
  return a;
}

std::string SweepAxis::Label(std::size_t i) const {
  if (count == 0) return listed_labels.at(i);
  double v = RangeValue(start, stop, count, i);
  // interior points to 15 digits (0.1:2.8:4 gives 1 and 1.9, not 0.99999999999999989);
  // endpoints as the shortest text that reads back as the number written
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.15g", v);
  bool endpoint = i == 0 || static_cast<long>(i) == count - 1;
  if (endpoint && std::strtod(buffer, nullptr) != v) {
    std::snprintf(buffer, sizeof(buffer), "%.17g", v);
  }
  return buffer;
}

long CaseCount(const std::vector<SweepAxis>& axes) {
  constexpr long kMostCases = 1L << 53;
  long n = 1;
  for (const SweepAxis& a : axes) {
    long size = static_cast<long>(a.size());
    if (size > 0 && n > kMostCases / size) {
      throw ArgumentError("vary", "",
                          "the product of the axes passes 2^53 cases; no sweep can run that "
                          "many. Use fewer values, or a rollout to sample the space at random.");
    }
    n *= size;
  }
  return n;
}

void RequireDistinctAxes(const std::vector<SweepAxis>& axes) {
  for (std::size_t a = 0; a < axes.size(); ++a) {
    for (std::size_t b = 0; b < a; ++b) {
      if (axes[a].path.field_index != axes[b].path.field_index ||
          axes[a].path.first != axes[b].path.first) {
        continue;
      }
      throw ArgumentError("vary", Quoted(axes[a].text) + " and " + Quoted(axes[b].text),
                          "both vary " + axes[b].path.text +
                              ": the later value would silently win in every case. Give each "
                              "element one axis with all its values.");
    }
  }
}

std::vector<std::size_t> CaseChoice(const std::vector<SweepAxis>& axes, long index) {
  std::vector<std::size_t> choice(axes.size());
  long rest = index;
  for (std::size_t a = axes.size(); a-- > 0;) {
    long n = static_cast<long>(axes[a].size());
    choice[a] = static_cast<std::size_t>(rest % n);
    rest /= n;
  }
  return choice;
}

std::vector<SweepRun> SweepRuns(const SweepSpec& spec) {
  std::vector<SweepRun> runs;
  for (std::size_t k = 0; k < spec.metrics.size(); ++k) {
    const Metric& metric = spec.metrics[k];
    bool at_time = metric.kind == MetricKind::kValueAt || metric.kind == MetricKind::kStateAt;
    double until = at_time ? metric.time : spec.until > 0 ? spec.until : DefaultDuration(metric);
    auto same =
        std::find_if(runs.begin(), runs.end(), [&](const SweepRun& r) { return r.until == until; });
    if (same == runs.end()) same = runs.insert(runs.end(), SweepRun{until, {}});
    same->metrics.push_back(k);
  }
  return runs;
}

void ValidateSweepSpec(const Model& model, const SweepSpec& spec) {
  if (spec.metrics.empty()) throw ArgumentError("metric", "", "a sweep needs at least one metric");
  if (spec.threads < 1) {
    throw ArgumentError("threads", std::to_string(spec.threads), "must be at least 1");
  }
  RequireDistinctAxes(spec.axes);
  CaseCount(spec.axes);
  // every case's runs must end on whole steps of its timestep: checked for all cases
  // before any runs, not found in the middle of the sweep
  std::vector<std::pair<double, std::string>> timesteps = {
      {RunTimestep(model, spec.sets), "the timestep the run uses"}};
  for (const SweepAxis& axis : spec.axes) {
    if (axis.path.field != "opt.timestep") continue;
    timesteps.clear();
    for (std::size_t v = 0; v < axis.size(); ++v) {
      timesteps.push_back({axis.Value(v).values[0], "varied by " + Quoted(axis.text)});
    }
  }
  if (spec.until != 0) {  // NaN too: only 0 means each metric's default
    if (!(spec.until > 0)) {
      throw ArgumentError("until", fmt::format("{:g}", spec.until),
                          "the run length must be a positive number of seconds (or leave it "
                          "out for each metric's default).");
    }
    for (const auto& ts : timesteps) RequireStepsToReach(spec.until, ts.first, "until");
  }
  for (const Metric& metric : spec.metrics) {
    bool at_time = metric.kind == MetricKind::kValueAt || metric.kind == MetricKind::kStateAt;
    double until = at_time ? metric.time : spec.until > 0 ? spec.until : DefaultDuration(metric);
    for (const auto& [step, source] : timesteps) {
      RequireWholeSteps(until, step, "metric", Quoted(metric.text), source);
    }
  }
}

void Sweep(const Model& model, const SweepSpec& spec, const std::vector<long>& skip,
           const std::function<void(const SweepCase&)>& emit, const StopToken& stop) {
  ValidateSweepSpec(model, spec);
  const long total = CaseCount(spec.axes);
  const std::vector<SweepRun> runs = SweepRuns(spec);

  std::atomic<long> done{0};
  // one case: false when a stop request abandoned it
  internal::WorkerPool::Job<SweepCase> run_case = [&](internal::WorkerPool::Worker& worker,
                                                      long index, SweepCase* c) {
    c->index = index;
    c->choice = CaseChoice(spec.axes, index);
    std::vector<Assignment> sets = spec.sets;
    for (std::size_t a = 0; a < spec.axes.size(); ++a) {
      sets.push_back(spec.axes[a].Value(c->choice[a]));
    }
    // a long range's values were not all checked when parsed: a bad one is this case's problem
    for (std::size_t a = 0; a < spec.axes.size(); ++a) {
      try {
        CheckAssignable(sets[spec.sets.size() + a].path, sets[spec.sets.size() + a].values[0]);
      } catch (const Error& e) {
        Measurement refused;
        refused.ok = false;
        refused.problem = e.what();
        c->metrics.assign(spec.metrics.size(), refused);
        return true;
      }
    }
    double case_dt = RunTimestep(model, sets);  // a varied timestep is the case's timestep
    try {
      // one simulation per run length: the metrics of one length are measured together
      c->metrics.assign(spec.metrics.size(), Measurement{});
      for (const SweepRun& run : runs) {
        std::vector<Metric> metrics;
        for (std::size_t k : run.metrics) metrics.push_back(spec.metrics[k]);
        std::vector<Measurement> measured = MeasureInPlace(model, worker.work, worker.data, sets,
                                                           metrics, case_dt, run.until, stop);
        for (std::size_t i = 0; i < run.metrics.size(); ++i) {
          c->metrics[run.metrics[i]] = measured[i];
        }
        ++c->runs;
      }
    } catch (const Interrupted&) {
      return false;  // abandoned mid-run
    }
    long finished = ++done;
    if (spec.progress) spec.progress(finished, total);
    return true;
  };
  // the cases not yet done, a chunk at a time (16 per thread), emitted in order (on a stop,
  // the finished ones after the first unfinished one follow it)
  const long chunk_size = 16L * spec.threads;
  long next = 0;
  auto next_chunk = [&](std::vector<long>* indices) {
    for (; next < total && static_cast<long>(indices->size()) < chunk_size; ++next) {
      if (!std::binary_search(skip.begin(), skip.end(), next)) indices->push_back(next);
    }
  };
  auto interrupted = [&] {
    return Interrupted("interrupted after " + std::to_string(done.load()) + " of " +
                       std::to_string(total - static_cast<long>(skip.size())) + " cases");
  };
  internal::WorkerPool pool(model, spec.threads);
  // on a stop every finished case is emitted (each names its index), so a store keeps it
  pool.Stream<SweepCase>(static_cast<std::size_t>(chunk_size), next_chunk, run_case, emit, stop,
                         interrupted, internal::WorkerPool::OnStop::kEveryFinished);
}

std::vector<SweepCase> Sweep(const Model& model, const SweepSpec& spec) {
  std::vector<SweepCase> cases;
  Sweep(model, spec, {}, [&](const SweepCase& c) { cases.push_back(c); });
  return cases;
}

}  // namespace plumb
