#include "plumb/sweep.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <cmath>
#include <optional>

#include "core/strings.h"
#include "plumb/error.h"

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
  axis.path = ResolvePath(model, path_text);
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
      double v = *count == 1 ? *start : *start + (*stop - *start) * i / (*count - 1);
      char buffer[32];
      std::snprintf(buffer, sizeof(buffer), "%.17g", v);
      axis.labels.push_back(buffer);
    }
  } else if (range.size() == 1) {
    axis.labels = Split(values, ',');
  } else {
    throw ValueError("--vary '" + axis.text + "': a range is START:STOP:COUNT.");
  }
  for (const std::string& label : axis.labels) {
    axis.values.push_back(ParseAssignment(model, path_text + "=" + label));
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
  double dt = [&] {
    Model nominal = model.Clone();
    Data data(nominal);
    ApplyAssignments(nominal, data, spec.sets);
    return nominal->opt.timestep;
  }();

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
    double case_dt = dt;
    for (const Assignment& s : sets) {
      if (s.path.field == "opt.timestep") case_dt = s.values[0];
    }
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
    tbb::parallel_for(tbb::blocked_range<long>(0, total, 1), [&](const tbb::blocked_range<long>& r) {
      for (long i = r.begin(); i != r.end(); ++i) run_case(i);
    });
  });
  return cases;
}

}  // namespace plumb
