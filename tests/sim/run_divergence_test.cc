// The state a failing step started from, as Run names it: kept every 64 steps and re-stepped
// from there when only the state decides the run, kept before every step otherwise.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "fixture.h"
#include "plumb/run.h"

namespace plumb {
namespace {

using RunDivergenceTest = testing::MujocoTest;

// Under Euler at 10 ms the spring is just unstable (omega * dt = 2.01): its swing grows by
// a quarter a step, and it diverges after about 80 steps, well past the first kept state.
constexpr char kSlowlyUnstable[] = R"(
<mujoco model="slow">
  <option timestep="0.01" gravity="0 0 0"/>
  <worldbody>
    <body name="mass">
      <joint name="slider" type="slide" axis="1 0 0" stiffness="4.05e4"/>
      <geom type="sphere" size="0.05" mass="1"/>
    </body>
  </worldbody>
  <actuator><motor name="push" joint="slider"/></actuator>
</mujoco>)";

Divergence RunToDivergence(Model& model, const RunSpec& spec, long* steps) {
  Data data(model);
  ApplyAssignments(model, data, {ParseAssignment(model, "qpos[slider]=0.01")});
  NullSink sink;
  RunResult result = plumb::Run(model, data, spec, sink);
  TakeMujocoWarnings();  // the divergence's own warning, expected here
  EXPECT_TRUE(result.divergence);
  *steps = result.steps;
  return result.divergence ? *result.divergence : Divergence{};
}

RunSpec TenSeconds() {
  RunSpec spec;
  spec.until = 10;
  spec.every = 0.01;
  return spec;
}

// The state after `steps` steps from the same start, stepped plainly.
StateSnapshot Stepped(Model& model, long steps) {
  Data data(model);
  ApplyAssignments(model, data, {ParseAssignment(model, "qpos[slider]=0.01")});
  for (long n = 0; n < steps; ++n) data.Step();
  return Snapshot(model, data, steps);
}

TEST_F(RunDivergenceTest, TheStateBeforeALateFailingStepIsTheRunsOwn) {
  Model model = Model::FromXmlString(kSlowlyUnstable, "slow.xml");
  long steps = 0;
  Divergence div = RunToDivergence(model, TenSeconds(), &steps);
  // re-stepped from a kept state after the first, not at one
  ASSERT_GT(div.last_good.step, 64) << div.reason;
  ASSERT_NE(div.last_good.step % 64, 0) << div.reason;
  EXPECT_EQ(div.last_good.step + 1, steps);
  EXPECT_DOUBLE_EQ(div.last_good.time, div.last_good.step * 0.01);
  StateSnapshot plain = Stepped(model, div.last_good.step);
  EXPECT_EQ(div.last_good.integration, plain.integration);
  EXPECT_EQ(div.last_good.qpos, plain.qpos);
  EXPECT_EQ(div.last_good.qvel, plain.qvel);
  EXPECT_TRUE(div.last_good.note.empty()) << div.last_good.note;
  // put back and stepped once, it fails as the run did
  Data again(model);
  Restore(model, again, div.last_good);
  again.Step();
  if (div.reset_by_mujoco) {
    EXPECT_EQ(div.bad.integration, div.last_good.integration);
    EXPECT_GT(again->warning[mjWARN_BADQACC].number + again->warning[mjWARN_BADQVEL].number +
                  again->warning[mjWARN_BADQPOS].number,
              0);
  } else {
    EXPECT_EQ(Snapshot(model, again, steps).integration, div.bad.integration);
  }
  TakeMujocoWarnings();
}

TEST_F(RunDivergenceTest, AStepCallbackWritingInputsHasEveryStateKept) {
  // re-stepping could not repeat what the callback wrote: the state before the failing step
  // holds the ctrl written for that very step
  Model model = Model::FromXmlString(kSlowlyUnstable, "slow.xml");
  RunSpec spec = TenSeconds();
  spec.before_step = [](mjData* d, long step) { d->ctrl[0] = 1e-3 * static_cast<double>(step); };
  long steps = 0;
  Divergence div = RunToDivergence(model, spec, &steps);
  ASSERT_GT(div.last_good.step, 64) << div.reason;
  ASSERT_EQ(div.last_good.ctrl.size(), 1u);
  EXPECT_DOUBLE_EQ(div.last_good.ctrl[0], 1e-3 * static_cast<double>(steps));
  EXPECT_TRUE(div.last_good.note.empty()) << div.last_good.note;
}

TEST_F(RunDivergenceTest, ReSteppingCallsNoCallbackAgain) {
  Model model = Model::FromXmlString(kSlowlyUnstable, "slow.xml");
  RunSpec spec = TenSeconds();
  long after = 0;
  spec.after_step = [&](const mjData*, long) { ++after; };
  long steps = 0;
  Divergence div = RunToDivergence(model, spec, &steps);
  ASSERT_GT(div.last_good.step, 64) << div.reason;
  EXPECT_EQ(after, steps - 1);  // every step but the failing one, once
}

}  // namespace
}  // namespace plumb
