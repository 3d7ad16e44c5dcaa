#include "plumb/timing.h"

#include <gtest/gtest.h>

#include "fixture.h"
#include "plumb/error.h"

namespace plumb {
namespace {

using testing::kPendulum;
using TimingTest = testing::MujocoTest;

TEST_F(TimingTest, TheExampleInTheHeader) {
  Model model = Model::Load(kPendulum);
  double dt = RunTimestep(model, {ParseAssignment(model, "opt.timestep=0.001")});
  EXPECT_EQ(dt, 0.001);
  EXPECT_EQ(RequireWholeSteps(0.1, dt, "every", "0.1"), 100);
  EXPECT_DOUBLE_EQ(DefaultEvery(dt), 0.1);
}

TEST_F(TimingTest, RunTimestepIsTheLastOneSet) {
  Model model = Model::Load(kPendulum);
  EXPECT_EQ(RunTimestep(model, {}), 0.002);
  EXPECT_EQ(RunTimestep(model, {ParseAssignment(model, "opt.timestep=0.001"),
                                ParseAssignment(model, "opt.timestep=0.004")}),
            0.004);
}

TEST_F(TimingTest, WholeStepsToleratesRoundingOnly) {
  EXPECT_EQ(WholeSteps(0.1, 0.002), 50);
  EXPECT_EQ(WholeSteps(0.3, 0.1), 3);  // 0.3 / 0.1 = 2.9999999999999996
  EXPECT_EQ(WholeSteps(0, 0.01), 0);
  EXPECT_FALSE(WholeSteps(0.1, 0.03));
  EXPECT_FALSE(WholeSteps(0.1, 0));
  EXPECT_FALSE(WholeSteps(NAN, 0.01));
}

TEST_F(TimingTest, RequireWholeStepsNamesTheNearestTimes) {
  try {
    RequireWholeSteps(0.1, 0.03, "every", "0.1", "the model's timestep");
    FAIL() << "0.1 s is not a whole number of 0.03 s steps";
  } catch (const ValueError& e) {
    std::string what = e.what();
    EXPECT_NE(what.find("every 0.1: 0.1 s is not a whole number of timesteps of 0.03 s"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("0.09 or 0.12"), std::string::npos) << what;
  }
  EXPECT_THROW(RequireWholeSteps(0, 0.01, "every", "0"), ArgumentError);  // fewer than one step
  EXPECT_EQ(RequireWholeSteps(0, 0.01, "metric", "'x@0'", "", 0), 0);
}

TEST_F(TimingTest, DefaultEveryIsTheNearestWholeNumberOfStepsToATenth) {
  EXPECT_DOUBLE_EQ(DefaultEvery(0.002), 0.1);
  EXPECT_DOUBLE_EQ(DefaultEvery(0.03), 0.09);  // dm_control's lqr.xml
  EXPECT_DOUBLE_EQ(DefaultEvery(0.07), 0.07);
  EXPECT_DOUBLE_EQ(DefaultEvery(0.5), 0.5);  // at least one step
  EXPECT_TRUE(WholeSteps(DefaultEvery(0.0025), 0.0025));
}

}  // namespace
}  // namespace plumb
