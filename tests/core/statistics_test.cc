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

TEST(StudentTTest, CdfAndQuantileMatchTabulatedValues) {
  // tabulated: P(T <= 2) = 0.963306 with 10 degrees of freedom; t(0.975, 10) = 2.228139;
  // one degree of freedom is Cauchy's: P(T <= 1) = 0.75
  EXPECT_NEAR(StudentTCdf(2.0, 10), 0.9633060, 1e-6);
  EXPECT_NEAR(StudentTCdf(-2.0, 10), 1 - 0.9633060, 1e-6);
  EXPECT_NEAR(StudentTCdf(1.0, 1), 0.75, 1e-12);
  EXPECT_DOUBLE_EQ(StudentTCdf(0.0, 3), 0.5);
  EXPECT_NEAR(StudentTQuantile(0.975, 10), 2.228139, 1e-6);
  EXPECT_NEAR(StudentTQuantile(0.95, 30), 1.697261, 1e-6);
  EXPECT_NEAR(StudentTQuantile(0.95, 1e6), 1.644854, 1e-5);  // the normal's
  EXPECT_TRUE(std::isnan(StudentTCdf(NAN, 4)));
  EXPECT_TRUE(std::isnan(StudentTQuantile(1.0, 4)));
}

TEST(EquivalenceTest, TwoOneSidedTestsDecideOnlyWithEvidence) {
  // small differences, many samples: equivalent within 0.1
  std::vector<double> small;
  for (int i = 0; i < 40; ++i) small.push_back(0.01 * ((i % 5) - 2));
  EquivalenceTest a = PairedEquivalence(small, 0.1, 0.05);
  EXPECT_TRUE(a.equivalent);
  EXPECT_EQ(a.n, 40);
  EXPECT_NEAR(a.mean, 0, 1e-12);
  EXPECT_LT(a.upper, 0.1);
  EXPECT_GT(a.lower, -0.1);
  // the same spread with three samples: not shown (no difference shown either)
  EquivalenceTest b = PairedEquivalence({0.05, -0.05, 0.06}, 0.1, 0.05);
  EXPECT_FALSE(b.equivalent);
  EXPECT_LT(b.lower, -0.1 + 0.2);
  EXPECT_GT(b.upper, 0.1 - 0.2);
  // a clear offset beyond the margin: not equivalent, interval outside
  std::vector<double> offset;
  for (int i = 0; i < 30; ++i) offset.push_back(0.5 + 0.01 * (i % 3));
  EquivalenceTest c = PairedEquivalence(offset, 0.1, 0.05);
  EXPECT_FALSE(c.equivalent);
  EXPECT_GT(c.lower, 0.1);
  // identical values: equivalent when inside the margin, with p 0; NaN left out
  EquivalenceTest d = PairedEquivalence({0.0, 0.0, NAN, 0.0}, 0.1, 0.05);
  EXPECT_TRUE(d.equivalent);
  EXPECT_EQ(d.n, 3);
  EXPECT_EQ(d.p_value, 0);
  // p-value: one-sided t tests by hand for mean 0.05, se 0.02, margin 0.1, 9 dof
  std::vector<double> e = {0.05 - 0.06, 0.05 + 0.06, 0.05, 0.05, 0.05 - 0.03,
                           0.05 + 0.03, 0.05,        0.05, 0.05, 0.05};
  EquivalenceTest f = PairedEquivalence(e, 0.1, 0.05);
  const double se = f.standard_error;
  EXPECT_NEAR(f.p_value, StudentTCdf((0.05 - 0.1) / se, 9), 1e-12);
}

}  // namespace
}  // namespace plumb
