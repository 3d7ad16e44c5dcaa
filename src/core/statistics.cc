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

}  // namespace plumb
