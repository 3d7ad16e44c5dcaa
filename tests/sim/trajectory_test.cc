#include "plumb/trajectory.h"

#include <gtest/gtest.h>

#include "fixture.h"
#include "plumb/error.h"
#include "plumb/timing.h"

namespace plumb {
namespace {

using testing::kChapterQ;
using testing::kPendulum;
using TrajectoryTest = testing::MujocoTest;

// The header's example: the chapter's run kept in one buffer, sized before the run.
TEST_F(TrajectoryTest, KeepsTheChaptersRunInOneBuffer) {
  Model model = Model::Load(kPendulum);
  Data data(model);
  ApplyAssignments(model, data, {ParseAssignment(model, "qpos[hinge]=0.7")});
  RunSpec spec;
  spec.until = 0.5;
  spec.every = RunEvery(std::nullopt, model->opt.timestep);
  spec.columns = RunColumns(model, {"time,qpos[hinge]"});
  Schedule schedule = MakeSchedule(model->opt.timestep, spec.until, spec.every);
  ASSERT_EQ(SampleCount(schedule), 6);
  TrajectorySink sink(SampleCount(schedule));
  plumb::Run(model, data, spec, sink);
  EXPECT_EQ(sink.names(), (std::vector<std::string>{"time", "qpos[hinge]"}));
  ASSERT_EQ(sink.rows(), 6);
  std::vector<double> values = sink.Take();
  ASSERT_EQ(values.size(), 12u);
  EXPECT_EQ(values.capacity(), 12u);  // one allocation of exactly the planned size
  for (int k = 1; k <= 5; ++k) {
    EXPECT_DOUBLE_EQ(values[2 * k], 0.1 * k);
    EXPECT_NEAR(values[2 * k + 1], kChapterQ[k - 1], 5e-6);
  }
}

TEST_F(TrajectoryTest, RefusesMoreSamplesThanPlanned) {
  TrajectorySink sink(1);
  Model model = Model::Load(kPendulum);
  sink.Begin(RunColumns(model, {"time"}));
  sink.Sample({0.0});
  EXPECT_THROW(sink.Sample({0.1}), InternalError);
}

TEST_F(TrajectoryTest, ColumnsExpandAndSplit) {
  Model model = Model::Load(kPendulum);
  EXPECT_EQ(RunColumns(model, {}).size(), DefaultColumns(model).size());
  std::vector<Path> columns = RunColumns(model, {"time,xpos[link]", "qpos[*]"});
  ASSERT_EQ(columns.size(), 5u);
  EXPECT_EQ(columns[1].text, "xpos[link][0]");
  EXPECT_EQ(columns[4].text, "qpos[hinge]");
  EXPECT_THROW(RunColumns(model, {"qpos[hinj]"}), PathError);
  EXPECT_EQ(SplitPathList("a,b[1,2],c"), (std::vector<std::string>{"a", "b[1,2]", "c"}));
}

// 0.1 s when it is whole steps, else the nearest whole number of steps; a given interval stays.
TEST_F(TrajectoryTest, EveryDefaultsToATenthOfASecondOnWholeSteps) {
  EXPECT_EQ(RunEvery(std::nullopt, 0.002), 0.1);
  EXPECT_DOUBLE_EQ(RunEvery(std::nullopt, 0.03), 0.09);
  EXPECT_EQ(RunEvery(0.25, 0.002), 0.25);
}

}  // namespace
}  // namespace plumb
