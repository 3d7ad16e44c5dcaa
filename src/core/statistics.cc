#include "plumb/statistics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace plumb {
namespace {

// The p-quantile of n (> 0) sorted values, interpolated linearly between order statistics.
double SortedQuantile(const double* sorted, long n, double p) {
  double at = p * static_cast<double>(n - 1);
  long lo = static_cast<long>(at);
  long hi = std::min<long>(lo + 1, n - 1);
  return sorted[lo] + (at - static_cast<double>(lo)) * (sorted[hi] - sorted[lo]);
}

}  // namespace

void P2Quantile::Add(double x) {
  if (n_ < 5) {
    q_[n_++] = x;
    if (n_ == 5) {
      std::stable_sort(q_.begin(), q_.end());
      for (int i = 0; i < 5; ++i) pos_[i] = i + 1;
      want_ = {1, 1 + 2 * p_, 1 + 4 * p_, 3 + 2 * p_, 5};
      step_ = {0, p_ / 2, p_, (1 + p_) / 2, 1};
    }
    return;
  }
  ++n_;
  // the cell x falls in; stretch the extremes
  int k;
  if (x < q_[0]) {
    q_[0] = x;
    k = 0;
  } else if (x >= q_[4]) {
    q_[4] = std::max(q_[4], x);
    k = 3;
  } else {
    k = 0;
    while (k < 3 && x >= q_[k + 1]) ++k;
  }
  for (int i = k + 1; i < 5; ++i) pos_[i] += 1;
  for (int i = 0; i < 5; ++i) want_[i] += step_[i];
  // move the middle markers toward their desired positions (parabolic, else linear)
  for (int i = 1; i <= 3; ++i) {
    double d = want_[i] - pos_[i];
    if ((d >= 1 && pos_[i + 1] - pos_[i] > 1) || (d <= -1 && pos_[i - 1] - pos_[i] < -1)) {
      int s = d > 0 ? 1 : -1;
      double parabolic =
          q_[i] + s / (pos_[i + 1] - pos_[i - 1]) *
                      ((pos_[i] - pos_[i - 1] + s) * (q_[i + 1] - q_[i]) / (pos_[i + 1] - pos_[i]) +
                       (pos_[i + 1] - pos_[i] - s) * (q_[i] - q_[i - 1]) / (pos_[i] - pos_[i - 1]));
      if (q_[i - 1] < parabolic && parabolic < q_[i + 1]) {
        q_[i] = parabolic;
      } else {
        q_[i] += s * (q_[i + s] - q_[i]) / (pos_[i + s] - pos_[i]);
      }
      pos_[i] += s;
    }
  }
}

double P2Quantile::Value() const {
  if (n_ == 0) return NAN;
  if (n_ < 5) {
    std::array<double, 5> sorted = q_;
    std::stable_sort(sorted.begin(), sorted.begin() + n_);
    return SortedQuantile(sorted.data(), n_, p_);
  }
  return q_[2];
}

void SummaryStatistics::Add(double x) {
  if (std::isnan(x)) {
    ++missing_;
    return;
  }
  ++n_;
  double delta = x - mean_;
  mean_ += delta / n_;
  m2_ += delta * (x - mean_);
  min_ = std::min(min_, x);
  max_ = std::max(max_, x);
  q05_.Add(x);
  q50_.Add(x);
  q95_.Add(x);
  if (n_ <= kExact) {
    exact_.push_back(x);
  } else if (!exact_.empty()) {
    exact_.clear();
    exact_.shrink_to_fit();
  }
}

double SummaryStatistics::Quantile(double p, const P2Quantile& estimate) const {
  if (n_ == 0) return NAN;
  if (n_ > kExact) return estimate.Value();
  std::vector<double> sorted = exact_;
  std::sort(sorted.begin(), sorted.end());
  return SortedQuantile(sorted.data(), n_, p);
}

namespace {

// The continued fraction of the regularized incomplete beta function (modified Lentz's method).
double BetaFraction(double a, double b, double x) {
  constexpr double kTiny = 1e-300;
  double c = 1, d = 1 - (a + b) * x / (a + 1);
  d = 1 / (std::abs(d) < kTiny ? kTiny : d);
  double h = d;
  for (int m = 1; m <= 300; ++m) {
    for (int odd = 0; odd < 2; ++odd) {
      const double num = odd == 0 ? m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m))
                                  : -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1));
      d = 1 + num * d;
      d = 1 / (std::abs(d) < kTiny ? kTiny : d);
      c = 1 + num / c;
      if (std::abs(c) < kTiny) c = kTiny;
      h *= d * c;
      if (odd == 1 && std::abs(d * c - 1) < 1e-15) return h;
    }
  }
  return h;
}

// I_x(a, b).
double RegularizedBeta(double a, double b, double x) {
  if (x <= 0) return 0;
  if (x >= 1) return 1;
  const double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) +
                                a * std::log(x) + b * std::log1p(-x));
  if (x < (a + 1) / (a + b + 2)) return front * BetaFraction(a, b, x) / a;
  return 1 - front * BetaFraction(b, a, 1 - x) / b;
}

}  // namespace

double StudentTCdf(double t, double dof) {
  if (std::isnan(t) || !(dof > 0)) return NAN;
  if (std::isinf(t)) return t > 0 ? 1 : 0;
  const double tail = 0.5 * RegularizedBeta(0.5 * dof, 0.5, dof / (dof + t * t));
  return t > 0 ? 1 - tail : tail;
}

double StudentTQuantile(double p, double dof) {
  if (!(p > 0 && p < 1) || !(dof > 0)) return NAN;
  double lo = -1, hi = 1;
  while (StudentTCdf(lo, dof) > p) lo *= 2;
  while (StudentTCdf(hi, dof) < p) hi *= 2;
  for (int i = 0; i < 200 && hi - lo > 1e-12 * std::max(1.0, std::abs(hi)); ++i) {
    const double mid = 0.5 * (lo + hi);
    (StudentTCdf(mid, dof) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

EquivalenceTest PairedEquivalence(const std::vector<double>& differences, double margin,
                                  double alpha) {
  EquivalenceTest test;
  test.margin = margin;
  test.alpha = alpha;
  SummaryStatistics s;
  for (double d : differences) {
    if (std::isfinite(d)) s.Add(d);
  }
  test.n = s.count();
  if (test.n < 2) return test;
  test.mean = s.mean();
  test.standard_error = s.stddev() / std::sqrt(static_cast<double>(test.n));
  const double dof = static_cast<double>(test.n - 1);
  if (test.standard_error == 0) {  // every difference the same
    test.lower = test.upper = test.mean;
    test.p_value = std::abs(test.mean) < margin ? 0 : 1;
  } else {
    const double p_low = 1 - StudentTCdf((test.mean + margin) / test.standard_error, dof);
    const double p_high = StudentTCdf((test.mean - margin) / test.standard_error, dof);
    test.p_value = std::max(p_low, p_high);
    const double t = StudentTQuantile(1 - alpha, dof);
    test.lower = test.mean - t * test.standard_error;
    test.upper = test.mean + t * test.standard_error;
  }
  test.equivalent = test.p_value < alpha;
  return test;
}

}  // namespace plumb
