#include "plumb/converge.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "plumb/error.h"

namespace plumb {

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

double ExpectedOrder(int integrator) { return integrator == mjINT_RK4 ? 4.0 : 1.0; }

ConvergenceResult Converge(const Model& model, const std::vector<Assignment>& sets,
                           const Metric& metric, double dt0, int halvings, double tol,
                           double until) {
  if (halvings < 2) throw ValueError("--halvings must be at least 2 to estimate an order");
  if (!(dt0 > 0)) throw ValueError("--dt must be a positive number of seconds");
  ConvergenceResult out;
  out.metric = metric.text;
  out.tol = tol;
  std::vector<Measurement> measured;
  for (int k = 0; k <= halvings; ++k) {
    double dt = dt0 / std::pow(2.0, k);
    Measurement m = Measure(model, sets, metric, dt, until);
    if (!m.ok && out.ok) {
      out.ok = false;
      out.diverged = m.diverged;
      out.problem = "at dt = " + Str(dt) + " s: " + m.problem;
    }
    measured.push_back(m);
    ConvergenceLevel level;
    level.dt = dt;
    level.value = m.ok ? m.value : kNaN;
    level.diff = level.order = level.error = kNaN;
    out.levels.push_back(level);
  }
  out.scale = measured.back().scale;
  if (!out.ok) return out;

  // successive differences (norms for state vectors) and local orders
  std::vector<double> values, diffs;
  for (std::size_t i = 0; i < measured.size(); ++i) {
    values.push_back(measured[i].value);
    if (i + 1 == measured.size()) break;
    double diff = 0;
    if (metric.kind == MetricKind::kStateAt) {
      for (std::size_t j = 0; j < measured[i].state.size(); ++j) {
        double e = measured[i].state[j] - measured[i + 1].state[j];
        diff += e * e;
      }
      diff = std::sqrt(diff);
    } else {
      diff = std::fabs(measured[i].value - measured[i + 1].value);
    }
    diffs.push_back(diff);
  }
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
  out.estimate = EstimateOrder(values, diffs, noise);
  if (!diffs.empty() && out.estimate.noise_from == 0) {
    // even the coarsest pair agrees to round-off: dt0 is as good as any smaller step
    out.recommended_dt = dt0;
    out.estimate.note =
        "every level agrees with the next to round-off (differences below " + Str(noise) +
        "): the result does not depend on the timestep at this precision, so dt0 is enough; "
        "the finest value is reported and no order can be measured";
    for (ConvergenceLevel& level : out.levels) level.error = kNaN;
    return out;
  }

  // estimated errors; for state vectors the difference to the finest level stands in
  for (std::size_t i = 0; i < out.levels.size(); ++i) {
    if (!out.estimate.resolved) {
      out.levels[i].error = kNaN;
    } else if (metric.kind == MetricKind::kStateAt) {
      double p = out.estimate.order;
      // sum of the geometric tail of differences beyond level i
      out.levels[i].error = i < diffs.size() ? diffs[i] / (1 - std::pow(2.0, -p)) : 0;
    } else {
      out.levels[i].error = std::fabs(out.levels[i].value - out.estimate.extrapolated);
    }
  }
  if (!out.estimate.resolved) {
    // without an order, a level whose difference to every finer one is within tolerance
    // is still converged: its error is about its difference (less for higher orders)
    for (std::size_t i = diffs.size(); i-- > 0 && diffs[i] <= tol * out.scale;) {
      out.recommended_dt = out.levels[i].dt;
    }
    if (out.recommended_dt > 0) {
      out.estimate.note +=
          "; the recommended dt is the coarsest level whose differences to all "
          "finer levels are within the tolerance";
    }
  }
  // the largest dt0 * 2^-k (k >= -1) whose predicted error meets tol * scale
  if (out.estimate.resolved) {
    double p = out.estimate.order;
    double err0 = out.levels[0].error;
    double target = tol * out.scale;
    for (int k = -1; k <= 30; ++k) {
      double predicted = err0 * std::pow(2.0, -p * k);
      if (predicted <= target) {
        out.recommended_dt = dt0 * std::pow(2.0, -k);
        break;
      }
    }
  }
  return out;
}

}  // namespace plumb
