#include "plumb/random.h"

#include <gtest/gtest.h>

#include <cmath>

namespace plumb {
namespace {

TEST(PhiloxTest, MatchesRandom123KnownAnswers) {
  // Random123's kat_vectors for philox4x32_10
  EXPECT_EQ(Philox4x32({0, 0, 0, 0}, 0),
            (std::array<std::uint32_t, 4>{0x6627e8d5, 0xe169c58d, 0xbc57ac4c, 0x9b00dbd8}));
  EXPECT_EQ(Philox4x32({0xffffffff, 0xffffffff, 0xffffffff, 0xffffffff}, 0xffffffffffffffffULL),
            (std::array<std::uint32_t, 4>{0x408f276d, 0x41c83b0e, 0xa20bc7c6, 0x6d5451fd}));
}

TEST(RandomTest, UniformAndNormalHaveTheRightMoments) {
  const int n = 200000;
  double sum = 0, sum2 = 0, zsum = 0, zsum2 = 0;
  for (int i = 0; i < n; ++i) {
    double u = Uniform01(42, i, 3, 0);
    ASSERT_GT(u, 0);
    ASSERT_LT(u, 1);
    sum += u;
    sum2 += u * u;
    double z = StandardNormal(42, i, 3, 1);
    zsum += z;
    zsum2 += z * z;
  }
  // standard errors: 1/sqrt(12 n) for the uniform mean, 1/sqrt(n) for the normal mean;
  // bounds at 5 standard errors fail by chance with probability < 1e-6
  EXPECT_NEAR(sum / n, 0.5, 5 / std::sqrt(12.0 * n));
  EXPECT_NEAR(sum2 / n - std::pow(sum / n, 2), 1.0 / 12, 5 * std::sqrt(1.0 / 180 / n));
  EXPECT_NEAR(zsum / n, 0, 5 / std::sqrt(n));
  EXPECT_NEAR(zsum2 / n, 1, 5 * std::sqrt(2.0 / n));
}

TEST(RandomTest, DrawsDependOnlyOnTheirKey) {
  EXPECT_EQ(Uniform01(1, 2, 3, 4), Uniform01(1, 2, 3, 4));
  EXPECT_NE(Uniform01(1, 2, 3, 4), Uniform01(1, 2, 3, 5));
  EXPECT_NE(Uniform01(1, 2, 3, 4), Uniform01(1, 3, 3, 4));
  EXPECT_NE(Uniform01(1, 2, 3, 4), Uniform01(2, 2, 3, 4));
}

}  // namespace
}  // namespace plumb
