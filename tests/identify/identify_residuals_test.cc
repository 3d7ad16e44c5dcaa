// The residuals' tests and the Newey–West sandwich of plumb identify, on series whose answers
// are known by hand or by theory.

#include "identify/identify_residuals.h"

#include <gtest/gtest.h>

#include <random>

namespace plumb {
using internal::AndrewsBandwidth;
using internal::DiagnoseResiduals;
using internal::JudgeMisspecification;
using internal::LagOneAutocorrelation;
using internal::NeweyWestBandwidth;
using internal::NeweyWestCovariance;
using internal::NeweyWestLongRun;
using internal::NormalUpperQuantile;
using internal::RunsTestZ;
using internal::StructureThreshold;

namespace {

// `n` draws of an AR(1), x_k = rho x_k-1 + e_k with unit normal e, from seed `seed`.
std::vector<double> Ar1(std::size_t n, double rho, unsigned seed) {
  std::mt19937_64 random(seed);
  std::normal_distribution<double> gauss;
  std::vector<double> x(n);
  double last = 0;
  for (double& v : x) v = last = rho * last + gauss(random);
  return x;
}

// A log of one measured signal per series of `values`, each at times 0, 1, 2, ... (all share
// their times, so the sandwich takes them as one series).
RobotLog LogOf(const std::vector<std::vector<double>>& values) {
  RobotLog log;
  log.source = "synthetic.csv";
  for (std::size_t i = 0; i < values.size(); ++i) {
    LogSignal s;
    s.column = "signal" + std::to_string(i);
    for (std::size_t k = 0; k < values[i].size(); ++k) s.time.push_back(static_cast<double>(k));
    s.value = values[i];
    log.measured.push_back(s);
  }
  return log;
}

// Signs by hand: +++--- has 2 runs where 3 and 3 give 4 on average, variance
// 2 * 9 * (18 - 6) / (36 * 5) = 1.2; ++--+- has the average 4; ten alternations, 20 runs
// against 11, variance 2 * 100 * 180 / (400 * 19).
TEST(IdentifyResidualsTest, TheRunsTestCountsRunsOfOneSign) {
  EXPECT_NEAR(RunsTestZ({1, 2, 3, -1, -2, -3}), -2 / std::sqrt(1.2), 1e-12);
  EXPECT_NEAR(RunsTestZ({1, 1, -1, -1, 1, -1}), 0, 1e-12);
  std::vector<double> alternating;
  for (int k = 0; k < 20; ++k) alternating.push_back(k % 2 == 0 ? 1 : -1);
  EXPECT_NEAR(RunsTestZ(alternating), 9 / std::sqrt(36000.0 / 7600), 1e-12);
  EXPECT_NEAR(RunsTestZ({1, 0, 2, 0, 3, -1, -2, -3}), -2 / std::sqrt(1.2), 1e-12);  // zeros skip
  EXPECT_TRUE(std::isnan(RunsTestZ({1, 2, 3, 4, -1})));  // one sign has a single sample
}

TEST(IdentifyResidualsTest, LagOneAutocorrelationOfKnownSeries) {
  std::vector<double> alternating;
  for (int k = 0; k < 1000; ++k) alternating.push_back(k % 2 == 0 ? 1 : -1);
  EXPECT_NEAR(LagOneAutocorrelation(alternating), -1, 2e-3);
  EXPECT_NEAR(LagOneAutocorrelation(Ar1(20000, 0.8, 1)), 0.8, 0.01);  // sd 0.6 / sqrt(20000)
  EXPECT_NEAR(LagOneAutocorrelation(Ar1(20000, 0, 2)), 0, 0.03);
  EXPECT_TRUE(std::isnan(LagOneAutocorrelation({2, 2, 2, 2})));
  EXPECT_TRUE(std::isnan(LagOneAutocorrelation({1, 2})));
}

// floor(4 (n / 100)^(2/9)): 4 at 100 samples, 5 at 500 (4 x 1.430), 6 at 1000 (4 x 1.668).
TEST(IdentifyResidualsTest, NeweyWestsBandwidthRule) {
  EXPECT_EQ(NeweyWestBandwidth(100), 4);
  EXPECT_EQ(NeweyWestBandwidth(500), 5);
  EXPECT_EQ(NeweyWestBandwidth(1000), 6);
  EXPECT_EQ(NeweyWestBandwidth(2), 1);
  EXPECT_EQ(NeweyWestBandwidth(1), 0);
}

// A constant score of 1 over 10 times with 2 lags: 10 + 2 (2/3 x 9 + 1/3 x 8).
TEST(IdentifyResidualsTest, NeweyWestLongRunByHand) {
  Eigen::MatrixXd ones = Eigen::MatrixXd::Ones(10, 1);
  EXPECT_NEAR(NeweyWestLongRun(ones, 2)(0, 0), 10 + 2 * (6 + 8.0 / 3), 1e-12);
  EXPECT_NEAR(NeweyWestLongRun(ones, 0)(0, 0), 10, 1e-12);
}

// An MA(1), x_k = e_k + e_k-1, has variance 2 and long-run variance (1 + 1)^2 = 4; the
// Bartlett kernel with 20 lags weighs the lag-1 covariance by 20/21: 2 + 2 x 20/21. White
// noise's long-run variance is its variance. Two columns give a symmetric matrix.
TEST(IdentifyResidualsTest, NeweyWestLongRunOfKnownProcesses) {
  const long n = 200000;
  std::vector<double> e = Ar1(n + 1, 0, 3);
  Eigen::MatrixXd scores(n, 2);
  for (long k = 0; k < n; ++k) scores(k, 0) = e[k + 1] + e[k], scores(k, 1) = e[k + 1];
  Eigen::MatrixXd s = NeweyWestLongRun(scores, 20) / static_cast<double>(n);
  EXPECT_NEAR(s(0, 0), 2 + 2 * 20.0 / 21, 0.08);
  EXPECT_NEAR(s(1, 1), 1, 0.02);
  EXPECT_NEAR(s(0, 1), s(1, 0), 1e-9);
  EXPECT_NEAR(s(0, 1), 1 + 20.0 / 21, 0.05);  // cov(x_k, e_k) + cov(x_k+1, e_k) at weight 20/21
}

// Andrews's AR(1) rule: alpha = 4 rho^2 / ((1 - rho)^2 (1 + rho)^2), 1.778 at rho = 0.5, so
// 1.1447 (1.778 x 1000)^(1/3) = 13.9 lags for 1000 samples, and 246 at rho = 0.99; white noise
// needs about none.
TEST(IdentifyResidualsTest, AndrewsBandwidthGrowsWithCorrelation) {
  std::vector<double> x = Ar1(1000, 0.5, 4);
  Eigen::MatrixXd scores = Eigen::Map<Eigen::VectorXd>(x.data(), 1000);
  EXPECT_NEAR(AndrewsBandwidth(scores), 13.9, 3);
  std::vector<double> w = Ar1(1000, 0, 5);
  EXPECT_LT(AndrewsBandwidth(Eigen::Map<Eigen::VectorXd>(w.data(), 1000)), 3);
  std::vector<double> slow = Ar1(1000, 0.99, 6);
  EXPECT_NEAR(AndrewsBandwidth(Eigen::Map<Eigen::VectorXd>(slow.data(), 1000)), 246, 60);
}

TEST(IdentifyResidualsTest, NormalQuantilesAndTheThreshold) {
  EXPECT_NEAR(NormalUpperQuantile(0.025), 1.959964, 1e-6);
  EXPECT_NEAR(NormalUpperQuantile(0.5), 0, 1e-9);
  EXPECT_NEAR(NormalUpperQuantile(2.5e-7), 5.0263, 1e-3);
  EXPECT_EQ(StructureThreshold(1), 4);                  // Bonferroni gives 3.48: never below 4
  EXPECT_NEAR(StructureThreshold(1000), 5.0263, 1e-3);  // 0.001 / (2 tests x 2 sides x 1000)
}

// White noise over many signals trips neither test; an AR(1) at 0.5 does, on autocorrelation
// (z about 0.5 sqrt(500) = 11) and on runs.
TEST(IdentifyResidualsTest, WhiteNoiseIsNotStructureAndCorrelationIs) {
  std::vector<std::vector<double>> noise;
  for (unsigned seed = 10; seed < 210; ++seed) noise.push_back(Ar1(500, 0, seed));
  IdentifyResult white;
  std::vector<double> all;
  for (const auto& v : noise) all.insert(all.end(), v.begin(), v.end());
  DiagnoseResiduals({LogOf(noise)}, all, {std::vector<double>(200, 1.0)}, &white);
  EXPECT_EQ(white.misspecification.structured, 0);
  EXPECT_EQ(white.misspecification.signals.size(), 200u);
  EXPECT_GT(white.misspecification.threshold, 4);

  std::vector<double> wave = Ar1(500, 0.5, 7);
  IdentifyResult structured;
  DiagnoseResiduals({LogOf({wave})}, wave, {{1.0}}, &structured);
  const ResidualStructure& s = structured.misspecification.signals[0];
  EXPECT_TRUE(s.structured);
  EXPECT_GT(s.autocorrelation_z, 8);
  EXPECT_LT(s.runs_z, -4);
}

// A fitted model that replays the log worse than the nominal one, on the same weights, is
// misspecified even when its residuals look like noise; by no more than chance allows, it is
// not.
TEST(IdentifyResidualsTest, AFitWorseThanNominalIsMisspecified) {
  std::vector<double> y(200, 0.0), noise = Ar1(200, 0, 8);
  RobotLog log = LogOf({y});
  IdentifyResult r;
  r.before.resize(1);
  r.after.resize(1);
  r.before[0].simulated.values = {noise};
  r.after[0].simulated.values = {noise};
  for (double& v : r.after[0].simulated.values[0]) v *= 1.5;
  DiagnoseResiduals({log}, noise, {{1.0}}, &r);
  JudgeMisspecification({log}, {{1.0}}, 3, &r);
  EXPECT_TRUE(r.misspecification.worse_than_nominal);
  EXPECT_TRUE(r.misspecification.detected);
  EXPECT_NE(r.misspecification.reason.find("worse than the nominal one"), std::string::npos);
  r.after[0].simulated.values = {noise};
  r.after[0].simulated.values[0][0] += 2;  // 2 x extra cost about 4 x noise[0]: chance
  JudgeMisspecification({log}, {{1.0}}, 3, &r);
  EXPECT_FALSE(r.misspecification.detected) << r.misspecification.reason;
}

// On residuals that are white noise the sandwich agrees with the classical covariance
// (sigma^2 (J'J)^-1); on an AR(1) at 0.5 it is about (1 + 0.5) / (1 - 0.5) = 3 times larger
// for a constant regressor, where the classical one sees none of it.
TEST(IdentifyResidualsTest, TheSandwichOfAMeanUnderCorrelatedResiduals) {
  const long n = 4000;
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Ones(n, 1);
  for (double rho : {0.0, 0.5}) {
    SCOPED_TRACE(rho);
    std::vector<double> e = Ar1(n, rho, 9);
    double variance = 0;
    for (double v : e) variance += v * v / n;
    Eigen::MatrixXd cov;
    int bandwidth = 0;
    std::string why;
    ASSERT_TRUE(NeweyWestCovariance({LogOf({e})}, jacobian, e, 1, &cov, &bandwidth, &why)) << why;
    double classical = variance / n;
    double expected = rho == 0 ? 1 : 3;
    EXPECT_NEAR(cov(0, 0) / classical, expected, 0.35 * expected) << "bandwidth " << bandwidth;
    EXPECT_GE(bandwidth, NeweyWestBandwidth(n));
  }
  // residuals that stay correlated over most of the series: withheld, with the reason
  std::vector<double> slow = Ar1(n, 0.999, 10);
  Eigen::MatrixXd cov;
  int bandwidth = 0;
  std::string why;
  EXPECT_FALSE(NeweyWestCovariance({LogOf({slow})}, jacobian, slow, 1, &cov, &bandwidth, &why));
  EXPECT_NE(why.find("stay correlated too long: a series of 4000 samples would need about"),
            std::string::npos)
      << why;
}

}  // namespace
}  // namespace plumb
