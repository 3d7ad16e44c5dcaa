// The version helpers of core/mujoco_compat.h, where every MuJoCo version comparison lives:
// numbers of both encodings (three digits up to 3.4.0, major*10^6 + minor*10^3 + patch from
// 3.5.0) compare as releases, so a 3.0-3.4 build knows it is past a change made in 3.0.0.

#include "core/mujoco_compat.h"

#include <gtest/gtest.h>

#include <mujoco/mujoco.h>

#include "plumb/model.h"

namespace plumb {
namespace {

TEST(MujocoCompatTest, VersionNumbersOfBothEncodingsCompareAsReleases) {
  EXPECT_EQ(compat::VersionNumber(222), 2002002);
  EXPECT_EQ(compat::VersionNumber(310), 3001000);
  EXPECT_EQ(compat::VersionNumber(340), 3004000);
  EXPECT_EQ(compat::VersionNumber(3011000), 3011000);
  EXPECT_EQ(compat::VersionNumber(4000001), 4000001);
  // 3.4.0 came after 3.3.6 and 3.0.0, as 3.1.0 did after 3.0.0, though 340 < 3003006
  EXPECT_GT(compat::VersionNumber(340), 3003006);
  EXPECT_GE(compat::VersionNumber(310), 3000000);
  EXPECT_LT(compat::VersionNumber(222), 3000000);
}

TEST(MujocoCompatTest, CompiledAtLeastAgreesWithTheNamedReleases) {
  EXPECT_EQ(compat::CompiledAtLeast(3000000), compat::kMujoco3);
  EXPECT_EQ(compat::CompiledAtLeast(3005000), compat::kMujoco35);
  EXPECT_EQ(compat::CompiledAtLeast(3006000), compat::kMujoco36);
  EXPECT_TRUE(compat::CompiledAtLeast(compat::VersionNumber(mjVERSION_HEADER)));
  EXPECT_FALSE(compat::CompiledAtLeast(compat::VersionNumber(mjVERSION_HEADER) + 1));
}

TEST(MujocoCompatTest, VersionTextReadsBothEncodings) {
  EXPECT_EQ(compat::VersionText(222), "2.2.2");
  EXPECT_EQ(compat::VersionText(340), "3.4.0");
  EXPECT_EQ(compat::VersionText(3011000), "3.11.0");
  EXPECT_EQ(compat::VersionText(4000001), "4.0.1");
  EXPECT_EQ(compat::CompiledVersionText(), CompiledMujocoVersion());
}

TEST(MujocoCompatTest, TheLoadedLibraryIsTheCompiledOne) {
  EXPECT_TRUE(compat::LoadedMujocoIsCompiledOne());  // the tests run with the library built with
  EXPECT_EQ(compat::CompiledVersionText(), MujocoVersion());
}

}  // namespace
}  // namespace plumb
