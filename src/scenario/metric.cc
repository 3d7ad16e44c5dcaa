#include "plumb/metric.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/strings.h"
#include "plumb/analytic.h"
#include "plumb/error.h"
#include "plumb/run.h"
#include "plumb/timing.h"
#include "scenario/metric_probe.h"

namespace plumb {
using internal::MetricProbe;
using internal::ParseNumber;
using internal::Trim;

namespace {

// Extracts X from "name(X)", or returns false.
bool Call(std::string_view text, std::string_view name, std::string_view* inner) {
  if (text.size() < name.size() + 2 || text.substr(0, name.size()) != name) return false;
  std::string_view rest = Trim(text.substr(name.size()));
  if (rest.size() < 2 || rest.front() != '(' || rest.back() != ')') return false;
  *inner = Trim(rest.substr(1, rest.size() - 2));
  return true;
}

}  // namespace

Metric ParseMetric(const Model& model, std::string_view raw) {
  std::string_view text = Trim(raw);
  Metric metric;
  metric.text = std::string(text);
  auto time_of = [&](std::string_view t) {
    std::optional<double> v = ParseNumber(t);
    if (!v || !std::isfinite(*v) || *v < 0) {
      throw ValueError("metric '" + metric.text + "': '" + std::string(t) +
                       "' is not a time in seconds >= 0.");
    }
    return *v;
  };
  std::string_view inner;
  if (text == "energy_drift") {
    metric.kind = MetricKind::kEnergyDrift;
  } else if (Call(text, "period", &inner)) {
    metric.kind = MetricKind::kPeriod;
    metric.path = ResolvePath(model, inner);
  } else if (Call(text, "maxabs", &inner)) {
    metric.kind = MetricKind::kMaxAbs;
    metric.path = ResolvePath(model, inner);
  } else if (std::size_t at = text.rfind('@'); at != std::string_view::npos) {
    std::string_view what = Trim(text.substr(0, at));
    metric.time = time_of(Trim(text.substr(at + 1)));
    if (what == "state") {
      metric.kind = MetricKind::kStateAt;
    } else {
      metric.kind = MetricKind::kValueAt;
      metric.path = ResolvePath(model, what);
    }
  } else {
    throw ValueError("unknown metric '" + metric.text +
                     "': use PATH@T (qpos[hinge]@2), period(PATH), maxabs(PATH), energy_drift "
                     "or state@T.");
  }
  if ((metric.kind != MetricKind::kEnergyDrift && metric.kind != MetricKind::kStateAt) &&
      metric.path.count != 1) {
    throw ValueError("metric '" + metric.text + "': '" + metric.path.text + "' has " +
                     std::to_string(metric.path.count) + " elements; pick one, e.g. " +
                     metric.path.text + "[0].");
  }
  return metric;
}

double DefaultDuration(const Metric& metric) {
  switch (metric.kind) {
    case MetricKind::kValueAt:
    case MetricKind::kStateAt:
      return metric.time;
    case MetricKind::kPeriod:
      return 20.0;
    default:
      return 2.0;
  }
}

Measurement Measure(const Model& model, const std::vector<Assignment>& sets, const Metric& metric,
                    double timestep, double until, const StopToken& stop) {
  Model work = model.Clone();
  Data data(work);
  return MeasureInPlace(model, work, data, sets, metric, timestep, until, stop);
}

Measurement MeasureInPlace(const Model& nominal, Model& work, Data& data,
                           const std::vector<Assignment>& sets, const Metric& metric,
                           double timestep, double until, const StopToken& stop) {
  if (metric.kind == MetricKind::kValueAt || metric.kind == MetricKind::kStateAt) {
    until = metric.time;
  }
  return MeasureInPlace(nominal, work, data, sets, std::vector<Metric>{metric}, timestep, until,
                        stop)[0];
}

std::vector<Measurement> MeasureInPlace(const Model& nominal, Model& work, Data& data,
                                        const std::vector<Assignment>& sets,
                                        const std::vector<Metric>& metrics, double timestep,
                                        double until, const StopToken& stop) {
  // start from the nominal model every time (a sweep's previous case may have edited it)
  mj_copyModel(work.get_mutable(), nominal.get());
  bool energy = false;
  for (const Metric& metric : metrics) {
    RequireWholeSteps(until, timestep, "metric", Quoted(metric.text), "", 0);
    energy = energy || metric.kind == MetricKind::kEnergyDrift;
  }
  std::vector<Assignment> all = sets;
  Assignment dt;
  dt.text = "opt.timestep";
  dt.path = ResolvePath(work, "opt.timestep");
  dt.values = {timestep};
  all.push_back(dt);
  if (energy) work.get_mutable()->opt.enableflags |= mjENBL_ENERGY;
  ApplyAssignments(work, data, all);

  MetricProbe probe(work, metrics, /*scales=*/true);
  RunSpec spec;
  spec.until = until;
  spec.every = timestep;  // the probe reads every step (the sink keeps nothing)
  spec.stop = stop;
  spec.after_step = [&](const mjData*, long step) { probe.Observe(data, step); };
  probe.Observe(data, 0);
  NullSink sink;
  RunResult result = Run(work, data, spec, sink);
  TakeMujocoWarnings();
  std::vector<Measurement> out;
  for (std::size_t k = 0; k < metrics.size(); ++k) {
    Measurement m;
    if (result.diverged) {
      m.ok = false;
      m.diverged = true;
      m.problem = result.divergence->reason;
    } else {
      m = probe.Result(k, until);
    }
    m.steps = result.steps;
    out.push_back(m);
  }
  return out;
}

}  // namespace plumb
