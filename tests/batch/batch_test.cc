// What every front end of rollout and sweep shares: the config line naming a batch, its JSON
// rows, a sweep case as a store row and the summary.

#include "plumb/batch.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "fixture.h"
#include "plumb/error.h"

namespace plumb {
namespace {

RolloutSpec Spec(const Model& model, std::uint64_t seed) {
  RolloutSpec spec;
  spec.count = 4;
  spec.seed = seed;
  spec.randomize = {ParseRandomization(model, "dof_damping[hinge]=*U(0.5,1.5)")};
  spec.metrics = {ParseMetric(model, "qpos[hinge]@1")};
  return spec;
}

TEST(BatchTest, TheConfigLineNamesEverythingThatDecidesTheRowsAndNothingElse) {
  Model model = Model::Load(testing::kPendulum);
  std::string start = StartConfig(model, {"", "", "", {"qpos[hinge]=0.7"}});
  EXPECT_EQ(start, " set=qpos[hinge]=0.7");
  // a whole qpos enters as its values: the same numbers written two ways are one config
  EXPECT_EQ(StartConfig(model, {"", "", "0.5", {}}), StartConfig(model, {"", "", "5e-1", {}}));
  EXPECT_EQ(StartConfig(model, {"", "", "0.5", {}}), " pose=qpos=0.5");
  RolloutSpec spec = Spec(model, 1);
  std::string config = RolloutConfig(spec, "abc", start);
  EXPECT_EQ(config.rfind("rollout model=abc count=4 until=2 seed=1 ctrl_noise=0 plumb=", 0), 0u)
      << config;
  EXPECT_NE(config.find(" set=qpos[hinge]=0.7 randomize=dof_damping[hinge]=*U(0.5,1.5) "
                        "metric=qpos[hinge]@1"),
            std::string::npos)
      << config;
  // threads and the shard decide no row: the same line
  RolloutSpec other = spec;
  other.threads = 2;
  other.shard_index = 1;
  other.shard_count = 2;
  EXPECT_EQ(RolloutConfig(other, "abc", start), config);
  EXPECT_NE(RolloutConfig(Spec(model, 2), "abc", start), config);

  SweepSpec sweep;
  sweep.axes = {ParseSweepAxis(model, "dof_damping[hinge]=0:1:3")};
  sweep.metrics = spec.metrics;
  RunInfo info = SweepRunInfo(model, sweep, {"p.xml", {"plumb", "sweep"}, start}, "");
  EXPECT_EQ(info.kind, "sweep");
  EXPECT_EQ(info.count, 3);
  EXPECT_EQ(info.parameters, std::vector<std::string>{"dof_damping[hinge]"});
  EXPECT_TRUE(info.model_hash.empty());  // no store: not hashed
  EXPECT_NE(info.config.find(" vary=dof_damping[hinge]=0:1:3 metric=qpos[hinge]@1"),
            std::string::npos);
}

TEST(BatchTest, AShardIsIOfN) {
  RolloutSpec spec;
  ParseShard("1/4", &spec);
  EXPECT_EQ(spec.shard_index, 1);
  EXPECT_EQ(spec.shard_count, 4);
  for (const char* bad : {"4/4", "1", "a/2", "1/0", "-1/2"}) {
    try {
      ParseShard(bad, &spec);
      ADD_FAILURE() << bad;
    } catch (const ArgumentError& e) {
      EXPECT_EQ(e.argument(), "shard");
      EXPECT_EQ(e.value(), Quoted(bad));
    }
  }
}

TEST(BatchTest, JsonRowsSayNullForWhatWasNotMeasured) {
  RolloutJson json({"p"}, {"m1", "m2"});
  RolloutResult r;
  r.index = 3;
  r.params = {0.5};
  r.metrics = {1.25, NAN};
  r.diverged = true;
  r.diverged_time = 0.1;
  r.problem = "diverged at t = 0.1 s";
  // one call at a time: the operands of + are evaluated in no fixed order
  std::string text = json.Begin();
  text += json.Row(r);
  text += json.Row(r);
  text += json.End();
  std::string row =
      R"({"rollout":3,"params":{"p":0.5},"metrics":{"m1":1.25,"m2":null},"diverged":true,)"
      R"("diverged_time":0.1,"problem":"diverged at t = 0.1 s"})";
  EXPECT_EQ(text, "[\n  " + row + ",\n  " + row + "\n]\n");

  SweepJson sweep("p.xml", {"a"}, {"m"});
  Measurement missing;
  missing.ok = false;
  missing.problem = "fewer than two crossings";
  std::string document = sweep.Begin();
  document += sweep.Row(0, {2.0}, {missing});
  document += sweep.End();
  EXPECT_EQ(document,
            "{\n  \"model\": \"p.xml\",\n  \"vary\": [\"a\"],\n  \"metrics\": [\"m\"],\n  "
            "\"cases\": [\n    "
            R"({"case":0,"values":{"a":2.0},"metrics":{"m":null},)"
            R"("problems":{"m":"fewer than two crossings"}})"
            "\n  ]\n}\n");
  SweepJson empty("p.xml", {"a"}, {"m"});
  EXPECT_EQ(empty.End(), "]\n}\n");
}

TEST(BatchTest, ASweepCaseIsAStoreRowWithItsReasonsJoined) {
  Model model = Model::Load(testing::kPendulum);
  SweepSpec spec;
  spec.axes = {ParseSweepAxis(model, "dof_damping[hinge]=0,0.5")};
  SweepCase c;
  c.index = 1;
  c.choice = {1};
  c.metrics.resize(3);
  c.metrics[0].value = 2;
  c.metrics[1].ok = false;
  c.metrics[1].diverged = true;
  c.metrics[1].problem = "diverged";
  c.metrics[2].ok = false;
  c.metrics[2].problem = "no crossings";
  RolloutResult r = SweepCaseResult(spec, c);
  EXPECT_EQ(r.index, 1);
  EXPECT_EQ(r.params, std::vector<double>{0.5});
  ASSERT_EQ(r.metrics.size(), 3u);
  EXPECT_EQ(r.metrics[0], 2);
  EXPECT_TRUE(std::isnan(r.metrics[1]) && std::isnan(r.metrics[2]));
  EXPECT_TRUE(r.diverged);
  EXPECT_EQ(r.problem, "diverged; no crossings");
}

TEST(BatchTest, TheSummaryCountsResumedRowsAndEachMetric) {
  BatchSummary summary(2);
  for (int i = 0; i < 4; ++i) {
    RolloutResult r;
    r.metrics = {static_cast<double>(i), NAN};
    r.diverged = i == 3;
    summary.Add(r);
  }
  summary.resumed = 1;
  summary.run_now = 3;
  std::string text = summary.Text({"x", "y"}, "rollouts", 0);
  EXPECT_NE(text.find("4 rollouts (1 stored before it resumed, 3 run now), 1 diverged (25.0%)"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("x: n 4 mean 1.5 "), std::string::npos) << text;
  EXPECT_NE(text.find("y: n 0, no value measured (4 missing)"), std::string::npos) << text;
}

}  // namespace
}  // namespace plumb
