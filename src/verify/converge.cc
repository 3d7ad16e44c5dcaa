#include "plumb/converge.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/mujoco_compat.h"
#include "core/solref.h"
#include "core/strings.h"
#include "plumb/error.h"
#include "plumb/run.h"
#include "plumb/timing.h"

namespace plumb {
using internal::Join;

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string Str(double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.3g", v);
  return buffer;
}
}  // namespace

OrderEstimate EstimateOrder(const std::vector<double>& values, const std::vector<double>& diffs,
                            double noise) {
  OrderEstimate out;
  out.extrapolated = values.empty() ? kNaN : values.back();
  // differences are ordered coarse to fine; the first one in the noise ends the useful part
  std::size_t clean = 0;
  while (clean < diffs.size() && diffs[clean] > noise) ++clean;
  if (clean < diffs.size()) out.noise_from = static_cast<int>(clean);
  if (clean < 2) {
    out.note = clean == diffs.size()
                   ? "fewer than three levels: the order cannot be estimated"
                   : "successive differences reach round-off (below " + Str(noise) +
                         ") before two clean ones exist: the order is unresolved and the "
                         "finest value is reported unextrapolated";
    return out;
  }
  // the finest clean pair is the closest to the asymptotic regime
  double finer = diffs[clean - 1], coarser = diffs[clean - 2];
  out.order = std::log2(coarser / finer);
  out.resolved = std::isfinite(out.order) && out.order > 0.2;
  if (!out.resolved) {
    out.note = "the differences do not shrink as dt halves (ratio " + Str(coarser / finer) +
               "): no convergence order is visible";
    return out;
  }
  if (out.noise_from >= 0) {
    // the finest levels already agree to round-off: they are the answer
    out.note = "differences below " + Str(noise) +
               " are round-off; the order comes from coarser levels and the finest value is "
               "reported without extrapolation";
    return out;
  }
  double vj = values[clean], vprev = values[clean - 1];
  out.extrapolated = vj + (vj - vprev) / (std::pow(2.0, out.order) - 1);
  out.note = "Richardson extrapolation from the two finest levels";
  return out;
}

std::string ContactCaveat(int max_contacts) {
  if (max_contacts <= 0) return "";
  return "contacts occur (up to " + std::to_string(max_contacts) +
         " at once): they make the trajectory non-smooth in time, so orders (even negative "
         "ones) and the extrapolation are rough; trust differences between levels more than "
         "the order";
}

namespace {
// Most contacts at once in the scenario's run at `dt` (the coarsest, cheapest level).
int MaxContacts(const Model& model, const std::vector<Assignment>& sets, double dt, double until,
                const StopToken& stop) {
  class MaxSink : public SampleSink {
   public:
    void Begin(const std::vector<Path>&) override {}
    void Sample(const std::vector<double>& row) override {
      most = std::max(most, static_cast<int>(row[0]));
    }
    int most = 0;
  } sink;
  Model work = model.Clone();
  Data data(work);
  std::vector<Assignment> all = sets;
  all.push_back(ParseAssignment(work, fmt::format("opt.timestep={:.17g}", dt)));
  ApplyAssignments(work, data, all);
  RunSpec spec;
  spec.until = until;
  spec.every = dt;
  spec.columns = {ResolvePath(work, "ncon")};
  spec.stop = stop;
  Run(work, data, spec, sink);
  TakeMujocoWarnings();  // the levels' own runs report them
  return sink.most;
}
}  // namespace

double ExpectedOrder(int integrator) { return integrator == mjINT_RK4 ? 4.0 : 1.0; }

namespace {

// The difference between two levels' measurements (a norm for state vectors).
double Distance(const Metric& metric, const Measurement& a, const Measurement& b) {
  if (metric.kind != MetricKind::kStateAt) return std::fabs(a.value - b.value);
  double sum = 0;
  for (std::size_t j = 0; j < a.state.size(); ++j) {
    double e = a.state[j] - b.state[j];
    sum += e * e;
  }
  return std::sqrt(sum);
}

// Successive differences of the levels' values (norms for state vectors).
std::vector<double> Differences(const Metric& metric, const std::vector<Measurement>& measured) {
  std::vector<double> diffs;
  for (std::size_t i = 0; i + 1 < measured.size(); ++i) {
    diffs.push_back(Distance(metric, measured[i], measured[i + 1]));
  }
  return diffs;
}

// Each level's spread: its largest difference to a finer level; the finest level's, its
// difference to the next coarser one.
void Spreads(const Metric& metric, const std::vector<Measurement>& measured,
             std::vector<ConvergenceLevel>* levels) {
  std::size_t n = measured.size();
  for (std::size_t i = 0; i < n; ++i) {
    double spread = i + 1 == n ? Distance(metric, measured[i - 1], measured[i]) : 0;
    for (std::size_t j = i + 1; j < n; ++j) {
      spread = std::max(spread, Distance(metric, measured[i], measured[j]));
    }
    (*levels)[i].spread = spread;
  }
}

// Estimated errors: against the extrapolated value, for state vectors the tail of the
// differences; a level whose difference is round-off has no error to show.
void LevelErrors(const Metric& metric, const std::vector<double>& diffs, ConvergenceResult* out) {
  std::size_t last = out->levels.size() - 1;
  for (std::size_t i = 0; i < out->levels.size(); ++i) {
    ConvergenceLevel& level = out->levels[i];
    level.error = kNaN;
    if (!out->estimate.resolved) continue;
    double p = out->estimate.order;
    if (out->estimate.noise_from >= 0) {
      // the finest levels agree to round-off: coarser levels' errors are their distance to
      // the finest value; the rest are in the noise
      if (static_cast<int>(i) < out->estimate.noise_from) {
        level.error = metric.kind == MetricKind::kStateAt
                          ? diffs[i] / (1 - std::pow(2.0, -p))
                          : std::fabs(level.value - out->estimate.extrapolated);
      }
    } else if (i == last) {
      // nothing finer to compare with: Richardson's estimate, labelled as such
      level.error = diffs.back() / (std::pow(2.0, p) - 1);
      level.error_is_richardson = true;
    } else if (metric.kind == MetricKind::kStateAt) {
      level.error = diffs[i] / (1 - std::pow(2.0, -p));
    } else {
      level.error = std::fabs(level.value - out->estimate.extrapolated);
    }
  }
}

// Recommends only a tested level, by the rule verify shares (RecommendedLevel).
void Recommend(double tol, ConvergenceResult* out) {
  int level = RecommendedLevel(out->levels, tol * out->scale);
  out->recommended_dt = level >= 0 ? out->levels[level].dt : 0;
  if (!out->estimate.resolved && out->recommended_dt > 0) {
    out->estimate.note +=
        "; the recommended dt is the coarsest level whose differences to all finer levels "
        "are within the tolerance";
  }
}

}  // namespace

bool LevelMeetsTolerance(const ConvergenceLevel& level, bool finest, double target) {
  bool estimated = std::isfinite(level.error);
  if (estimated && level.error > target) return false;
  if (finest && estimated) return true;  // nothing finer: Richardson's estimate is all there is
  return level.spread <= target || level.roundoff;
}

int RecommendedLevel(const std::vector<ConvergenceLevel>& levels, double target) {
  // walk up from the finest level while every level so far meets the tolerance
  int recommended = -1;
  for (int i = static_cast<int>(levels.size()) - 1; i >= 0; --i) {
    bool finest = i + 1 == static_cast<int>(levels.size());
    if (!LevelMeetsTolerance(levels[i], finest, target)) break;
    recommended = i;
  }
  return recommended;
}

std::vector<Assignment> HoldSolref(const Model& model, double floor, std::string* held) {
  std::vector<Assignment> out;
  std::vector<std::string> counts;
  const mjModel* m = model.get();
  std::vector<internal::SolrefBelow> below = internal::SolrefsBelow(m, floor);
  for (const compat::SolrefArray& a : compat::ClampedSolrefArrays(m)) {
    std::vector<double> values(a.data, a.data + a.rows * mjNREF);
    int raised = 0;
    for (const internal::SolrefBelow& row : below) {
      if (row.array != a.name) continue;
      values[static_cast<std::size_t>(row.row) * mjNREF] = floor;
      ++raised;
    }
    if (raised == 0) continue;
    Assignment set;
    set.text = fmt::format("{} (time constants below {:g} s raised to it)", a.name, floor);
    set.path = ResolvePath(model, a.name);
    set.values = std::move(values);
    out.push_back(std::move(set));
    counts.push_back(fmt::format("{} ({})", a.name, raised));
  }
  if (held != nullptr) *held = Join(counts, ", ");
  return out;
}

std::string SolrefNote(const ConvergenceResult& result) {
  if (result.solref_floor <= 0) return "";
  return fmt::format(
      "solref time constants below {0:g} s held at {0:g} s across levels (MuJoCo's 2*dt floor "
      "at the coarsest level), so every level runs the model the coarsest runs: {1}",
      result.solref_floor, result.solref_held);
}

ConvergenceResult Converge(const Model& model, const std::vector<Assignment>& sets,
                           const Metric& metric, double dt0, int halvings, double tol, double until,
                           const StopToken& stop) {
  if (halvings < 2) {
    throw ArgumentError("halvings", std::to_string(halvings),
                        "must be at least 2 to estimate an order");
  }
  if (!(dt0 > 0)) {
    throw ArgumentError("dt", fmt::format("{:g}", dt0), "must be a positive number of seconds");
  }
  ConvergenceResult out;
  out.model = model.file();
  out.metric = metric.text;
  out.until = until;
  out.tol = tol;
  std::vector<Assignment> level_sets = sets;
  {
    Model nominal = model.Clone();  // `sets` may choose the integrator and the solrefs
    Data data(nominal);
    ApplyAssignments(nominal, data, sets);
    out.integrator = nominal->opt.integrator;
    out.expected_order = ExpectedOrder(nominal->opt.integrator);
    // one model at every level: the solrefs MuJoCo runs at dt0, held as dt shrinks
    std::vector<Assignment> held = HoldSolref(nominal, 2 * dt0, &out.solref_held);
    if (!held.empty()) out.solref_floor = 2 * dt0;
    level_sets.insert(level_sets.end(), held.begin(), held.end());
  }
  std::vector<Measurement> measured;
  for (int k = 0; k <= halvings; ++k) {
    double dt = dt0 / std::pow(2.0, k);
    Measurement m;
    try {
      m = Measure(model, level_sets, metric, dt, until, stop);
    } catch (const MujocoError& e) {
      // one level's fatal error (an arena too small at this step size) is this level's
      // result, and the others still run
      m.ok = false;
      m.problem = FatalRunProblem(model, e.what());
    }
    if (!m.ok && out.ok) {
      out.ok = false;
      out.diverged = m.diverged;
      out.problem = "at dt = " + Str(dt) + " s: " + m.problem;
    }
    measured.push_back(m);
    ConvergenceLevel level;
    level.dt = dt;
    level.value = m.ok ? m.value : kNaN;
    level.diff = level.order = level.error = level.spread = kNaN;
    out.levels.push_back(level);
  }
  out.scale = measured.back().scale;
  if (!out.ok) return out;
  bool at_time = metric.kind == MetricKind::kValueAt || metric.kind == MetricKind::kStateAt;
  out.max_contacts = MaxContacts(model, level_sets, dt0, at_time ? metric.time : until, stop);
  out.caveat = ContactCaveat(out.max_contacts);

  std::vector<double> values;
  for (const Measurement& m : measured) values.push_back(m.value);
  std::vector<double> diffs = Differences(metric, measured);
  // round-off: a few ulps of the scale per step, accumulating like a random walk
  double steps = static_cast<double>(std::max(1L, measured.back().steps));
  double noise = 4 * std::numeric_limits<double>::epsilon() * out.scale * std::sqrt(steps);
  for (std::size_t i = 0; i < out.levels.size(); ++i) {
    out.levels[i].diff = i < diffs.size() ? diffs[i] : kNaN;
    out.levels[i].roundoff = i < diffs.size() && diffs[i] <= noise;
    // an order from a difference in the noise means nothing: left out
    bool clean = i + 1 < diffs.size() && diffs[i] > noise && diffs[i + 1] > noise;
    out.levels[i].order = clean ? std::log2(diffs[i] / diffs[i + 1]) : kNaN;
  }
  Spreads(metric, measured, &out.levels);
  out.estimate = EstimateOrder(values, diffs, noise);
  if (!diffs.empty() && out.estimate.noise_from == 0) {
    // even the coarsest pair agrees to round-off: dt0 is as good as any smaller step
    out.estimate.note =
        "every level agrees with the next to round-off (differences below " + Str(noise) +
        "): the result does not depend on the timestep at this precision, so dt0 is enough; "
        "the finest value is reported and no order can be measured";
    for (ConvergenceLevel& level : out.levels) level.error = kNaN;
    out.recommended_dt = dt0;  // every level meets any tolerance above round-off
    return out;
  }
  LevelErrors(metric, diffs, &out);
  Recommend(tol, &out);
  return out;
}

ConvergenceResult Converge(const Model& model, const Metric& metric,
                           const ConvergeOptions& options) {
  auto positive = [](const std::optional<double>& v, const char* argument, const char* what) {
    if (v && !(*v > 0 && std::isfinite(*v))) {
      throw ArgumentError(argument, fmt::format("{:g}", *v),
                          fmt::format("{} must be a positive, finite number", what));
    }
  };
  positive(options.dt, "dt", "the coarsest timestep (s)");
  positive(options.until, "until", "the run length (s)");
  positive(options.tol, "tol", "the relative tolerance");
  double dt0 = options.dt ? *options.dt : RunTimestep(model, options.sets);
  double until = options.until ? *options.until : DefaultDuration(metric);
  // the finest level takes the most steps
  if (options.until) {
    RequireStepsToReach(until, std::ldexp(dt0, -std::max(0, options.halvings)), "until", "",
                        "the timestep of the finest level");
  }
  ConvergenceResult r = Converge(model, options.sets, metric, dt0, options.halvings, options.tol,
                                 until, options.stop);
  if (!r.ok && !r.diverged) {
    throw ArgumentError("metric", Quoted(metric.text),
                        r.problem + ". Start the motion (set a qpos or qvel) or choose another metric.");
  }
  return r;
}

}  // namespace plumb
