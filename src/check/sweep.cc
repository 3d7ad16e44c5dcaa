#include "plumb/sweep.h"

#include <fmt/format.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <optional>

#include "core/strings.h"
#include "plumb/error.h"
#include "plumb/timing.h"

namespace plumb {

SweepAxis ParseSweepAxis(const Model& model, std::string_view text) {
  std::size_t eq = text.find('=');
  if (eq == std::string_view::npos) {
    throw ValueError("--vary '" + std::string(text) +
                     "': expected PATH=V1,V2,... or PATH=START:STOP:COUNT, e.g. "
                     "dof_damping[hinge]=0,0.05,1 or qpos[hinge]=0.1:2.8:10.");
  }
  SweepAxis axis;
  axis.text = std::string(text);
  std::string path_text(text.substr(0, eq));
  // errors from the path and value parsers speak of --set; here the user wrote --vary
  auto as_vary = [&](const Error& e) {
    std::string message = e.what();
    std::size_t colon = message.rfind("--set '", 0) == 0 ? message.find("': ") : std::string::npos;
    if (colon != std::string::npos) message = message.substr(colon + 3);
    return ValueError("--vary '" + axis.text + "': " + message);
  };
  try {
    axis.path = ResolvePath(model, path_text);
  } catch (const PathError& e) {
    throw as_vary(e);
  }
  if (axis.path.count != 1) {
    throw ValueError("--vary '" + axis.text + "': '" + axis.path.text + "' has " +
                     std::to_string(axis.path.count) + " elements; vary one, e.g. " +
                     axis.path.text + "[0].");
  }
  std::string values(text.substr(eq + 1));
  std::vector<std::string> range = Split(values, ':');
  if (range.size() == 3) {
    std::optional<double> start = ParseNumber(range[0]), stop = ParseNumber(range[1]);
    std::optional<long> count = ParseIndex(range[2]);
    if (!start || !stop || !count || *count < 1 || !std::isfinite(*start) ||
        !std::isfinite(*stop)) {
      throw ValueError("--vary '" + axis.text +
                       "': START:STOP:COUNT needs two numbers and a whole count >= 1.");
    }
    for (long i = 0; i < *count; ++i) {
      // the endpoints exactly as written: start + (stop - start) can round away from stop
      double v = i == 0            ? *start
                 : i == *count - 1 ? *stop
                                   : *start + (*stop - *start) * static_cast<double>(i) /
                                                  static_cast<double>(*count - 1);
      // interior points to 15 digits (0.1:2.8:4 gives 1 and 1.9, not 0.99999999999999989);
      // endpoints as the shortest text that reads back as the number written
      char buffer[32];
      std::snprintf(buffer, sizeof(buffer), "%.15g", v);
      bool endpoint = i == 0 || i == *count - 1;
      if (endpoint && std::strtod(buffer, nullptr) != v) {
        std::snprintf(buffer, sizeof(buffer), "%.17g", v);
      }
      axis.labels.push_back(buffer);
    }
  } else if (range.size() == 1) {
    axis.labels = Split(values, ',');
  } else {
    throw ValueError("--vary '" + axis.text + "': a range is START:STOP:COUNT.");
  }
  for (const std::string& label : axis.labels) {
    try {
      axis.values.push_back(ParseAssignment(model, path_text + "=" + label));
    } catch (const Error& e) {
      throw as_vary(e);
    }
  }
  return axis;
}

long CaseCount(const std::vector<SweepAxis>& axes) {
  long n = 1;
  for (const SweepAxis& a : axes) n *= static_cast<long>(a.values.size());
  return n;
}

std::vector<SweepCase> Sweep(const Model& model, const SweepSpec& spec) {
  if (spec.metrics.empty()) throw ValueError("a sweep needs at least one --metric");
  if (spec.threads < 1) throw ValueError("--threads must be at least 1");
  long total = CaseCount(spec.axes);
  std::vector<SweepCase> cases(total);
  double dt = RunTimestep(model, spec.sets);

  // every case's runs must end on whole steps of its timestep: checked for all cases
  // before any runs, not found in the middle of the sweep
  std::vector<std::pair<double, std::string>> timesteps = {{dt, "the timestep the run uses"}};
  for (const SweepAxis& axis : spec.axes) {
    if (axis.path.field != "opt.timestep") continue;
    timesteps.clear();
    for (std::size_t v = 0; v < axis.values.size(); ++v) {
      timesteps.push_back({axis.values[v].values[0], "--vary '" + axis.text + "'"});
    }
  }
  for (const Metric& metric : spec.metrics) {
    bool at_time = metric.kind == MetricKind::kValueAt || metric.kind == MetricKind::kStateAt;
    double until = at_time ? metric.time : spec.until > 0 ? spec.until : DefaultDuration(metric);
    for (const auto& [step, source] : timesteps) {
      RequireWholeSteps(until, step, "--metric '" + metric.text + "'", source);
    }
  }

  // one model copy and one data per worker, made on first use
  struct Worker {
    Model work;
    Data data;
    explicit Worker(const Model& nominal) : work(nominal.Clone()), data(work) {}
  };
  tbb::enumerable_thread_specific<std::optional<Worker>> workers;
  std::atomic<long> done{0};

  auto run_case = [&](long index) {
    std::optional<Worker>& worker = workers.local();
    if (!worker) worker.emplace(model);
    SweepCase& c = cases[index];
    c.index = index;
    // the case's choice of values, last axis fastest
    std::vector<Assignment> sets = spec.sets;
    c.choice.resize(spec.axes.size());
    long rest = index;
    for (std::size_t a = spec.axes.size(); a-- > 0;) {
      std::size_t n = spec.axes[a].values.size();
      c.choice[a] = static_cast<std::size_t>(rest % static_cast<long>(n));
      rest /= static_cast<long>(n);
    }
    for (std::size_t a = 0; a < spec.axes.size(); ++a) {
      sets.push_back(spec.axes[a].values[c.choice[a]]);
    }
    // a varied timestep is the case's timestep
    double case_dt = RunTimestep(model, sets);
    for (const Metric& metric : spec.metrics) {
      double until = spec.until > 0 ? spec.until : DefaultDuration(metric);
      c.metrics.push_back(
          MeasureInPlace(model, worker->work, worker->data, sets, metric, case_dt, until));
    }
    long finished = ++done;
    if (spec.progress) spec.progress(finished, total);
  };

  tbb::task_arena arena(spec.threads);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<long>(0, total, 1),
                      [&](const tbb::blocked_range<long>& r) {
                        for (long i = r.begin(); i != r.end(); ++i) run_case(i);
                      });
  });
  return cases;
}

}  // namespace plumb
