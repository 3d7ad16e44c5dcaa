// Metrics at API level: every kind measured on the chapter's pendulum, and the one probe
// giving the same numbers through plumb::Measure (converge, sweep) and through a rollout.

#include "plumb/metric.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "fixture.h"
#include "plumb/rollout.h"

namespace plumb {
namespace {

using MetricTest = testing::MujocoTest;

std::vector<Assignment> Start(const Model& model) {
  return {ParseAssignment(model, "qpos[hinge]=0.7")};
}

TEST_F(MetricTest, ValueAtReproducesTheChaptersNumbers) {
  Model model = Model::Load(testing::kPendulum);
  for (int k = 0; k < 5; ++k) {
    double t = 0.1 * (k + 1);
    Measurement q = Measure(model, Start(model),
                            ParseMetric(model, "qpos[hinge]@" + std::to_string(t)), 0.002, t);
    ASSERT_TRUE(q.ok) << q.problem;
    EXPECT_NEAR(q.value, testing::kChapterQ[k], 5e-6) << t;
    Measurement dq = Measure(model, Start(model),
                             ParseMetric(model, "qvel[hinge]@" + std::to_string(t)), 0.002, t);
    EXPECT_NEAR(dq.value, testing::kChapterDq[k], 5e-6) << t;
  }
}

TEST_F(MetricTest, EveryKindMeasuresWhatItSays) {
  Model model = Model::Load(testing::kPendulum);
  std::vector<Assignment> sets = Start(model);
  Measurement maxabs = Measure(model, sets, ParseMetric(model, "maxabs(qpos[hinge])"), 0.002, 2);
  EXPECT_NEAR(maxabs.value, 0.7, 1e-12);  // damped: the start is the widest swing
  Measurement state = Measure(model, sets, ParseMetric(model, "state@0.5"), 0.002, 2);
  ASSERT_EQ(state.state.size(), 2u);  // qpos, qvel (no act)
  EXPECT_NEAR(state.state[0], testing::kChapterQ[4], 5e-6);
  EXPECT_NEAR(state.value, std::hypot(state.state[0], state.state[1]), 1e-12);
  Measurement period = Measure(model, sets, ParseMetric(model, "period(qpos[hinge])"), 0.002, 20);
  ASSERT_TRUE(period.ok) << period.problem;
  // the capsule's inertia about the hinge makes it swing in about 1.69 s at 0.7 rad
  EXPECT_GT(period.value, 1.6);
  EXPECT_LT(period.value, 1.8);
  EXPECT_EQ(period.scale, period.value);
  Measurement drift = Measure(model, sets, ParseMetric(model, "energy_drift"), 0.002, 2);
  EXPECT_LT(drift.value, 0);  // damping removes energy
  // a period that cannot be measured says why and is not a divergence
  Measurement still = Measure(model, {}, ParseMetric(model, "period(qpos[hinge])"), 0.002, 1);
  EXPECT_FALSE(still.ok);
  EXPECT_FALSE(still.diverged);
  EXPECT_NE(still.problem.find("fewer than twice"), std::string::npos) << still.problem;
}

// The same probe measures a rollout: a rollout with nothing randomized gives exactly what
// plumb::Measure gives, for every kind.
TEST_F(MetricTest, RolloutsAndMeasureShareOneProbe) {
  Model model = Model::Load(testing::kPendulum);
  RolloutSpec spec;
  spec.count = 1;
  spec.until = 4;
  spec.sets = Start(model);
  std::vector<std::string> texts = {"qpos[hinge]@1", "maxabs(qvel[hinge])", "period(qpos[hinge])",
                                    "energy_drift", "state@2"};
  for (const std::string& t : texts) spec.metrics.push_back(ParseMetric(model, t));
  std::vector<RolloutResult> results;
  Rollout(model, spec, [&](const RolloutResult& r) { results.push_back(r); });
  ASSERT_EQ(results.size(), 1u);
  for (std::size_t k = 0; k < texts.size(); ++k) {
    Measurement m = Measure(model, spec.sets, spec.metrics[k], 0.002, 4);
    ASSERT_TRUE(m.ok) << texts[k] << ": " << m.problem;
    EXPECT_EQ(results[0].metrics[k], m.value) << texts[k];
  }
}

}  // namespace
}  // namespace plumb
