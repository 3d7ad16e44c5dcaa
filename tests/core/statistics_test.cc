#include "plumb/statistics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace plumb {
namespace {

// The q-quantile of `v` by linear interpolation between order statistics.
double Exact(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  double at = q * static_cast<double>(v.size() - 1);
  std::size_t lo = static_cast<std::size_t>(at), hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (at - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

TEST(SummaryStatisticsTest, NothingYetIsNaNAndInfinities) {
  SummaryStatistics s;
  EXPECT_EQ(s.count(), 0);
  EXPECT_TRUE(std::isnan(s.q50()));
  EXPECT_EQ(s.min(), INFINITY);
  EXPECT_EQ(s.max(), -INFINITY);
  EXPECT_EQ(s.stddev(), 0);
}

TEST(SummaryStatisticsTest, SmallBatchesAreExactAndNaNIsCountedApart) {
  SummaryStatistics s;
  std::vector<double> v = {3, 1, 4, 1, 5, 9, 2, 6};
  for (double x : v) s.Add(x);
  s.Add(NAN);
  EXPECT_EQ(s.count(), 8);
  EXPECT_EQ(s.missing(), 1);
  EXPECT_DOUBLE_EQ(s.mean(), 31.0 / 8);
  double m2 = 0;
  for (double x : v) m2 += (x - 31.0 / 8) * (x - 31.0 / 8);
  EXPECT_NEAR(s.stddev(), std::sqrt(m2 / 7), 1e-12);
  EXPECT_EQ(s.min(), 1);
  EXPECT_EQ(s.max(), 9);
  EXPECT_DOUBLE_EQ(s.q05(), Exact(v, 0.05));
  EXPECT_DOUBLE_EQ(s.q50(), Exact(v, 0.5));  // 3.5
  EXPECT_DOUBLE_EQ(s.q95(), Exact(v, 0.95));
}

TEST(SummaryStatisticsTest, WelfordHoldsItsDigitsFarFromZero) {
  // the textbook sum-of-squares formula loses every digit of a spread of 1 around 1e9
  SummaryStatistics s;
  for (int i = 0; i < 1000; ++i) s.Add(1e9 + (i % 2 == 0 ? 1 : -1));
  EXPECT_NEAR(s.mean(), 1e9, 1e-6);
  EXPECT_NEAR(s.stddev(), std::sqrt(1000.0 / 999.0), 1e-9);
}

TEST(SummaryStatisticsTest, LargeBatchesEstimateQuantilesInFixedMemory) {
  // 200 000 draws (past the 4096 kept exactly): the P-square estimates land within 1 % of the
  // distribution's spread of the exact quantiles, for a uniform and a skewed distribution
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uniform(-2, 3);
  std::exponential_distribution<double> skewed(1.5);
  for (int kind = 0; kind < 2; ++kind) {
    SummaryStatistics s;
    std::vector<double> all;
    for (int i = 0; i < 200000; ++i) {
      double x = kind == 0 ? uniform(rng) : skewed(rng);
      s.Add(x);
      all.push_back(x);
    }
    double spread = Exact(all, 0.95) - Exact(all, 0.05);
    EXPECT_NEAR(s.q05(), Exact(all, 0.05), 0.01 * spread) << kind;
    EXPECT_NEAR(s.q50(), Exact(all, 0.5), 0.01 * spread) << kind;
    EXPECT_NEAR(s.q95(), Exact(all, 0.95), 0.01 * spread) << kind;
    EXPECT_EQ(s.count(), 200000);
  }
}

TEST(P2QuantileTest, FewerThanFiveValuesInterpolateExactly) {
  P2Quantile median(0.5);
  EXPECT_TRUE(std::isnan(median.Value()));
  median.Add(10);
  median.Add(0);
  EXPECT_DOUBLE_EQ(median.Value(), 5);
  median.Add(4);
  EXPECT_DOUBLE_EQ(median.Value(), 4);
}

}  // namespace
}  // namespace plumb
