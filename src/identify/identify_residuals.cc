// The residuals' structure, the fit against nominal, and Newey–West standard errors
// (identify_residuals.h).

#include "identify/identify_residuals.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace plumb::internal {
namespace {

// The longest Newey–West bandwidth, as a fraction of a series' samples, from which its long-run
// variance is still estimated: beyond it the series holds fewer than about four independent
// stretches, and the standard errors are withheld.
constexpr double kMostBandwidth = 0.25;

// How much more the fitted model may cost than the nominal one, both replayed from the logged
// start on the same weights, before the fit counts as worse than nominal.
constexpr double kWorseThanNominal = 0.1;

// Residuals below this fraction of a signal's largest value are rounding, not noise: a log the
// model replays exactly (plumb's own) leaves such, with the structure rounding has.
constexpr double kRounding = 1e-9;

// What a divergence counts as, per sample, in units of the noise (as the fit's residuals).
constexpr double kDiverged = 1e6;

// The structured signal that departs most from white noise, or -1.
long MostStructured(const Misspecification& m) {
  long worst = -1;
  double most = 0;
  for (std::size_t i = 0; i < m.signals.size(); ++i) {
    const ResidualStructure& s = m.signals[i];
    double z = std::max(std::fabs(s.autocorrelation_z), std::fabs(s.runs_z));
    if (s.structured && z > most) most = z, worst = static_cast<long>(i);
  }
  return worst;
}

// One series for the sandwich: the rows of the residual vector it takes, time by time (a row
// of each signal sampled at that time).
struct Series {
  std::vector<std::vector<long>> rows;  // [time][signal]
};

// Each log's signals sampled at the same times as its first form one series (their errors at
// one time are as correlated as their lags); any other signal is a series of its own.
std::vector<Series> SeriesOf(const std::vector<RobotLog>& logs) {
  std::vector<Series> out;
  long at = 0;
  for (const RobotLog& log : logs) {
    std::size_t shared = out.size();
    for (std::size_t i = 0; i < log.measured.size(); ++i) {
      const LogSignal& s = log.measured[i];
      bool joins = i > 0 && s.time == log.measured.front().time;
      if (!joins) out.emplace_back();
      Series& series = joins ? out[shared] : out.back();
      series.rows.resize(s.value.size());
      for (std::size_t k = 0; k < s.value.size(); ++k) series.rows[k].push_back(at++);
    }
  }
  return out;
}

}  // namespace

double LagOneAutocorrelation(const std::vector<double>& e) {
  std::size_t n = e.size();
  if (n < 3) return NAN;
  double mean = 0;
  for (double v : e) mean += v / static_cast<double>(n);
  double lag = 0, var = 0;
  for (std::size_t k = 0; k < n; ++k) {
    var += (e[k] - mean) * (e[k] - mean);
    if (k + 1 < n) lag += (e[k] - mean) * (e[k + 1] - mean);
  }
  return var > 0 ? lag / var : NAN;
}

double RunsTestZ(const std::vector<double>& e) {
  double plus = 0, minus = 0, runs = 0;
  int last = 0;
  for (double v : e) {
    int sign = v > 0 ? 1 : v < 0 ? -1 : 0;
    if (sign == 0) continue;
    (sign > 0 ? plus : minus) += 1;
    if (sign != last) runs += 1;
    last = sign;
  }
  if (plus < 2 || minus < 2) return NAN;
  double n = plus + minus;
  double mean = 2 * plus * minus / n + 1;
  double var = 2 * plus * minus * (2 * plus * minus - n) / (n * n * (n - 1));
  return var > 0 ? (runs - mean) / std::sqrt(var) : NAN;
}

int NeweyWestBandwidth(long samples) {
  if (samples < 2) return 0;
  int rule = static_cast<int>(std::floor(4 * std::pow(samples / 100.0, 2.0 / 9.0)));
  return static_cast<int>(std::min<long>(rule, samples - 1));
}

double AndrewsBandwidth(const Eigen::MatrixXd& scores) {
  long n = scores.rows();
  if (n < 3) return 0;
  double top = 0, bottom = 0;
  for (long j = 0; j < scores.cols(); ++j) {
    Eigen::VectorXd now = scores.col(j).tail(n - 1), before = scores.col(j).head(n - 1);
    double lag = before.squaredNorm();
    if (!(lag > 0)) continue;  // a column the residuals do not move
    double rho = before.dot(now) / lag;
    if (rho >= 1) return INFINITY;
    double s2 = (now - rho * before).squaredNorm() / static_cast<double>(n - 1);
    top += 4 * rho * rho * s2 * s2 / (std::pow(1 - rho, 6) * (1 + rho) * (1 + rho));
    bottom += s2 * s2 / std::pow(1 - rho, 4);
  }
  return bottom > 0 ? 1.1447 * std::cbrt(top / bottom * static_cast<double>(n)) : 0;
}

Eigen::MatrixXd NeweyWestLongRun(const Eigen::MatrixXd& scores, int bandwidth) {
  long t = scores.rows();
  Eigen::MatrixXd s = scores.transpose() * scores;
  for (long l = 1; l <= bandwidth && l < t; ++l) {
    double w = 1 - static_cast<double>(l) / (bandwidth + 1);
    Eigen::MatrixXd gamma = scores.bottomRows(t - l).transpose() * scores.topRows(t - l);
    s += w * (gamma + gamma.transpose());
  }
  return s;
}

double NormalUpperQuantile(double p) {
  // bisection on the tail 0.5 erfc(z / sqrt 2), which falls monotonically in z
  double lo = -40, hi = 40;
  for (int i = 0; i < 200; ++i) {
    double mid = (lo + hi) / 2;
    (0.5 * std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
  }
  return (lo + hi) / 2;
}

double StructureThreshold(std::size_t signals) {
  double tests = 2.0 * static_cast<double>(std::max<std::size_t>(signals, 1));
  return std::max(4.0, NormalUpperQuantile(kStructureFalseAlarm / (2 * tests)));
}

void DiagnoseResiduals(const std::vector<RobotLog>& logs, const std::vector<double>& residuals,
                       const std::vector<std::vector<double>>& weights, IdentifyResult* result) {
  Misspecification& m = result->misspecification;
  std::size_t count = 0;
  for (const RobotLog& log : logs) count += log.measured.size();
  m.threshold = StructureThreshold(count);
  m.false_alarm = kStructureFalseAlarm;
  m.signals.clear();
  m.structured = 0;
  auto at = residuals.begin();
  for (std::size_t l = 0; l < logs.size(); ++l) {
    for (std::size_t i = 0; i < logs[l].measured.size(); ++i) {
      const std::vector<double>& logged = logs[l].measured[i].value;
      std::vector<double> e(at, at + static_cast<long>(logged.size()));
      at += static_cast<long>(logged.size());
      ResidualStructure r;
      r.log = logs[l].source;
      r.column = logs[l].measured[i].column;
      r.samples = static_cast<long>(e.size());
      double sum = 0, largest = 0;
      for (double v : e) sum += v * v;
      for (double y : logged) largest = std::max(largest, std::fabs(y));
      r.rms = r.samples > 0 ? std::sqrt(sum / static_cast<double>(r.samples)) * weights[l][i] : 0;
      r.exact = r.rms <= kRounding * largest;
      r.autocorrelation = LagOneAutocorrelation(e);
      r.autocorrelation_z = r.autocorrelation * std::sqrt(static_cast<double>(r.samples));
      r.runs_z = RunsTestZ(e);
      r.structured = !r.exact && (std::fabs(r.autocorrelation_z) > m.threshold ||
                                  std::fabs(r.runs_z) > m.threshold);
      m.structured += r.structured;
      m.signals.push_back(r);
    }
  }
}

double WeightedCost(const RobotLog& log, const ReplayResult& replay,
                    const std::vector<double>& weights) {
  double cost = 0;
  for (std::size_t i = 0; i < log.measured.size(); ++i) {
    const std::vector<double>& logged = log.measured[i].value;
    for (std::size_t k = 0; k < logged.size(); ++k) {
      double r = (replay.simulated.values[i][k] - logged[k]) / weights[i];
      if (!std::isfinite(r)) r = kDiverged;
      cost += r * r / 2;
    }
  }
  return cost;
}

void JudgeMisspecification(const std::vector<RobotLog>& logs,
                           const std::vector<std::vector<double>>& weights, std::size_t unknowns,
                           IdentifyResult* result) {
  Misspecification& m = result->misspecification;
  m.before_cost = m.after_cost = 0;
  for (std::size_t l = 0; l < logs.size(); ++l) {
    m.before_cost += WeightedCost(logs[l], result->before[l], weights[l]);
    m.after_cost += WeightedCost(logs[l], result->after[l], weights[l]);
  }
  // replayed from the logged start, not the fitted one, a right model's estimates can cost
  // more than nominal (when nominal is the truth) by the start's noise: over 20 seeds of the
  // pendulum, up to 3.8 %; worse means beyond kWorseThanNominal, and beyond 4 standard
  // deviations of a chi-square with `unknowns` degrees of freedom (twice the cost)
  double k = static_cast<double>(unknowns);
  m.worse_than_nominal = 2 * (m.after_cost - m.before_cost) > k + 4 * std::sqrt(2 * k) &&
                         m.after_cost > (1 + kWorseThanNominal) * m.before_cost;
  m.detected = m.structured > 0 || m.worse_than_nominal;
  std::string evidence;
  long worst = MostStructured(m);
  if (worst >= 0) {
    const ResidualStructure& s = m.signals[static_cast<std::size_t>(worst)];
    evidence = fmt::format(
        "{} of {} signals' residuals have structure over time that noise lacks (|z| > {:.2f}); "
        "the most: {} of {}, lag-1 autocorrelation {:.3f} (z {:.1f}), runs z {:.1f}",
        m.structured, m.signals.size(), m.threshold, s.column, s.log, s.autocorrelation,
        s.autocorrelation_z, s.runs_z);
  }
  if (m.worse_than_nominal) {
    evidence += fmt::format(
        "{}the fitted model replays the logs worse than the nominal one (cost {:.6g} against "
        "{:.6g}, in units of the noise)",
        evidence.empty() ? "" : "; ", m.after_cost, m.before_cost);
  }
  long exact = std::count_if(m.signals.begin(), m.signals.end(),
                             [](const ResidualStructure& s) { return s.exact; });
  std::string rounding =
      exact > 0 ? fmt::format(" ({} matched to rounding, which is not noise to judge)", exact) : "";
  m.reason = m.detected
                 ? "the model cannot explain the logs up to their noise: " + evidence
                 : fmt::format(
                       "none found: every signal's residuals look like white noise (lag-1 "
                       "autocorrelation and runs |z| <= {:.2f}){}, and the fit replays the logs "
                       "no worse than nominal",
                       m.threshold, rounding);
}

NormalInverse InvertNormal(const Eigen::MatrixXd& jacobian) {
  Eigen::VectorXd norms = jacobian.colwise().norm().transpose();
  Eigen::VectorXd scale = norms.unaryExpr([](double n) { return n > 0 ? 1 / n : 0.0; });
  // J itself is decomposed, not J'J, whose condition number would be J's squared
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> decomposition(jacobian *
                                                                        scale.asDiagonal());
  NormalInverse out;
  out.rank = decomposition.rank();
  for (long j = 0; j < norms.size(); ++j) {
    if (!(norms[j] > 0)) out.rank = std::min(out.rank, norms.size() - 1);
  }
  Eigen::MatrixXd pseudo = decomposition.pseudoInverse();  // n x m
  out.inverse = scale.asDiagonal() * (pseudo * pseudo.transpose()) * scale.asDiagonal();
  return out;
}

bool NeweyWestCovariance(const std::vector<RobotLog>& logs, const Eigen::MatrixXd& jacobian,
                         const std::vector<double>& residuals, long parameters,
                         Eigen::MatrixXd* covariance, int* bandwidth, std::string* why) {
  long m = jacobian.rows(), p = jacobian.cols();
  NormalInverse bread = InvertNormal(jacobian);
  if (bread.rank < p) {
    *why = "the Jacobian is rank deficient, so no sandwich can be formed";
    return false;
  }
  Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(p, p);
  *bandwidth = 0;
  for (const Series& series : SeriesOf(logs)) {
    long t = static_cast<long>(series.rows.size());
    Eigen::MatrixXd scores = Eigen::MatrixXd::Zero(t, p);
    for (long k = 0; k < t; ++k) {
      for (long row : series.rows[static_cast<std::size_t>(k)]) {
        scores.row(k) += jacobian.row(row) * residuals[static_cast<std::size_t>(row)];
      }
    }
    // the lags the model parameters' scores need, at least Newey and West's rule
    double need =
        std::max<double>(NeweyWestBandwidth(t), AndrewsBandwidth(scores.leftCols(parameters)));
    if (!(need <= kMostBandwidth * static_cast<double>(t))) {
      *why = fmt::format(
          "the residuals stay correlated too long: a series of {} samples would need {} lags, "
          "and its variance cannot be estimated beyond {:.0f} ({:.0f} % of it)",
          t, std::isfinite(need) ? fmt::format("about {:.0f}", need) : std::string("all its"),
          kMostBandwidth * static_cast<double>(t), 100 * kMostBandwidth);
      return false;
    }
    int l = static_cast<int>(std::ceil(need));
    *bandwidth = std::max(*bandwidth, l);
    meat += NeweyWestLongRun(scores, l);
  }
  const Eigen::MatrixXd& inverse = bread.inverse;
  *covariance = inverse * meat * inverse * (static_cast<double>(m) / static_cast<double>(m - p));
  if (!covariance->allFinite()) {
    *why = "the sandwich is not finite (a divergence in the residuals)";
    return false;
  }
  return true;
}

void JudgeFit(const std::vector<RobotLog>& logs, const std::vector<FitParameter>& params,
              const Eigen::MatrixXd& jacobian, const std::vector<double>& residuals,
              const std::vector<std::vector<double>>& weights, IdentifyResult* result) {
  DiagnoseResiduals(logs, residuals, weights, result);
  JudgeMisspecification(logs, weights, static_cast<std::size_t>(jacobian.cols()), result);
  StdErrors& se = result->std_errors;
  if (!result->misspecification.detected) {
    se.kind = StdErrorKind::kClassical;
    se.why = "classical (the Jacobian and the residual variance): no misspecification found";
    return;
  }
  Eigen::MatrixXd cov;
  std::string why;
  long parameters = static_cast<long>(params.size());
  if (!NeweyWestCovariance(logs, jacobian, residuals, parameters, &cov, &se.bandwidth, &why)) {
    se.kind = StdErrorKind::kWithheld;
    se.why =
        "withheld: the model is misspecified, so the classical ones would be too small, "
        "and Newey–West's cannot be had: " +
        why;
    for (Estimate& e : result->estimates) e.std_error = NAN;
    return;
  }
  se.kind = StdErrorKind::kNeweyWest;
  se.why = fmt::format(
      "Newey–West (Bartlett kernel, {} lags), or the classical one where that is larger: the "
      "model is misspecified and its residuals correlate over time, which the classical ones "
      "ignore; they cover the noise's effect, not the bias a wrong model gives the estimates",
      se.bandwidth);
  for (std::size_t i = 0; i < result->estimates.size(); ++i) {
    // never below the classical one: that pools the misfit of the signals the model cannot
    // explain into its variance, where the sandwich weighs each signal by its own residuals
    Estimate& e = result->estimates[i];
    double v = cov(static_cast<long>(i), static_cast<long>(i));
    double robust = v >= 0 ? std::sqrt(v) * params[i].scale : NAN;
    e.std_error =
        std::isfinite(e.classical_std_error) ? std::max(robust, e.classical_std_error) : robust;
  }
}

}  // namespace plumb::internal

// the public part (plumb/identify.h)
namespace plumb {

std::string DescribeResidualVariance(const IdentifyResult& r) {
  if (!r.misspecification.detected) {
    return fmt::format(
        "residual variance {:.3g} (about 1 when the model explains all but the noise; no "
        "misspecification found)",
        r.residual_variance);
  }
  return fmt::format(
      "residual variance {:.3g}: no sign of a good fit here, since the model is misspecified "
      "(a fit weighted by its residuals' own rms gives about 1 whatever the model)",
      r.residual_variance);
}

const char* StdErrorKindName(StdErrorKind kind) {
  switch (kind) {
    case StdErrorKind::kClassical:
      return "classical";
    case StdErrorKind::kNeweyWest:
      return "newey-west";
    case StdErrorKind::kWithheld:
      return "withheld";
  }
  return "classical";
}

}  // namespace plumb
