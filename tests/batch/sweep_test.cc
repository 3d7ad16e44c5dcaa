#include "plumb/sweep.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <thread>

#include "fixture.h"
#include "plumb/error.h"

namespace plumb {
namespace {

using SweepTest = testing::MujocoTest;

TEST_F(SweepTest, AxesParseListsRangesAndNames) {
  Model model = Model::Load(testing::kPendulum);
  SweepAxis list = ParseSweepAxis(model, "dof_damping[hinge]=0,0.05,1");
  EXPECT_EQ(list.size(), 3u);
  EXPECT_EQ(list.Value(1).values[0], 0.05);
  SweepAxis range = ParseSweepAxis(model, "qpos[hinge]=0.1:2.8:4");
  ASSERT_EQ(range.size(), 4u);
  EXPECT_DOUBLE_EQ(range.Value(0).values[0], 0.1);
  EXPECT_DOUBLE_EQ(range.Value(3).values[0], 2.8);
  SweepAxis names = ParseSweepAxis(model, "opt.integrator=Euler,RK4");
  EXPECT_EQ(names.Value(1).values[0], mjINT_RK4);
  EXPECT_EQ(CaseCount({list, range, names}), 24);
  EXPECT_THROW(ParseSweepAxis(model, "opt.gravity=1,2"), ValueError);  // 3 elements
  EXPECT_THROW(ParseSweepAxis(model, "qpos[hinge]=1:2"), ValueError);
  EXPECT_THROW(ParseSweepAxis(model, "qpos[hinge]=a,b"), ValueError);
  EXPECT_THROW(ParseSweepAxis(model, "qpos[hinge]"), ValueError);
}

TEST_F(SweepTest, CasesComeInOrderAndMatchSingleRuns) {
  Model model = Model::Load(testing::kPendulum);
  SweepSpec spec;
  spec.sets = {ParseAssignment(model, "qpos[hinge]=0.7")};
  spec.axes = {ParseSweepAxis(model, "dof_damping[hinge]=0,0.05"),
               ParseSweepAxis(model, "opt.timestep=0.002,0.001")};
  spec.metrics = {ParseMetric(model, "qpos[hinge]@2")};
  std::vector<SweepCase> cases = Sweep(model, spec);
  ASSERT_EQ(cases.size(), 4u);
  EXPECT_EQ(cases[2].choice, (std::vector<std::size_t>{1, 0}));  // first axis slowest
  // case 2 is damping 0.05 at dt 0.002: the chapter's pendulum. 0.310947692600239 is its
  // q(2) with Euler as MuJoCo 2.2.2 computes it, the value `plumb run models/pendulum.xml
  // --set 'qpos[hinge]=0.7' --until 2 --every 2 --format csv` prints
  EXPECT_NEAR(cases[2].metrics[0].value, 0.310947692600239, 1e-13);
  Measurement single =
      Measure(model, {spec.sets[0], spec.axes[0].Value(1)}, spec.metrics[0], 0.002, 2);
  EXPECT_EQ(cases[2].metrics[0].value, single.value);
}

// MuJoCo's control callback, called in every mj_step and mj_forward: what a run costs.
std::atomic<long> g_calls{0};
void CountCall(const mjModel*, mjData*) { ++g_calls; }

template <typename F>
long CallsOf(F&& run) {
  g_calls = 0;
  mjcb_control = &CountCall;
  run();
  mjcb_control = nullptr;
  return g_calls.load();
}

// 9 cases x 2 metrics of one run length cost 9 simulations, not 18: a case's metrics are
// measured in one run (as many MuJoCo calls as one metric's run), and each gives what its own
// run gave.
TEST_F(SweepTest, ACaseRunsOnceForAllItsMetricsOfOneLength) {
  Model model = Model::Load(testing::kPendulum);
  SweepSpec spec;
  spec.sets = {ParseAssignment(model, "qpos[hinge]=0.7")};
  spec.axes = {ParseSweepAxis(model, "dof_damping[hinge]=0:0.4:9")};
  spec.metrics = {ParseMetric(model, "maxabs(qvel[hinge])"), ParseMetric(model, "energy_drift")};
  spec.until = 1;  // 500 steps
  std::vector<Measurement> single;
  long one_run = 0;
  const std::vector<Assignment> case4 = {spec.sets[0], spec.axes[0].Value(4)};
  for (const Metric& metric : spec.metrics) {
    long calls = CallsOf([&] { single.push_back(Measure(model, case4, metric, 0.002, 1)); });
    one_run = std::max(one_run, calls);
  }
  std::vector<SweepCase> cases;
  long sweep = CallsOf([&] { cases = Sweep(model, spec); });
  ASSERT_EQ(cases.size(), 9u);
  EXPECT_GE(one_run, 500);
  EXPECT_EQ(sweep, 9 * one_run) << "one run per case costs " << one_run << " calls";
  for (const SweepCase& c : cases) EXPECT_EQ(c.runs, 1);
  for (std::size_t k = 0; k < spec.metrics.size(); ++k) {
    EXPECT_EQ(cases[4].metrics[k].value, single[k].value) << spec.metrics[k].text;
  }
  // metrics of two lengths: two runs
  spec.metrics.push_back(ParseMetric(model, "qpos[hinge]@0.5"));
  cases = Sweep(model, spec);
  EXPECT_EQ(cases[0].runs, 2);
  EXPECT_EQ(cases[0].metrics[2].value,
            Measure(model, {spec.sets[0], spec.axes[0].Value(0)}, spec.metrics[2], 0.002, 0.5)
                .value);
}

TEST_F(SweepTest, OneAndTwoThreadsAreBitIdentical) {
  Model model = Model::Load(testing::kHumanoid);
  SweepSpec spec;
  // 64 cases, so two workers interleave many times
  spec.axes = {ParseSweepAxis(model, "body_mass[torso]=4:8:16"),
               ParseSweepAxis(model, "opt.gravity[2]=-9.81,-5,-3.71,-1.62")};
  spec.metrics = {ParseMetric(model, "state@0.2"), ParseMetric(model, "xpos[head][2]@0.2")};
  spec.threads = 1;
  std::vector<SweepCase> one = Sweep(model, spec);
  spec.threads = 2;
  std::atomic<long> progress_calls{0};
  spec.progress = [&](long, long total) {
    EXPECT_EQ(total, 64);
    ++progress_calls;
  };
  std::vector<SweepCase> two = Sweep(model, spec);
  EXPECT_EQ(progress_calls.load(), 64);
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t i = 0; i < one.size(); ++i) {
    for (std::size_t m = 0; m < one[i].metrics.size(); ++m) {
      const Measurement& a = one[i].metrics[m];
      const Measurement& b = two[i].metrics[m];
      EXPECT_EQ(std::memcmp(&a.value, &b.value, sizeof(double)), 0) << "case " << i;
      EXPECT_EQ(a.state, b.state) << "case " << i;
    }
  }
  // a heavier torso changes the dynamics: the sweep really varies the model
  EXPECT_NE(one[0].metrics[0].value, one[10].metrics[0].value);
}

TEST_F(SweepTest, DivergedCaseIsRecordedAndTheSweepGoesOn) {
  Model model = Model::FromXmlString(R"(<mujoco><option gravity="0 0 0"/><worldbody>
      <body><joint name="slider" type="slide" axis="1 0 0" stiffness="1e6"/>
      <geom type="sphere" size="0.05" mass="1"/></body></worldbody></mujoco>)");
  SweepSpec spec;
  spec.sets = {ParseAssignment(model, "qpos[slider]=0.01")};
  spec.axes = {ParseSweepAxis(model, "opt.timestep=0.0001,0.01")};
  spec.metrics = {ParseMetric(model, "maxabs(qpos[slider])")};
  spec.until = 1;
  std::vector<SweepCase> cases = Sweep(model, spec);
  TakeMujocoWarnings();
  EXPECT_TRUE(cases[0].metrics[0].ok);
  EXPECT_NEAR(cases[0].metrics[0].value, 0.01, 1e-4);
  EXPECT_FALSE(cases[1].metrics[0].ok);
  EXPECT_NE(cases[1].metrics[0].problem.find("diverged"), std::string::npos);
}

TEST_F(SweepTest, AHundredMillionValueRangeTakesNoMemory) {
  // --vary 'x=1:2:100000000' once built 10^8 assignments (2.9 GB in 18 s) before any output
  Model model = Model::Load(testing::kPendulum);
  SweepAxis range = ParseSweepAxis(model, "dof_damping[hinge]=1:2:100000000");
  EXPECT_EQ(range.size(), 100000000u);
  EXPECT_TRUE(range.listed.empty());
  EXPECT_EQ(range.Value(0).values[0], 1);
  EXPECT_EQ(range.Value(99999999).values[0], 2);
  EXPECT_EQ(range.Label(99999999), "2");
  EXPECT_NEAR(range.Value(50000000).values[0], 1.5, 1e-8);
  EXPECT_EQ(CaseCount({range}), 100000000);
  // the endpoints are checked as they always were
  EXPECT_THROW(ParseSweepAxis(model, "opt.timestep=-1:2:100000000"), ValueError);
}

TEST_F(SweepTest, ACaseCountBeyondTwoToThe53IsRefusedNotWrapped) {
  Model model = Model::Load(testing::kPendulum);
  SweepAxis big = ParseSweepAxis(model, "dof_damping[hinge]=1:2:999999999");
  SweepAxis more = ParseSweepAxis(model, "qpos[hinge]=0:1:999999999");
  EXPECT_THROW(CaseCount({big, more}), ValueError);
  EXPECT_EQ(CaseCount({big}), 999999999);
}

TEST_F(SweepTest, TheSameElementVariedTwiceIsRefused) {
  // two --vary of one element gave two columns with one name, the later silently winning
  Model model = Model::Load(testing::kPendulum);
  SweepSpec spec;
  spec.axes = {ParseSweepAxis(model, "dof_damping[hinge]=0,0.05"),
               ParseSweepAxis(model, "dof_damping[0]=1,2")};
  spec.metrics = {ParseMetric(model, "qpos[hinge]@1")};
  try {
    ValidateSweepSpec(model, spec);
    FAIL() << "accepted";
  } catch (const ValueError& e) {
    EXPECT_NE(std::string(e.what()).find("both vary dof_damping[hinge]"), std::string::npos)
        << e.what();
  }
  spec.axes[1] = ParseSweepAxis(model, "dof_damping[hinge]=1,2");
  EXPECT_THROW(ValidateSweepSpec(model, spec), ValueError);
  // different elements of one field are fine
  spec.axes[1] = ParseSweepAxis(model, "dof_armature[hinge]=0,1");
  EXPECT_NO_THROW(ValidateSweepSpec(model, spec));
}

// The pendulum from 0.7 rad at 40 dampings from 0 to 1, on two threads.
SweepSpec FortyDampings(const Model& model, const std::string& metric) {
  SweepSpec spec;
  spec.sets = {ParseAssignment(model, "qpos[hinge]=0.7")};
  spec.axes = {ParseSweepAxis(model, "dof_damping[hinge]=0:1:40")};
  spec.metrics = {ParseMetric(model, metric)};
  spec.threads = 2;
  return spec;
}

TEST_F(SweepTest, StreamingSkipsStoredCasesAndKeepsFinishedOnStop) {
  Model model = Model::Load(testing::kPendulum);
  SweepSpec spec = FortyDampings(model, "qpos[hinge]@0.2");
  std::vector<SweepCase> all = Sweep(model, spec);
  ASSERT_EQ(all.size(), 40u);
  // a resumed sweep runs only what is not stored, in order, with the same numbers
  std::vector<long> skip = {0, 1, 2, 10, 39};
  std::vector<long> seen;
  Sweep(model, spec, skip, [&](const SweepCase& c) {
    seen.push_back(c.index);
    EXPECT_EQ(c.metrics[0].value, all[c.index].metrics[0].value) << c.index;
  });
  EXPECT_EQ(seen.size(), 35u);
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  for (long s : skip) EXPECT_EQ(std::count(seen.begin(), seen.end(), s), 0) << s;
  // a stop request keeps every case emitted before it, then every other finished one (in
  // order, with gaps where a case did not finish: WorkerPool::OnStop::kEveryFinished), and
  // throws Interrupted
  StopSource stop;
  std::vector<long> before_stop;
  EXPECT_THROW(Sweep(
                   model, spec, {},
                   [&](const SweepCase& c) {
                     before_stop.push_back(c.index);
                     if (c.index == 5) stop.RequestStop();
                   },
                   stop.token()),
               Interrupted);
  ASSERT_GE(before_stop.size(), 6u);
  EXPECT_LT(before_stop.size(), 40u);
  for (std::size_t i = 0; i < 6; ++i) EXPECT_EQ(before_stop[i], static_cast<long>(i));
  EXPECT_TRUE(std::adjacent_find(before_stop.begin(), before_stop.end(),
                                 std::greater_equal<long>()) == before_stop.end());
}

// Two sweeps on two threads, each with its own stop request: stopping one leaves the other
// running to the end, with the same cases as alone (the Python package cancels one call of
// a notebook without stopping another's).
TEST_F(SweepTest, StoppingOneSweepLeavesAnotherThreadsSweepRunning) {
  Model model = Model::Load(testing::kPendulum);
  SweepSpec spec = FortyDampings(model, "qpos[hinge]@0.5");
  std::vector<SweepCase> alone = Sweep(model, spec);
  StopSource first, second;
  std::vector<long> stopped_cases;
  std::vector<SweepCase> other_cases;
  std::thread stopped([&] {
    EXPECT_THROW(Sweep(
                     model, spec, {},
                     [&](const SweepCase& c) {
                       stopped_cases.push_back(c.index);
                       if (c.index == 3) first.RequestStop();
                     },
                     first.token()),
                 Interrupted);
  });
  std::thread other([&] {
    Sweep(
        model, spec, {}, [&](const SweepCase& c) { other_cases.push_back(c); }, second.token());
  });
  stopped.join();
  other.join();
  EXPECT_LT(stopped_cases.size(), 40u);
  ASSERT_EQ(other_cases.size(), alone.size());
  for (std::size_t i = 0; i < alone.size(); ++i) {
    EXPECT_EQ(other_cases[i].metrics[0].value, alone[i].metrics[0].value) << i;
  }
}

}  // namespace
}  // namespace plumb
