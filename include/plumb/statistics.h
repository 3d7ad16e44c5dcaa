// Streaming summary statistics of a batch's metric (plumb rollout's summary, a Python
// caller's own loop): count, mean, standard deviation (Welford), min, max and the 5 %, 50 %
// and 95 % quantiles (exact for the first 4096 values, then the P-square estimator of Jain
// and Chlamtac, 1985), in memory that does not grow however many values arrive.
//
// Example:
//   plumb::SummaryStatistics s;
//   for (double x : values) s.Add(x);   // NaN is counted apart (missing)
//   std::printf("%g +- %g, median %g\n", s.mean(), s.stddev(), s.q50());
//
// Thread-safety: one object per thread (Add writes it); const methods may run at once on an
// object no thread is adding to. Nothing throws but std::bad_alloc (the first 4096 values are
// kept).

#ifndef PLUMB_INCLUDE_PLUMB_STATISTICS_H_
#define PLUMB_INCLUDE_PLUMB_STATISTICS_H_

#include <array>
#include <cmath>
#include <vector>

namespace plumb {

// One quantile p in (0, 1), estimated with five markers (P-square). NaN before any value.
class P2Quantile {
 public:
  explicit P2Quantile(double p) : p_(p) {}
  void Add(double x);
  double Value() const;

 private:
  double p_;
  long n_ = 0;
  std::array<double, 5> q_{}, pos_{}, want_{}, step_{};
};

class SummaryStatistics {
 public:
  void Add(double x);                // NaN values are counted apart
  long count() const { return n_; }  // values other than NaN
  long missing() const { return missing_; }
  double mean() const { return mean_; }
  double stddev() const { return n_ > 1 ? std::sqrt(m2_ / (n_ - 1)) : 0; }  // sample (n - 1)
  double min() const { return min_; }                                       // +inf before any value
  double max() const { return max_; }                                       // -inf before any value
  // Linear interpolation between order statistics while at most kExact values arrived, the
  // P-square estimate beyond. NaN before any value.
  double q05() const { return Quantile(0.05, q05_); }
  double q50() const { return Quantile(0.5, q50_); }
  double q95() const { return Quantile(0.95, q95_); }
  static constexpr long kExact = 4096;

 private:
  double Quantile(double p, const P2Quantile& estimate) const;
  std::vector<double> exact_;
  long n_ = 0, missing_ = 0;
  double mean_ = 0, m2_ = 0, min_ = INFINITY, max_ = -INFINITY;
  P2Quantile q05_{0.05}, q50_{0.5}, q95_{0.95};
};

// P(T <= t) for Student's t distribution with `dof` > 0 degrees of freedom (through the
// regularized incomplete beta function); NaN for a NaN argument.
double StudentTCdf(double t, double dof);

// The t value with P(T <= t) = p, for p in (0, 1) (bisection on StudentTCdf, to 1e-12).
double StudentTQuantile(double p, double dof);

// Two one-sided tests (Schuirmann, 1987) on paired differences d_i = a_i - b_i: the evidence
// that the mean difference lies within (-margin, +margin). Both one-sided nulls (mean <= -margin,
// mean >= +margin) are rejected at level alpha exactly when the 1 - 2 alpha confidence interval
// of the mean lies inside the margin. "Not significantly different" is not this: too few
// samples or too much spread leave a TOST undecided (equivalent false), never falsely sure.
struct EquivalenceTest {
  long n = 0;                       // finite differences used
  double mean = NAN;                // of the differences
  double standard_error = NAN;      // of the mean
  double lower = NAN, upper = NAN;  // the 1 - 2 alpha confidence interval of the mean
  double p_value = NAN;             // the larger of the two one-sided p-values
  double margin = 0, alpha = 0;
  bool equivalent = false;  // p_value < alpha (needs n >= 2)
};
EquivalenceTest PairedEquivalence(const std::vector<double>& differences, double margin,
                                  double alpha);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_STATISTICS_H_
