// The scenario language at API level: control shapes, assertion parsing into enums, and the
// assertion engine's verdicts (reading scenario files is tested in audit_test.cc, where the
// audit runs them).

#include "plumb/scenario.h"

#include <gtest/gtest.h>

#include "fixture.h"
#include "plumb/error.h"
#include "scenario/assertion_tally.h"

namespace plumb {
using internal::AssertionTally;

namespace {

using ScenarioTest = testing::MujocoTest;

TEST_F(ScenarioTest, ControlShapesFollowTheirDefinition) {
  ControlSchedule c;
  c.type = ControlShape::kStep;
  c.before = 1;
  c.value = 2;
  c.at = 0.5;
  EXPECT_EQ(c.At(0.4), 1);
  EXPECT_EQ(c.At(0.5), 2);
  c.type = ControlShape::kRamp;
  c.start = 1;
  c.end = 3;
  c.to = 5;
  EXPECT_EQ(c.At(0), 1);
  EXPECT_EQ(c.At(2), 3);
  EXPECT_EQ(c.At(4), 5);
  c.type = ControlShape::kSine;
  c.value = 1;
  c.amplitude = 2;
  c.frequency = 0.25;
  c.phase = 0;
  EXPECT_NEAR(c.At(1), 3, 1e-12);
  EXPECT_STREQ(ControlShapeName(ControlShape::kRamp), "ramp");
}

TEST_F(ScenarioTest, AssertionsParseIntoEnums) {
  Model model = Model::Load(testing::kPendulum);
  Assertion a = ParseAssertion(model, "final(qpos[hinge]) <= 0.3 during [1, 2]");
  EXPECT_EQ(a.reduce, Reduction::kFinal);
  EXPECT_EQ(a.op, Comparison::kLessEqual);
  EXPECT_EQ(a.bound, 0.3);
  EXPECT_EQ(a.from, 1);
  EXPECT_EQ(a.to, 2);
  Assertion b = ParseAssertion(model, "qvel[hinge] > -3");
  EXPECT_EQ(b.reduce, Reduction::kEach);
  EXPECT_EQ(b.op, Comparison::kGreater);
  EXPECT_TRUE(Holds(Comparison::kGreater, -2, -3));
  EXPECT_FALSE(Holds(Comparison::kLess, 1, 1));
  EXPECT_THROW(ParseAssertion(model, "qpos[hinge] = 1"), ValueError);
  EXPECT_THROW(ParseAssertion(model, "min(qpos[hinge]) < 1 during [2, 1]"), ValueError);
}

TEST_F(ScenarioTest, TheTallyJudgesEachReductionOverItsWindow) {
  Model model = Model::Load(testing::kPendulum);
  Data data(model);
  std::vector<Assertion> assertions = {
      ParseAssertion(model, "qpos[hinge] < 0.5"),                      // fails at t = 0.2
      ParseAssertion(model, "max(qpos[hinge]) <= 0.6 during [0, 1]"),  // the max is 0.6
      ParseAssertion(model, "min(qpos[hinge]) > 0 during [0.5, 1]"),   // no sample: fails
      ParseAssertion(model, "final(qpos[hinge]) > 0.35"),              // the last is 0.4
  };
  AssertionTally tally(assertions);
  for (auto [t, q] : {std::pair{0.0, 0.1}, {0.2, 0.6}, {0.4, 0.4}}) {
    data->qpos[0] = q;
    tally.Sample(model, data, t);
  }
  AssertionTally::Verdict each = tally.Judge(0);
  EXPECT_FALSE(each.ok);
  EXPECT_NE(each.measured.find("= 0.6 at t = 0.2 s"), std::string::npos) << each.measured;
  EXPECT_TRUE(tally.Judge(1).ok) << tally.Judge(1).measured;
  EXPECT_EQ(tally.Judge(1).measured, "max(qpos[hinge]) = 0.6");
  EXPECT_FALSE(tally.Judge(2).ok);
  EXPECT_EQ(tally.Judge(2).measured, "no sample in the window");
  EXPECT_TRUE(tally.Judge(3).ok);
}

TEST_F(ScenarioTest, EachReductionParsesByItsWholeName) {
  Model model = Model::Load(testing::kPendulum);
  EXPECT_EQ(ParseAssertion(model, "maxabs(qpos[hinge]) < 1").reduce, Reduction::kMaxAbs);
  EXPECT_EQ(ParseAssertion(model, "max(qpos[hinge]) < 1").reduce, Reduction::kMax);
  EXPECT_EQ(ParseAssertion(model, "min (qpos[hinge]) < 1").reduce, Reduction::kMin);
  Assertion mean = ParseAssertion(model, "mean(qvel[hinge]) > 0.3 during [7, 11]");
  EXPECT_EQ(mean.reduce, Reduction::kMean);
  EXPECT_EQ(mean.from, 7);
  EXPECT_EQ(mean.to, 11);
  ASSERT_EQ(mean.paths.size(), 1u);
  EXPECT_EQ(mean.paths[0].text, "qvel[hinge]");
  EXPECT_STREQ(ReductionName(Reduction::kMean), "mean");
  EXPECT_THROW(ParseAssertion(model, "mean() < 1"), ValueError);
}

TEST_F(ScenarioTest, TheMeanAveragesTheSamplesInItsWindow) {
  Model model = Model::Load(testing::kPendulum);
  Data data(model);
  std::vector<Assertion> assertions = {
      ParseAssertion(model, "mean(qpos[hinge]) < 0.35 during [0.1, 0.5]"),  // (0.6 + 0.2) / 2
      ParseAssertion(model, "mean(qpos[hinge]) < 0.35"),                    // 0.9 / 4 = 0.225
      ParseAssertion(model, "mean(qpos[hinge]) > 0.45 during [0.1, 0.5]"),
  };
  AssertionTally tally(assertions);
  for (auto [t, q] : {std::pair{0.0, 0.1}, {0.2, 0.6}, {0.4, 0.2}, {0.6, 0.0}}) {
    data->qpos[0] = q;
    tally.Sample(model, data, t);
  }
  AssertionTally::Verdict windowed = tally.Judge(0);
  EXPECT_FALSE(windowed.ok);
  EXPECT_EQ(windowed.measured, "mean(qpos[hinge]) = 0.4");
  EXPECT_NEAR(windowed.value, 0.4, 1e-12);
  EXPECT_TRUE(tally.Judge(1).ok) << tally.Judge(1).measured;
  EXPECT_NEAR(tally.Judge(1).value, 0.225, 1e-12);
  EXPECT_FALSE(tally.Judge(2).ok);
}

TEST_F(ScenarioTest, TheTallyTakesValuesOfSignalsWithoutPaths) {
  Model model = Model::Load(testing::kPendulum);
  Assertion a = ParseAssertion(model, "max(qpos[hinge]) < 1 during [0, 1]");
  a.paths.clear();
  std::vector<Assertion> assertions = {a};
  AssertionTally tally(assertions, {{"left", "right"}});
  tally.SampleValue(0, 0, 0.5, 0.1);
  tally.SampleValue(0, 0, 5, 2);  // outside the window: not counted
  EXPECT_FALSE(tally.Judge(0).ok);
  EXPECT_EQ(tally.Judge(0).measured, "no sample of right in the window");
  tally.SampleValue(0, 1, 0.9, 0.2);
  AssertionTally::Verdict v = tally.Judge(0);
  EXPECT_TRUE(v.ok);
  EXPECT_EQ(v.measured, "max(right) = 0.9 (closest of 2 signals)");
  EXPECT_EQ(v.value, 0.9);
}

}  // namespace
}  // namespace plumb
