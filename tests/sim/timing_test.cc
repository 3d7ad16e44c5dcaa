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

// issue 46: one rule turns a time into steps, for every command and argument
TEST_F(TimingTest, RequireStepsToReachRefusesWhatCannotBeCounted) {
  EXPECT_EQ(RequireStepsToReach(0.1, 0.002, "until"), 50);
  EXPECT_EQ(RequireStepsToReach(0.1001, 0.002, "until"), 51);  // up to the next step
  EXPECT_EQ(RequireStepsToReach(0, 0.002, "at"), 0);
  for (double bad : {-1.0, double(NAN), double(INFINITY), 1e17, 1e30}) {
    try {
      RequireStepsToReach(bad, 0.002, "at");
      FAIL() << bad << " s was accepted";
    } catch (const ArgumentError& e) {
      EXPECT_EQ(e.argument(), "at") << e.what();  // the caller's name, never another's
      EXPECT_EQ(std::string(e.what()).find("-1.84467e+16"), std::string::npos) << e.what();
    }
  }
  try {
    RequireStepsToReach(1e17, 0.002, "until", "1e17", "the finest level");
    FAIL();
  } catch (const ArgumentError& e) {
    EXPECT_EQ(e.value(), "1e17");
    EXPECT_NE(e.problem().find("5e+19 steps of 0.002 s (the finest level; plumb counts steps "
                               "exactly up to 2^53"),
              std::string::npos)
        << e.problem();
  }
  EXPECT_THROW(RequireStepsToReach(1, 0, "until"), ValueError);
}

// a time beyond 2^53 steps has no nearest whole time: "Use 1e+30" repeated the input
TEST_F(TimingTest, RequireWholeStepsSuggestsNoTimeItCannotRun) {
  for (double bad : {1e30, double(INFINITY), double(NAN)}) {
    try {
      RequireWholeSteps(bad, 0.002, "until", "x");
      FAIL() << bad;
    } catch (const ArgumentError& e) {
      EXPECT_EQ(e.problem().find("Use "), std::string::npos) << e.problem();
    }
  }
}

TEST_F(TimingTest, RequireMemoryForRefusesWhatNoMachineHolds) {
  EXPECT_NO_THROW(RequireMemoryFor(1e6, "the rows", "count", "10"));
  try {
    RequireMemoryFor(1e30, "the rows of 1e+29 cases", "count", "100000000000000000000000000000");
    FAIL();
  } catch (const ArgumentError& e) {
    EXPECT_EQ(e.argument(), "count");
    EXPECT_NE(e.problem().find("the rows of 1e+29 cases take 1e+30 bytes, more than this "
                               "machine's memory"),
              std::string::npos)
        << e.problem();
  }
  EXPECT_THROW(RequireMemoryFor(INFINITY, "x", "count", "1"), ArgumentError);
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
