#include "plumb/metric.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "plumb/strings.h"
#include "plumb/analytic.h"
#include "plumb/error.h"
#include "plumb/run.h"
#include "plumb/timing.h"

namespace plumb {
namespace {


// Extracts X from "name(X)", or returns false.
bool Call(std::string_view text, std::string_view name, std::string_view* inner) {
  if (text.size() < name.size() + 2 || text.substr(0, name.size()) != name) return false;
  std::string_view rest = Trim(text.substr(name.size()));
  if (rest.size() < 2 || rest.front() != '(' || rest.back() != ')') return false;
  *inner = Trim(rest.substr(1, rest.size() - 2));
  return true;
}

// Collects what a metric needs at every sample.
class MetricSink : public SampleSink {
 public:
  explicit MetricSink(MetricKind kind) : kind_(kind) {}
  void Begin(const std::vector<Path>&) override {}
  void Sample(const std::vector<double>& row) override {
    switch (kind_) {
      case MetricKind::kPeriod:
        t.push_back(row[0]);
        x.push_back(row[1]);
        break;
      case MetricKind::kMaxAbs:
      case MetricKind::kValueAt:
        maxabs = std::max(maxabs, std::fabs(row[1]));
        low = std::min(low, row[1]);
        high = std::max(high, row[1]);
        last = row;
        break;
      case MetricKind::kEnergyDrift:
        if (first.empty()) first = row;
        max_kinetic = std::max(max_kinetic, row[2]);
        last = row;
        break;
      case MetricKind::kStateAt: {
        double norm = 0;
        for (std::size_t i = 1; i < row.size(); ++i) norm += row[i] * row[i];
        maxabs = std::max(maxabs, std::sqrt(norm));
        if (first.empty()) first = row;
        double moved = 0;
        for (std::size_t i = 1; i < row.size(); ++i)
          moved += (row[i] - first[i]) * (row[i] - first[i]);
        excursion = std::max(excursion, std::sqrt(moved));
        last = row;
        break;
      }
    }
  }

  // How far the signal moves: half its range (the amplitude of a swing), or for a state
  // the largest distance from the start. Independent of the coordinate's offset, so a
  // pendulum swinging about q = 100 is judged like one swinging about 0; a signal that
  // does not move falls back to its magnitude.
  double Scale() const {
    double moved = kind_ == MetricKind::kStateAt ? excursion : 0.5 * (high - low);
    return std::max(moved > 0 ? moved : maxabs, 1e-300);
  }

  MetricKind kind_;
  std::vector<double> t, x, first, last;
  double maxabs = 0, max_kinetic = 0, excursion = 0;
  double low = std::numeric_limits<double>::infinity(), high = -low;
};

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
                    double timestep, double until) {
  Model work = model.Clone();
  Data data(work);
  return MeasureInPlace(model, work, data, sets, metric, timestep, until);
}

Measurement MeasureInPlace(const Model& nominal, Model& work, Data& data,
                           const std::vector<Assignment>& sets, const Metric& metric,
                           double timestep, double until) {
  // start from the nominal model every time (a sweep's previous case may have edited it)
  mj_copyModel(work.get_mutable(), nominal.get());
  if (metric.kind == MetricKind::kValueAt || metric.kind == MetricKind::kStateAt) {
    until = metric.time;
  }
  RequireWholeSteps(until, timestep, "metric '" + metric.text + "'", "", 0);
  std::vector<Assignment> all = sets;
  Assignment dt;
  dt.text = "opt.timestep";
  dt.path = ResolvePath(work, "opt.timestep");
  dt.values = {timestep};
  all.push_back(dt);
  if (metric.kind == MetricKind::kEnergyDrift) work.get_mutable()->opt.enableflags |= mjENBL_ENERGY;
  ApplyAssignments(work, data, all);

  RunSpec spec;
  spec.until = until;
  spec.every = timestep;
  spec.columns = {ResolvePath(work, "time")};
  switch (metric.kind) {
    case MetricKind::kEnergyDrift:
      spec.columns.push_back(ResolvePath(work, "energy[0]"));
      spec.columns.push_back(ResolvePath(work, "energy[1]"));
      break;
    case MetricKind::kStateAt:
      for (const char* field : {"qpos", "qvel", "act"}) {
        Path whole;
        try {
          whole = ResolvePath(work, field);
        } catch (const PathError&) {
          continue;  // an empty array (na = 0)
        }
        for (Path& p : ScalarPaths(whole)) spec.columns.push_back(p);
      }
      break;
    default:
      spec.columns.push_back(metric.path);
  }
  MetricSink sink(metric.kind);
  RunResult result = Run(work, data, spec, sink);
  TakeMujocoWarnings();

  Measurement out;
  out.steps = result.steps;
  if (result.diverged) {
    out.ok = false;
    out.diverged = true;
    out.problem = result.divergence->reason;
    return out;
  }
  switch (metric.kind) {
    case MetricKind::kValueAt:
      out.value = sink.last[1];
      out.scale = sink.Scale();
      break;
    case MetricKind::kMaxAbs:
      out.value = sink.maxabs;
      out.scale = sink.Scale();
      break;
    case MetricKind::kStateAt: {
      out.state.assign(sink.last.begin() + 1, sink.last.end());
      double norm = 0;
      for (double v : out.state) norm += v * v;
      out.value = std::sqrt(norm);
      out.scale = sink.Scale();
      break;
    }
    case MetricKind::kPeriod: {
      // oscillation about the signal's mid-range
      auto [lo, hi] = std::minmax_element(sink.x.begin(), sink.x.end());
      double level = 0.5 * (*lo + *hi);
      std::optional<double> period = PeriodFromCrossings(sink.t, sink.x, level);
      if (!period) {
        out.ok = false;
        out.problem = "'" + metric.path.text +
                      "' crossed its mid-range upward fewer than twice in " +
                      FormatNumber(until) + " s; run longer (--until) or it does not oscillate";
        return out;
      }
      out.value = *period;
      out.scale = *period;
      break;
    }
    case MetricKind::kEnergyDrift: {
      double e0 = sink.first[1] + sink.first[2];
      double e1 = sink.last[1] + sink.last[2];
      double scale = sink.max_kinetic > 0 ? sink.max_kinetic : std::max(std::fabs(e0), 1.0);
      out.value = (e1 - e0) / scale;
      out.scale = 1;
      break;
    }
  }
  return out;
}

}  // namespace plumb
