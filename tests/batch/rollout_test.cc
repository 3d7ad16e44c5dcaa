#include "plumb/rollout.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>

#include "fixture.h"
#include "plumb/error.h"
#include "plumb/stored_run.h"

namespace plumb {
namespace {

std::vector<RolloutResult> Collect(const Model& model, const RolloutSpec& spec) {
  std::vector<RolloutResult> out;
  Rollout(model, spec, [&](const RolloutResult& r) { out.push_back(r); });
  return out;
}

bool BitEqual(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

TEST(DistributionTest, ParsesAllForms) {
  Distribution u = ParseDistribution("U(0.5,1.2)");
  EXPECT_EQ(u.kind, Distribution::Kind::kUniform);
  EXPECT_DOUBLE_EQ(u.Apply(7, 0.5, 0), 0.85);
  Distribution scale = ParseDistribution("*U(0.9,1.1)");
  EXPECT_EQ(scale.mode, Distribution::Mode::kScale);
  EXPECT_DOUBLE_EQ(scale.Apply(2, 0.5, 0), 2.0);
  Distribution offset = ParseDistribution("+N(0,0.01)");
  EXPECT_EQ(offset.mode, Distribution::Mode::kOffset);
  EXPECT_DOUBLE_EQ(offset.Apply(1, 0.3, 2), 1.02);
  EXPECT_DOUBLE_EQ(ParseDistribution("LogU(1,100)").Apply(0, 0.5, 0), 10);
  for (const char* bad : {"U(1)", "Q(0,1)", "LogU(0,1)", "N(0,-1)", "U(2,1)", "U(a,b)", "U0,1"}) {
    EXPECT_THROW(ParseDistribution(bad), ValueError) << bad;
  }
}

class RolloutTest : public testing::MujocoTest {
 protected:
  Model humanoid_ = Model::Load(testing::kHumanoid);
};

TEST_F(RolloutTest, SampleMomentsMatchEachDistribution) {
  Model pendulum = Model::Load(testing::kPendulum);
  RolloutSpec spec;
  spec.count = 4000;
  spec.until = 0.002;
  spec.seed = 11;
  spec.randomize = {ParseRandomization(pendulum, "dof_damping[hinge]=U(1,3)"),
                    ParseRandomization(pendulum, "body_mass[link]=N(2,0.5)"),
                    ParseRandomization(pendulum, "opt.timestep=LogU(0.001,0.004)")};
  // the timestep varies, so no metric with a fixed time here
  std::vector<double> s(3), s2(3);
  std::vector<RolloutResult> results = Collect(pendulum, spec);
  ASSERT_EQ(results.size(), 4000u);
  for (const RolloutResult& r : results) {
    for (int k = 0; k < 3; ++k) {
      s[k] += r.params[k];
      s2[k] += r.params[k] * r.params[k];
    }
  }
  double n = 4000;
  auto mean = [&](int k) { return s[k] / n; };
  auto var = [&](int k) { return s2[k] / n - mean(k) * mean(k); };
  // bounds at 5 standard errors
  EXPECT_NEAR(mean(0), 2, 5 * std::sqrt(4.0 / 12 / n));
  EXPECT_NEAR(var(0), 4.0 / 12, 5 * std::sqrt(16.0 / 180 / n));
  EXPECT_NEAR(mean(1), 2, 5 * 0.5 / std::sqrt(n));
  EXPECT_NEAR(var(1), 0.25, 5 * 0.25 * std::sqrt(2.0 / n));
  // log-uniform: the log is uniform on [log 0.001, log 0.004]
  double lsum = 0, lsum2 = 0;
  for (const RolloutResult& r : results) {
    lsum += std::log(r.params[2]);
    lsum2 += std::log(r.params[2]) * std::log(r.params[2]);
  }
  double width = std::log(4.0);  // log 0.004 - log 0.001
  double lmean = lsum / n, lvar = lsum2 / n - lmean * lmean;
  EXPECT_NEAR(lmean, 0.5 * (std::log(0.001) + std::log(0.004)), 5 * width / std::sqrt(12 * n));
  // a uniform of width w has variance w^2/12 and fourth central moment w^4/80
  EXPECT_NEAR(lvar, width * width / 12,
              5 * std::sqrt((std::pow(width, 4) / 80 - std::pow(width * width / 12, 2)) / n));
  // and the values themselves: E[x] = (b - a) / ln(b/a), E[x^2] = (b^2 - a^2) / (2 ln(b/a))
  double xmean = mean(2), xvar = var(2);
  double ex = (0.004 - 0.001) / width, ex2 = (0.004 * 0.004 - 0.001 * 0.001) / (2 * width);
  EXPECT_NEAR(xmean, ex, 5 * std::sqrt((ex2 - ex * ex) / n));
  EXPECT_NEAR(xvar, ex2 - ex * ex, 0.1 * (ex2 - ex * ex));
}

TEST_F(RolloutTest, OneTwoThreadsAndShardsAreBitIdentical) {
  RolloutSpec spec;
  spec.count = 12;
  spec.until = 0.3;
  spec.seed = 5;
  spec.ctrl_noise = 0.01;
  spec.randomize = {ParseRandomization(humanoid_, "body_mass[*]=*U(0.9,1.1)"),
                    ParseRandomization(humanoid_, "geom_friction[floor][0]=U(0.5,1.2)")};
  spec.metrics = {ParseMetric(humanoid_, "xpos[torso][2]@0.3"),
                  ParseMetric(humanoid_, "state@0.3")};
  std::vector<RolloutResult> one = Collect(humanoid_, spec);
  spec.threads = 2;
  std::vector<RolloutResult> two = Collect(humanoid_, spec);
  std::vector<RolloutResult> shards;
  spec.shard_count = 3;
  for (long s = 0; s < 3; ++s) {
    spec.shard_index = s;
    for (RolloutResult& r : Collect(humanoid_, spec)) shards.push_back(r);
  }
  std::sort(shards.begin(), shards.end(),
            [](const RolloutResult& a, const RolloutResult& b) { return a.index < b.index; });
  ASSERT_EQ(one.size(), 12u);
  ASSERT_EQ(two.size(), 12u);
  ASSERT_EQ(shards.size(), 12u);
  for (std::size_t i = 0; i < one.size(); ++i) {
    EXPECT_EQ(one[i].index, static_cast<long>(i));
    EXPECT_EQ(one[i].params.size(), 17u);  // 16 bodies (not the world) + the floor friction
    for (std::size_t k = 0; k < one[i].metrics.size(); ++k) {
      EXPECT_TRUE(BitEqual(one[i].metrics[k], two[i].metrics[k])) << i;
      EXPECT_TRUE(BitEqual(one[i].metrics[k], shards[i].metrics[k])) << i;
    }
    EXPECT_EQ(one[i].params, shards[i].params);
  }
}

TEST_F(RolloutTest, ResultsDoNotDependOnTheOrderRolloutsRun) {
  // the same indices forwards, backwards and in one reused pool give the same rows
  RolloutSpec spec;
  spec.until = 0.1;
  spec.seed = 21;
  spec.ctrl_noise = 0.01;
  spec.randomize = {ParseRandomization(humanoid_, "body_mass[*]=*U(0.8,1.2)")};
  spec.metrics = {ParseMetric(humanoid_, "state@0.1")};
  std::vector<long> forwards = {0, 1, 2, 3, 4, 5, 6, 7};
  std::vector<long> backwards(forwards.rbegin(), forwards.rend());
  std::map<long, RolloutResult> a, b, c;
  RolloutCases(humanoid_, spec, forwards, [&](const RolloutResult& r) { a[r.index] = r; });
  RolloutCases(humanoid_, spec, backwards, [&](const RolloutResult& r) { b[r.index] = r; });
  RolloutPool pool(humanoid_, spec);
  pool.Run({5, 6, 7}, [&](const RolloutResult& r) { c[r.index] = r; });
  pool.Run({4, 0, 3, 1, 2}, [&](const RolloutResult& r) { c[r.index] = r; });
  ASSERT_EQ(a.size(), 8u);
  for (long i = 0; i < 8; ++i) {
    EXPECT_TRUE(BitEqual(a[i].metrics[0], b[i].metrics[0])) << i;
    EXPECT_TRUE(BitEqual(a[i].metrics[0], c[i].metrics[0])) << i;
    EXPECT_EQ(a[i].params, c[i].params) << i;
  }
}

TEST_F(RolloutTest, SkippedIndicesAreNotRunAndOthersUnchanged) {
  RolloutSpec spec;
  spec.count = 6;
  spec.until = 0.1;
  spec.randomize = {ParseRandomization(humanoid_, "body_mass[torso]=*U(0.5,1.5)")};
  spec.metrics = {ParseMetric(humanoid_, "state@0.1")};
  std::vector<RolloutResult> all = Collect(humanoid_, spec);
  spec.skip = {1, 4};
  std::vector<RolloutResult> rest = Collect(humanoid_, spec);
  ASSERT_EQ(rest.size(), 4u);
  EXPECT_EQ(rest[1].index, 2);
  EXPECT_TRUE(BitEqual(rest[1].metrics[0], all[2].metrics[0]));
}

// issue 46: a count near 2^63 was listed index by index before the first rollout ran (bad_alloc,
// or minutes deaf to a stop): the shard is counted, and its indices made as they run
TEST_F(RolloutTest, AHugeCountStartsAtOnceAndStops) {
  RolloutSpec spec;
  spec.count = std::numeric_limits<long>::max();
  spec.until = 0.002;
  spec.shard_index = 1;
  spec.shard_count = 3;
  spec.skip = {1, 4, 5};
  EXPECT_EQ(ShardSize(spec), (spec.count - 2) / 3 + 1);
  EXPECT_EQ(ShardToRun(spec), ShardSize(spec) - 2);  // 5 is not of this shard
  StopSource stop;
  std::vector<long> run;
  EXPECT_THROW(Rollout(
                   humanoid_, spec,
                   [&](const RolloutResult& r) {
                     run.push_back(r.index);
                     if (run.size() == 3) stop.RequestStop();
                   },
                   stop.token()),
               Interrupted);
  ASSERT_GE(run.size(), 3u);
  EXPECT_EQ(run[0], 7);
  EXPECT_EQ(run[1], 10);
  spec.count = 5;
  spec.skip.clear();
  EXPECT_EQ(ShardSize(spec), 2);  // 1 and 4
}

TEST_F(RolloutTest, ControlNoiseIsAFractionNeverNaN) {
  EXPECT_NO_THROW(RequireCtrlNoise(0));
  EXPECT_NO_THROW(RequireCtrlNoise(1));
  for (double bad : {-1.0, 1.5, double(NAN), double(INFINITY)}) {
    EXPECT_THROW(RequireCtrlNoise(bad), ArgumentError) << bad;
    RolloutSpec spec;
    spec.ctrl_noise = bad;
    EXPECT_THROW(ValidateRolloutSpec(humanoid_, spec), ArgumentError) << bad;
  }
}

TEST_F(RolloutTest, RandomizedMassChangesTheDynamicsThroughSetConst) {
  // a heavier pendulum rod has the same period (it scales with I/(m*g*d)) but more
  // damping-independent momentum: compare with a mass that also moves the com
  Model model = Model::FromXmlString(R"(<mujoco><option gravity="0 0 -9.81"/><worldbody>
      <body name="link" pos="0 0 1"><joint name="hinge" axis="0 1 0" damping="0.5"/>
        <geom type="capsule" fromto="0 0 0 0 0 -1" size="0.05" mass="1"/></body>
    </worldbody></mujoco>)");
  RolloutSpec spec;
  spec.count = 2;
  spec.until = 1;
  spec.sets = {ParseAssignment(model, "qpos[hinge]=0.7")};
  spec.randomize = {ParseRandomization(model, "body_mass[link]=U(0.2,5)")};
  spec.metrics = {ParseMetric(model, "qpos[hinge]@1")};
  std::vector<RolloutResult> r = Collect(model, spec);
  // with damping fixed, a lighter rod is damped more: different angles at 1 s
  EXPECT_NE(r[0].params[0], r[1].params[0]);
  EXPECT_GT(std::fabs(r[0].metrics[0] - r[1].metrics[0]), 1e-3);
  // and the result equals a plain run with that mass set (mj_setConst applied)
  Measurement plain =
      Measure(model,
              {ParseAssignment(model, "qpos[hinge]=0.7"),
               ParseAssignment(model, "body_mass[link]=" + std::to_string(r[0].params[0]))},
              spec.metrics[0], 0.002, 1);
  EXPECT_NEAR(plain.value, r[0].metrics[0], 1e-6);
}

TEST_F(RolloutTest, DerivedMetricsDescribeTheStateOfTheirStep) {
  // xpos of the rod's tip at 1 s must be the tip of the state at 1 s, not of the step
  // before (mj_step leaves derived quantities one step behind)
  Model model = Model::FromXmlString(R"(<mujoco><worldbody>
      <body name="link" pos="0 0 1"><joint name="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0 0 -1" size="0.05" mass="1"/>
        <body name="tip" pos="0 0 -1"/></body>
    </worldbody></mujoco>)");
  for (const char* integrator : {"Euler", "RK4"}) {
    RolloutSpec spec;
    spec.until = 1;
    spec.sets = {ParseAssignment(model, "qpos[hinge]=0.7"),
                 ParseAssignment(model, std::string("opt.integrator=") + integrator)};
    spec.metrics = {ParseMetric(model, "xpos[tip][0]@1"), ParseMetric(model, "qpos[hinge]@1"),
                    ParseMetric(model, "maxabs(xpos[tip][0])")};
    std::vector<RolloutResult> r = Collect(model, spec);
    ASSERT_EQ(r.size(), 1u);
    // the tip of a unit rod at angle q about y sits at x = -sin(q)
    EXPECT_NEAR(r[0].metrics[0], -std::sin(r[0].metrics[1]), 1e-12) << integrator;
    // the largest |x| is the start's, sin(0.7), reached again only at the far turning point
    EXPECT_NEAR(r[0].metrics[2], std::sin(0.7), 1e-3) << integrator;
    EXPECT_GE(r[0].metrics[2], std::fabs(r[0].metrics[0])) << integrator;
  }
}

TEST_F(RolloutTest, DivergedRolloutIsRecordedAndTheBatchGoesOn) {
  Model model = Model::FromXmlString(R"(<mujoco><option timestep="0.01" gravity="0 0 0"/><worldbody>
      <body><joint name="slider" type="slide" axis="1 0 0"/>
      <geom type="sphere" size="0.05" mass="1"/></body></worldbody></mujoco>)");
  RolloutSpec spec;
  spec.count = 4;
  spec.until = 1;
  spec.sets = {ParseAssignment(model, "qpos[slider]=0.01")};
  spec.randomize = {ParseRandomization(model, "jnt_stiffness[slider]=LogU(1,1e7)")};
  spec.metrics = {ParseMetric(model, "maxabs(qpos[slider])")};
  std::vector<RolloutResult> r = Collect(model, spec);
  TakeMujocoWarnings();
  ASSERT_EQ(r.size(), 4u);
  int diverged = 0;
  for (const RolloutResult& x : r) {
    if (x.diverged) {
      ++diverged;
      EXPECT_TRUE(std::isnan(x.metrics[0]));
      EXPECT_GT(x.diverged_time, 0);
    } else {
      EXPECT_NEAR(x.metrics[0], 0.01, 1e-3);
    }
  }
  // omega*dt > 2 diverges: stiffness above 4e4 with dt = 0.01
  int expected = 0;
  for (const RolloutResult& x : r) expected += x.params[0] > 4e4;
  EXPECT_EQ(diverged, expected);
}

TEST_F(RolloutTest, DerivedConstantsFollowTheRandomizedMass) {
  // body_subtreemass is computed by mj_setConst: it equals the drawn masses only if the
  // rollout recomputed it, and returns to nominal for the next rollout
  Model model = Model::FromXmlString(R"(<mujoco><worldbody>
      <body name="upper" pos="0 0 1"><joint axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.05" mass="1"/>
        <body name="lower" pos="0 0 -0.5"><joint axis="0 1 0"/>
          <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.05" mass="2"/></body></body>
    </worldbody></mujoco>)");
  RolloutSpec spec;
  spec.count = 6;
  spec.until = 0.1;
  spec.randomize = {ParseRandomization(model, "body_mass[lower]=U(3,4)")};
  spec.metrics = {ParseMetric(model, "body_subtreemass[upper]@0.1")};
  for (const RolloutResult& r : Collect(model, spec)) {
    EXPECT_NEAR(r.metrics[0], 1 + r.params[0], 1e-12) << r.index;
  }
}

TEST_F(RolloutTest, ADrawMujocoCannotTakeIsThatRolloutsProblem) {
  // N(0.2, 1) masses are often negative: those rollouts are refused with the reason, the
  // others run, and a refused draw leaves the next rollout's model untouched
  Model model = Model::FromXmlString(R"(<mujoco><worldbody>
      <body name="link" pos="0 0 1"><joint name="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0 0 -1" size="0.05" mass="1"/></body>
    </worldbody></mujoco>)");
  RolloutSpec spec;
  spec.count = 40;
  spec.until = 0.2;
  spec.sets = {ParseAssignment(model, "qpos[hinge]=0.7")};
  spec.randomize = {ParseRandomization(model, "body_mass[link]=N(0.2,1)")};
  spec.metrics = {ParseMetric(model, "qpos[hinge]@0.2")};
  std::vector<RolloutResult> r = Collect(model, spec);
  ASSERT_EQ(r.size(), 40u);
  int refused = 0;
  for (const RolloutResult& x : r) {
    if (x.params[0] < 0) {
      ++refused;
      EXPECT_TRUE(std::isnan(x.metrics[0]));
      EXPECT_FALSE(x.diverged);
      EXPECT_NE(x.problem.find("rollout " + std::to_string(x.index)), std::string::npos);
      EXPECT_NE(x.problem.find("body_mass[link]=N(0.2,1)"), std::string::npos) << x.problem;
    } else {
      EXPECT_TRUE(std::isfinite(x.metrics[0])) << x.index;
      EXPECT_TRUE(x.problem.empty()) << x.problem;
    }
  }
  EXPECT_GT(refused, 5);
  EXPECT_LT(refused, 35);
}

TEST_F(RolloutTest, WarningsAreRecordedPerRollout) {
  Model model = Model::FromXmlString(testing::OverfullModel());
  RolloutSpec spec;
  spec.count = 2;
  spec.until = 0.1;
  std::vector<RolloutResult> r = Collect(model, spec);
  TakeMujocoWarnings();
  ASSERT_EQ(r.size(), 2u);
  EXPECT_NE(r[0].warnings.find(testing::kOverfullWarning), std::string::npos) << r[0].warnings;
  EXPECT_EQ(DecodeResult(EncodeResult(r[0])).warnings, r[0].warnings);
}

// A damaged message (as MPI carries them) is refused before anything is allocated for it:
// truncated, a count beyond the bytes left, a negative count, bytes after the end.
TEST_F(RolloutTest, DamagedResultMessagesAreRefused) {
  RolloutResult r;
  r.index = 7;
  r.params = {1, 2};
  r.metrics = {3};
  r.problem = "p";
  std::string bytes = EncodeResult(r);
  RolloutResult back = DecodeResult(bytes);
  EXPECT_EQ(back.index, 7);
  EXPECT_EQ(back.params, r.params);
  EXPECT_EQ(back.metrics, r.metrics);
  EXPECT_EQ(back.problem, "p");
  EXPECT_THROW(DecodeResult(bytes.substr(0, bytes.size() - 1)), ValueError);
  EXPECT_THROW(DecodeResult(bytes + "x"), ValueError);
  std::string huge = bytes;
  std::int64_t n = std::int64_t{1} << 60;  // the params count, after index, diverged, time
  std::memcpy(huge.data() + 24, &n, sizeof(n));
  EXPECT_THROW(DecodeResult(huge), ValueError);
  n = -1;
  std::memcpy(huge.data() + 24, &n, sizeof(n));
  EXPECT_THROW(DecodeResult(huge), ValueError);
}

TEST_F(RolloutTest, BadSpecsAreRejected) {
  RolloutSpec spec;
  spec.shard_count = 2;
  spec.shard_index = 2;
  EXPECT_THROW(Collect(humanoid_, spec), ValueError);
  spec = {};
  spec.metrics = {ParseMetric(humanoid_, "xpos[torso][2]@5")};
  spec.until = 1;
  EXPECT_THROW(Collect(humanoid_, spec), ValueError);  // metric time beyond the run
  EXPECT_THROW(ParseRandomization(humanoid_, "xpos[torso][2]=U(0,1)"), PathError);
  EXPECT_THROW(ParseRandomization(humanoid_, "body_mass[*]"), ValueError);
}

TEST_F(RolloutTest, CtrlNoiseIsIndependentPerRolloutAndSeed) {
  // the noise was one Halton sequence shared by every rollout: identical rows for all
  RolloutSpec spec;
  spec.count = 3;
  spec.until = 0.2;
  spec.seed = 1;
  spec.ctrl_noise = 0.5;
  spec.metrics = {ParseMetric(humanoid_, "state@0.2")};
  std::vector<RolloutResult> a = Collect(humanoid_, spec);
  ASSERT_EQ(a.size(), 3u);
  EXPECT_NE(a[0].metrics[0], a[1].metrics[0]);
  EXPECT_NE(a[1].metrics[0], a[2].metrics[0]);
  // deterministic: the same seed gives the same rows, any thread count
  spec.threads = 2;
  std::vector<RolloutResult> again = Collect(humanoid_, spec);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_TRUE(BitEqual(a[i].metrics[0], again[i].metrics[0])) << i;
  }
  // another seed, other noise
  spec.seed = 2;
  std::vector<RolloutResult> other = Collect(humanoid_, spec);
  EXPECT_NE(a[0].metrics[0], other[0].metrics[0]);
}

TEST_F(RolloutTest, TheSameElementRandomizedTwiceIsRefused) {
  // two --randomize of one element gave two columns with one name, the later draw winning
  RolloutSpec spec;
  spec.randomize = {ParseRandomization(humanoid_, "body_mass[torso]=*U(0.9,1.1)"),
                    ParseRandomization(humanoid_, "body_mass[*]=*U(0.5,2)")};
  try {
    ValidateRolloutSpec(humanoid_, spec);
    FAIL() << "accepted";
  } catch (const ValueError& e) {
    EXPECT_NE(std::string(e.what()).find("both draw body_mass[torso]"), std::string::npos)
        << e.what();
  }
  spec.randomize = {ParseRandomization(humanoid_, "body_mass[torso]=*U(0.9,1.1)"),
                    ParseRandomization(humanoid_, "body_ipos[torso][0]=U(0,0.01)")};
  EXPECT_NO_THROW(ValidateRolloutSpec(humanoid_, spec));
}

TEST_F(RolloutTest, AStopRequestKeepsTheRolloutsThatFinished) {
  RolloutSpec spec;
  spec.count = 200;
  spec.until = 0.05;
  spec.metrics = {ParseMetric(humanoid_, "state@0.05")};
  StopSource stop;
  std::vector<long> emitted;
  EXPECT_THROW(Rollout(
                   humanoid_, spec,
                   [&](const RolloutResult& r) {
                     emitted.push_back(r.index);
                     if (r.index == 2) stop.RequestStop();
                   },
                   stop.token()),
               Interrupted);
  ASSERT_GE(emitted.size(), 3u);
  EXPECT_LT(emitted.size(), 200u);
  for (std::size_t i = 0; i < emitted.size(); ++i) EXPECT_EQ(emitted[i], static_cast<long>(i));
}

// A stop in the middle of a chunk of two threads: every rollout that finished is emitted and
// stored, also those after the first unfinished one (before, a stop kept only the results
// before it), and resuming the store completes a batch equal to one never stopped.
TEST_F(RolloutTest, AStopMidChunkStoresEveryFinishedRolloutAndResumeCompletesIt) {
  testing::TempDir dir;
  const std::string db = dir.File("r.sqlite");
  RolloutSpec spec;
  spec.count = 300;
  spec.until = 0.3;
  spec.threads = 2;
  spec.randomize = {ParseRandomization(humanoid_, "body_mass[torso]=*U(0.8,1.2)")};
  spec.metrics = {ParseMetric(humanoid_, "xpos[torso][2]@0.3")};
  const std::vector<RolloutResult> whole = Collect(humanoid_, spec);
  RunInfo info = NewRunInfo("rollout", "stop-mid-chunk", {"test"}, "humanoid.xml", "h");
  info.count = spec.count;

  StopSource stop;
  std::atomic<long> finished{0};
  RolloutSpec stopped = spec;
  stopped.progress = [&](long done, long) {
    for (long seen = finished.load(); seen < done && !finished.compare_exchange_weak(seen, done);) {
    }
    if (done == 40) stop.RequestStop();  // a chunk is 128 rollouts: this is the middle of one
  };
  std::vector<long> emitted;
  {
    StoredRun run = OpenStoredRun(db, false, info);
    EXPECT_THROW(Rollout(
                     humanoid_, stopped,
                     [&](const RolloutResult& r) {
                       emitted.push_back(r.index);
                       run.store->Add(run.id, r);
                     },
                     stop.token()),
                 Interrupted);
    run.store->Commit();
  }
  ASSERT_GE(emitted.size(), 40u);
  ASSERT_LT(emitted.size(), 300u);
  // every rollout that finished was emitted, in increasing index order (gaps allowed)
  EXPECT_EQ(static_cast<long>(emitted.size()), finished.load());
  EXPECT_TRUE(std::is_sorted(emitted.begin(), emitted.end()));
  // and stored
  StoredRun resumed = OpenStoredRun(db, true, info);
  EXPECT_EQ(resumed.done, emitted);

  // the rest, resumed, completes the batch: every row as the uninterrupted batch's
  RolloutSpec rest = spec;
  rest.skip = resumed.done;
  Rollout(humanoid_, rest, [&](const RolloutResult& r) { resumed.store->Add(resumed.id, r); });
  CompleteStoredRun(resumed, spec.count);
  std::vector<RolloutResult> stored = resumed.store->Results(resumed.id);
  ASSERT_EQ(stored.size(), whole.size());
  std::sort(stored.begin(), stored.end(),
            [](const RolloutResult& a, const RolloutResult& b) { return a.index < b.index; });
  for (std::size_t i = 0; i < whole.size(); ++i) {
    SCOPED_TRACE(i);
    ASSERT_EQ(stored[i].index, whole[i].index);
    ASSERT_EQ(stored[i].metrics.size(), 1u);
    EXPECT_TRUE(BitEqual(stored[i].metrics[0], whole[i].metrics[0]));
    EXPECT_TRUE(BitEqual(stored[i].params[0], whole[i].params[0]));
    EXPECT_EQ(stored[i].diverged, whole[i].diverged);
  }
}

}  // namespace
}  // namespace plumb
