#include "plumb/run.h"

#include <gtest/gtest.h>

#include <cmath>

#include "fixture.h"
#include "plumb/error.h"
#include "plumb/sample_writer.h"
#include "sim/start_hints.h"

namespace plumb {
using internal::StartHint;
using internal::StartHints;

namespace {

using testing::kChapterDq;
using testing::kChapterQ;
using testing::kPendulum;
using testing::MujocoTest;

// Keeps every row (tests only: real sinks stream).
class RecordingSink : public SampleSink {
 public:
  void Begin(const std::vector<Path>& columns) override { columns_ = columns; }
  void Sample(const std::vector<double>& row) override { rows.push_back(row); }
  void End() override { ended = true; }
  std::vector<std::vector<double>> rows;
  std::vector<Path> columns_;
  bool ended = false;
};

RunSpec PendulumSpec(const Model& model, double until = 2.0, double every = 0.1) {
  RunSpec spec;
  spec.until = until;
  spec.every = every;
  spec.columns = DefaultColumns(model);
  return spec;
}

using RunTest = MujocoTest;

TEST_F(RunTest, ReproducesTheChaptersPrintedLines) {
  Model model = Model::Load(kPendulum);
  Data data(model);
  ApplyAssignments(model, data, {ParseAssignment(model, "qpos[hinge]=0.7")});
  RecordingSink sink;
  RunResult result = plumb::Run(model, data, PendulumSpec(model), sink);
  ASSERT_FALSE(result.diverged);
  EXPECT_EQ(result.steps, 1000);
  ASSERT_EQ(sink.rows.size(), 21u);  // t = 0, 0.1, ..., 2
  EXPECT_TRUE(sink.ended);
  // the chapter prints 5 decimals: agreement to half a unit in the last place
  for (int k = 0; k < 5; ++k) {
    EXPECT_NEAR(sink.rows[k + 1][1], kChapterQ[k], 5e-6) << "t = " << 0.1 * (k + 1);
    EXPECT_NEAR(sink.rows[k + 1][2], kChapterDq[k], 5e-6) << "t = " << 0.1 * (k + 1);
  }
  EXPECT_TRUE(result.warnings.empty());
}

// A run finishes its sink on every path: the end, a divergence, a stop request, and an
// exception from a step callback or MuJoCo.
TEST_F(RunTest, TheSinkIsFinishedOnEveryPath) {
  Model model = Model::Load(kPendulum);
  {
    Data data(model);
    RecordingSink sink;
    RunSpec spec = PendulumSpec(model, 0.1);
    spec.before_step = [](mjData*, long step) {
      if (step == 3) throw ValueError("a controller failed");
    };
    EXPECT_THROW(plumb::Run(model, data, spec, sink), ValueError);
    EXPECT_TRUE(sink.ended);
    EXPECT_EQ(sink.rows.size(), 1u);
  }
  {
    Data data(model);
    RecordingSink sink;
    StopSource stop;
    stop.RequestStop();
    RunSpec spec = PendulumSpec(model, 0.1);
    spec.stop = stop.token();
    EXPECT_THROW(plumb::Run(model, data, spec, sink), Interrupted);
    EXPECT_TRUE(sink.ended);
  }
  {
    Data data(model);
    RecordingSink sink;
    EXPECT_FALSE(plumb::Run(model, data, PendulumSpec(model, 0.1), sink).diverged);
    EXPECT_TRUE(sink.ended);
  }
}

// The time column is the step count times the timestep, in the decimals the timestep has:
// 175 * 0.002 is 0.35000000000000003 in binary (18 % of rows printed so broke joins on time),
// and the column holds the double nearest 0.35.
TEST_F(RunTest, SampleTimesAreStepMultiplesInTheTimestepsDecimals) {
  Model model = Model::Load(kPendulum);
  Data data(model);
  RecordingSink sink;
  plumb::Run(model, data, PendulumSpec(model, 2.0, 0.05), sink);
  ASSERT_EQ(sink.rows.size(), 41u);
  for (std::size_t k = 0; k < sink.rows.size(); ++k) {
    EXPECT_EQ(sink.rows[k][0], static_cast<double>(50 * k) / 1000) << k;  // nearest to k/20
    EXPECT_LE(CsvNumber(sink.rows[k][0]).size(), 4u) << CsvNumber(sink.rows[k][0]);
  }
  EXPECT_EQ(CsvNumber(sink.rows[7][0]), "0.35");
  // d->time accumulated by addition agrees to round-off only
  EXPECT_NEAR(data->time, 2.0, 1e-12);
}

TEST_F(RunTest, ScheduleRejectsBadIntervals) {
  EXPECT_EQ(MakeSchedule(0.002, 2.0, 0.1).steps, 1000);
  EXPECT_EQ(MakeSchedule(0.002, 2.0, 0.1).stride, 50);
  EXPECT_EQ(MakeSchedule(0.002, 0.0031, 0.002).steps, 2);  // like while (time < until)
  EXPECT_EQ(MakeSchedule(0.002, 0, 0.002).steps, 0);
  EXPECT_THROW(MakeSchedule(0.002, 2.0, 0.003), ValueError);
  EXPECT_THROW(MakeSchedule(0.002, 2.0, 0.001), ValueError);
  EXPECT_THROW(MakeSchedule(0.002, 2.0, 0), ValueError);
  EXPECT_THROW(MakeSchedule(0.002, -1, 0.1), ValueError);
  EXPECT_THROW(MakeSchedule(0.002, NAN, 0.1), ValueError);
  try {
    MakeSchedule(0.002, 2.0, 0.003);
  } catch (const ValueError& e) {
    EXPECT_NE(std::string(e.what()).find("0.002 or 0.004"), std::string::npos) << e.what();
  }
}

// A stiff spring: semi-implicit Euler is unstable once omega * dt > 2 (here 10).
constexpr char kStiffSpring[] = R"(
<mujoco model="stiff">
  <option timestep="0.01" gravity="0 0 0"/>
  <worldbody>
    <body name="mass">
      <joint name="slider" type="slide" axis="1 0 0" stiffness="1e6"/>
      <geom type="sphere" size="0.05" mass="1"/>
    </body>
  </worldbody>
</mujoco>)";

// Steps are numbered by the data's clock: a run that starts later (audit's step response
// after its hold, a run in pieces) names a divergence by the same step as one run from t = 0
// (audit said "step 59" where run said "step 534").
TEST_F(RunTest, StepsAreNumberedByTheClockWhereverARunStarts) {
  Model model = Model::FromXmlString(kStiffSpring, "stiff.xml");
  auto diverge = [&](double first_piece) {
    Data data(model);
    ApplyAssignments(model, data, {ParseAssignment(model, "qpos[slider]=0.01")});
    RecordingSink sink;
    if (first_piece > 0) {
      EXPECT_FALSE(plumb::Run(model, data, PendulumSpec(model, first_piece, 0.01), sink).diverged);
    }
    return plumb::Run(model, data, PendulumSpec(model, 10, 0.01), sink);
  };
  RunResult whole = diverge(0), pieces = diverge(0.02);
  ASSERT_TRUE(whole.divergence && pieces.divergence);
  EXPECT_EQ(pieces.steps + 2, whole.steps);  // steps taken by each run
  EXPECT_EQ(pieces.divergence->reason, whole.divergence->reason);
  EXPECT_EQ(pieces.divergence->bad.step, whole.divergence->bad.step);
  EXPECT_EQ(pieces.divergence->last_good.step, whole.divergence->last_good.step);
  ASSERT_FALSE(whole.warnings.empty());
  EXPECT_EQ(pieces.warnings[0].first_step, whole.warnings[0].first_step);
  TakeMujocoWarnings();  // MuJoCo's BADQACC, expected here
}

TEST_F(RunTest, DivergenceStopsTheRunWithBothStates) {
  Model model = Model::FromXmlString(kStiffSpring, "stiff.xml");
  Data data(model);
  ApplyAssignments(model, data, {ParseAssignment(model, "qpos[slider]=0.01")});
  RecordingSink sink;
  RunResult result = plumb::Run(model, data, PendulumSpec(model, 10, 0.01), sink);
  ASSERT_TRUE(result.diverged);
  ASSERT_TRUE(result.divergence);
  EXPECT_LT(result.steps, 1000);
  const Divergence& div = *result.divergence;
  // the failing step is the last one taken; a state MuJoCo found bad is the one that
  // step started from, and every state's step agrees with its time
  EXPECT_EQ(div.last_good.step + 1, result.steps);
  EXPECT_EQ(div.bad.step, div.reset_by_mujoco ? div.last_good.step : div.last_good.step + 1);
  EXPECT_DOUBLE_EQ(div.bad.time, div.bad.step * 0.01);
  EXPECT_LE(std::fabs(div.last_good.qpos[0]), 1e10);
  EXPECT_TRUE(std::isfinite(div.last_good.qvel[0]));
  // the last good state is the one the failing step started from, timed by its step
  EXPECT_DOUBLE_EQ(div.last_good.time, div.last_good.step * 0.01);
  EXPECT_NE(div.reason.find("diverged"), std::string::npos) << div.reason;
  EXPECT_NE(div.element.find("joint 'slider'"), std::string::npos) << div.element;
  EXPECT_TRUE(sink.ended);
  TakeMujocoWarnings();  // MuJoCo may have warned about the bad state: expected here
}

// Regression: MuJoCo's mj_checkAcc resets the data to qpos0 in the middle of the step,
// and the bad state, its time and the warning's time used to be read from the reset data.
TEST_F(RunTest, DivergenceCaughtByMujocoKeepsTheStateItFoundBad) {
  Model model = Model::FromXmlString(kStiffSpring, "stiff.xml");
  Data data(model);
  ApplyAssignments(model, data, {ParseAssignment(model, "qpos[slider]=0.01")});
  NullSink sink;
  RunResult result = plumb::Run(model, data, PendulumSpec(model, 10, 0.01), sink);
  TakeMujocoWarnings();
  ASSERT_TRUE(result.diverged);
  const Divergence& div = *result.divergence;
  ASSERT_TRUE(div.reset_by_mujoco) << div.reason;
  // MuJoCo found the accelerations at the state the step started from bad
  EXPECT_DOUBLE_EQ(div.bad.time, div.last_good.time);
  EXPECT_EQ(div.bad.qpos, div.last_good.qpos);
  EXPECT_GT(std::fabs(div.bad.qpos[0]), 1e3);  // not qpos0 = 0
  ASSERT_EQ(div.bad.qacc.size(), 1u);
  EXPECT_FALSE(std::fabs(div.bad.qacc[0]) <= 1e10) << div.bad.qacc[0];
  EXPECT_NE(div.bad.note.find("BADQACC"), std::string::npos) << div.bad.note;
  ASSERT_EQ(result.warnings.size(), 1u);
  EXPECT_EQ(result.warnings[0].kind, "BADQACC");
  EXPECT_EQ(result.warnings[0].first_step, result.steps);
  EXPECT_DOUBLE_EQ(result.warnings[0].first_time, div.last_good.time);
}

TEST_F(RunTest, AFinalTimeBeyondExactStepCountsIsRefused) {
  EXPECT_THROW(MakeSchedule(0.002, 1e17, 0.1), ValueError);
  EXPECT_THROW(MakeSchedule(0.002, 1e300, 0.1), ValueError);
  EXPECT_EQ(MakeSchedule(0.002, 1e6, 0.1).steps, 500000000L);
}

// A jointpos sensor and a free body's position, sampled after mj_step: the derived
// columns must describe the same state as qpos in the same row.
constexpr char kSensed[] = R"(
<mujoco model="sensed">
  <worldbody>
    <body name="arm" pos="0 0 1">
      <joint name="elbow" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.05" mass="1"/>
    </body>
    <body name="ball" pos="1 0 2">
      <freejoint name="root"/>
      <geom type="sphere" size="0.1" mass="1" contype="0" conaffinity="0"/>
    </body>
  </worldbody>
  <sensor><jointpos name="elbow_pos" joint="elbow"/></sensor>
</mujoco>)";

TEST_F(RunTest, DerivedColumnsDescribeTheSampledState) {
  Model model = Model::FromXmlString(kSensed, "sensed.xml");
  for (const char* integrator : {"Euler", "RK4"}) {
    Data data(model);
    ApplyAssignments(model, data,
                     {ParseAssignment(model, std::string("opt.integrator=") + integrator)});
    RunSpec spec;
    spec.until = 0.2;
    spec.every = 0.002;
    for (const char* p :
         {"time", "qpos[elbow]", "sensordata[elbow_pos]", "qpos[root][2]", "xpos[ball][2]"}) {
      spec.columns.push_back(ResolvePath(model, p));
    }
    RecordingSink sink;
    plumb::Run(model, data, spec, sink);
    ASSERT_EQ(sink.rows.size(), 101u);
    for (const std::vector<double>& row : sink.rows) {
      EXPECT_EQ(row[2], row[1]) << integrator << " t = " << row[0];
      EXPECT_EQ(row[4], row[3]) << integrator << " t = " << row[0];
    }
    EXPECT_LT(sink.rows.back()[3], 2.0 - 0.1);  // it did fall
  }
}

// mj_forward before a sample re-evaluates the state; it must not change where it goes.
TEST_F(RunTest, SamplingDerivedColumnsLeavesTheTrajectoryUnchanged) {
  Model model = Model::Load(testing::kHumanoid);
  for (const char* integrator : {"Euler", "RK4", "implicit"}) {
    std::vector<std::vector<double>> final_qpos;
    std::vector<int> contact_warnings;
    for (bool derived : {false, true}) {
      Data data(model);
      ApplyAssignments(model, data,
                       {ParseAssignment(model, std::string("opt.integrator=") + integrator)});
      RunSpec spec;
      spec.until = 0.5;
      spec.every = model.get()->opt.timestep;
      spec.columns = {ResolvePath(model, "time"), ResolvePath(model, "qpos[root][2]")};
      if (derived) spec.columns.push_back(ResolvePath(model, "xpos[torso][2]"));
      NullSink sink;
      RunResult result = plumb::Run(model, data, spec, sink);
      ASSERT_FALSE(result.diverged);
      final_qpos.emplace_back(data.get()->qpos, data.get()->qpos + model.get()->nq);
      contact_warnings.push_back(data.get()->warning[mjWARN_CONTACTFULL].number);
    }
    EXPECT_EQ(final_qpos[0], final_qpos[1]) << integrator;  // bit-identical
    EXPECT_EQ(contact_warnings[0], contact_warnings[1]) << integrator;
  }
}

TEST_F(RunTest, TheSameSpringIsStableWithASmallTimestep) {
  Model model = Model::FromXmlString(kStiffSpring, "stiff.xml");
  Data data(model);
  ApplyAssignments(
      model, data,
      {ParseAssignment(model, "opt.timestep=0.0001"), ParseAssignment(model, "qpos[slider]=0.01")});
  NullSink sink;
  RunSpec spec = PendulumSpec(model, 0.1, 0.01);
  EXPECT_FALSE(plumb::Run(model, data, spec, sink).diverged);
}

// Contacts overflow a deliberately tiny contact buffer: MuJoCo warns, the run goes on.
TEST_F(RunTest, WarningsAreSummarisedWithFirstTime) {
  Model model = Model::FromXmlString(testing::OverfullModel(), "crowded.xml");
  Data data(model);
  NullSink sink;
  RunResult result = plumb::Run(model, data, PendulumSpec(model, 0.1, 0.01), sink);
  TakeMujocoWarnings();
  EXPECT_FALSE(result.diverged);
  ASSERT_EQ(result.warnings.size(), 1u);
  EXPECT_EQ(result.warnings[0].kind, testing::kOverfullWarning);
  EXPECT_GT(result.warnings[0].count, 0);
  EXPECT_GE(result.warnings[0].first_step, 1);
  EXPECT_FALSE(result.warnings[0].message.empty());
}

TEST_F(RunTest, AStopRequestInterrupts) {
  Model model = Model::Load(kPendulum);
  Data data(model);
  StopSource stop;
  stop.RequestStop();
  RunSpec spec = PendulumSpec(model);
  spec.stop = stop.token();
  NullSink sink;
  EXPECT_THROW(plumb::Run(model, data, spec, sink), Interrupted);
}

TEST_F(RunTest, AtRestInEquilibriumGetsTheChaptersHint) {
  Model model = Model::Load(kPendulum);
  Data data(model);
  ApplyAssignments(model, data, {});
  std::vector<StartHint> hints = StartHints(model, data);
  ASSERT_EQ(hints.size(), 1u);
  EXPECT_NE(hints[0].problem.find("will not move"), std::string::npos);
  EXPECT_EQ(hints[0].assignment, "qpos[hinge]=0.7");

  ApplyAssignments(model, data, {ParseAssignment(model, "qpos[hinge]=0.7")});
  EXPECT_TRUE(StartHints(model, data).empty());
  ApplyAssignments(model, data, {ParseAssignment(model, "qvel[hinge]=1")});
  EXPECT_TRUE(StartHints(model, data).empty());
}

// The value of `path` at every sample of a run of `model` from `sets`.
std::vector<double> Sampled(Model& model, const std::string& path,
                            const std::vector<std::string>& sets = {}, double until = 0.5) {
  Data data(model);
  std::vector<Assignment> assignments;
  for (const std::string& s : sets) assignments.push_back(ParseAssignment(model, s));
  ApplyAssignments(model, data, assignments);
  RunSpec spec;
  spec.until = until;
  spec.every = 0.1;
  spec.columns = {ResolvePath(model, "time"), ResolvePath(model, path)};
  RecordingSink sink;
  plumb::Run(model, data, spec, sink);
  std::vector<double> values;
  for (const std::vector<double>& row : sink.rows) values.push_back(row[1]);
  return values;
}

// issue 9: energy read 0 on every model without <flag energy="enable"/>
TEST_F(RunTest, EnergyIsComputedWithoutTheEnergyFlag) {
  Model model = Model::Load(kPendulum);
  ASSERT_FALSE(model->opt.enableflags & mjENBL_ENERGY);
  Model flagged = model.Clone();
  flagged.get_mutable()->opt.enableflags |= mjENBL_ENERGY;
  for (const char* path : {"energy[0]", "energy[1]"}) {
    std::vector<double> computed = Sampled(model, path, {"qpos[hinge]=0.7"});
    EXPECT_EQ(computed, Sampled(flagged, path, {"qpos[hinge]=0.7"})) << path;
    EXPECT_NE(computed.back(), 0) << path;
  }
  // potential energy at the start: -m g . (com position), the mass alone on its hinge
  Data data(model);
  ApplyAssignments(model, data, {ParseAssignment(model, "qpos[hinge]=0.7")});
  double mgh = 0;
  for (int b = 1; b < model->nbody; ++b) {
    mgh -= model->body_mass[b] * mju_dot3(model->opt.gravity, data->xipos + 3 * b);
  }
  EXPECT_NEAR(Sampled(model, "energy[0]", {"qpos[hinge]=0.7"})[0], mgh, 1e-12 * std::fabs(mgh));
  EXPECT_NE(mgh, 0);
}

// A box resting on the floor, with and without an accelerometer (which makes MuJoCo
// compute cacc and cfrc_* itself).
constexpr char kRestingBox[] = R"(
<mujoco model="resting">
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1"/>
    <body name="box" pos="0 0 0.1"><freejoint/><geom type="box" size="0.1 0.1 0.1" mass="2"/>
      <site name="imu"/></body>
  </worldbody>
  SENSORS
</mujoco>)";

std::string RestingBox(bool sensor) {
  std::string xml = kRestingBox;
  xml.replace(xml.find("SENSORS"), 7,
              sensor ? "<sensor><accelerometer name=\"acc\" site=\"imu\"/></sensor>" : "");
  return xml;
}

// issue 9: cacc, cfrc_int and cfrc_ext read 0 on every sample: MuJoCo computes them only
// in mj_rnePostConstraint, which mj_forward calls for acceleration and force sensors
TEST_F(RunTest, ComAccelerationsAndForcesAreComputedOnDemand) {
  Model plain = Model::FromXmlString(RestingBox(false), "resting.xml");
  Model sensed = Model::FromXmlString(RestingBox(true), "resting_sensed.xml");
  for (const char* path : {"cacc[box][5]", "cfrc_ext[box][5]", "cfrc_int[box][5]"}) {
    EXPECT_EQ(Sampled(plain, path), Sampled(sensed, path)) << path;
  }
  // at rest on the floor: the contact carries the weight, the com accelerates at -g
  // against the free-falling frame MuJoCo uses (what an accelerometer reads)
  double weight = 2 * 9.81;
  EXPECT_NEAR(Sampled(plain, "cfrc_ext[box][5]").back(), weight, 1e-3 * weight);
  EXPECT_NEAR(Sampled(plain, "cacc[box][5]").back(), 9.81, 1e-3 * 9.81);
}

// sampling the on-demand quantities must not change where the model goes
TEST_F(RunTest, SamplingEnergyAndComForcesLeavesTheTrajectoryUnchanged) {
  Model model = Model::Load(testing::kHumanoid);
  std::vector<std::vector<double>> final_qpos;
  for (bool derived : {false, true}) {
    Data data(model);
    ApplyAssignments(model, data, {});
    RunSpec spec;
    spec.until = 0.3;
    spec.every = model->opt.timestep;
    spec.columns = {ResolvePath(model, "time")};
    if (derived) {
      for (const char* p :
           {"energy[0]", "cfrc_ext[torso][5]", "cacc[torso][5]", "subtree_linvel[torso][2]"}) {
        spec.columns.push_back(ResolvePath(model, p));
      }
    }
    NullSink sink;
    ASSERT_FALSE(plumb::Run(model, data, spec, sink).diverged);
    final_qpos.emplace_back(data->qpos, data->qpos + model->nq);
  }
  EXPECT_EQ(final_qpos[0], final_qpos[1]);  // bit-identical
}

// issue 9: on cartpole the hint suggested the slider, which leaves the pole balanced, so
// following it printed the same hint again
constexpr char kCartpole[] = R"(
<mujoco model="cartpole">
  <worldbody>
    <body name="cart">
      <joint name="slider" type="slide" axis="1 0 0" limited="true" range="-1.8 1.8"/>
      <geom type="box" size="0.2 0.15 0.1" mass="1"/>
      <body name="pole">
        <joint name="hinge_1" type="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0 0 1" size="0.045" mass="0.1"/>
      </body>
    </body>
  </worldbody>
  <actuator><motor name="slide" joint="slider" gear="10" ctrlrange="-1 1" ctrllimited="true"/></actuator>
</mujoco>)";

TEST_F(RunTest, EquilibriumHintSuggestsACoordinateThatMoves) {
  Model model = Model::FromXmlString(kCartpole, "cartpole.xml");
  for (const char* start : {"qpos[slider]=0", "qpos[slider]=0.7"}) {
    Data data(model);
    ApplyAssignments(model, data, {ParseAssignment(model, start)});
    std::vector<StartHint> hints = StartHints(model, data);
    ASSERT_EQ(hints.size(), 1u) << start;
    std::string advice = hints[0].assignment;
    EXPECT_EQ(advice.find("qpos[slider]"), std::string::npos) << advice;
    EXPECT_EQ(advice.rfind("qpos[hinge_1]=", 0), 0u) << advice;
    // following it: no hint, and the model moves
    ApplyAssignments(model, data, {ParseAssignment(model, start), ParseAssignment(model, advice)});
    EXPECT_TRUE(StartHints(model, data).empty()) << advice;
    std::vector<double> pole = Sampled(model, "qpos[hinge_1]", {start, advice});
    EXPECT_NE(pole.front(), pole.back());
  }
}

// with nothing that pulls (no gravity), no offset breaks the equilibrium: a velocity does
TEST_F(RunTest, WeightlessEquilibriumHintSuggestsAVelocity) {
  Model model = Model::FromXmlString(kCartpole, "cartpole.xml");
  Data data(model);
  ApplyAssignments(model, data, {ParseAssignment(model, "opt.gravity=0,0,0")});
  std::vector<StartHint> hints = StartHints(model, data);
  ASSERT_EQ(hints.size(), 1u);
  EXPECT_EQ(hints[0].assignment, "qvel[slider]=1");
}

TEST_F(RunTest, RunsAreBitIdentical) {
  Model model = Model::Load(testing::kHumanoid);
  std::vector<std::vector<double>> first;
  for (int repeat = 0; repeat < 2; ++repeat) {
    Data data(model);
    ApplyAssignments(model, data, {});
    RecordingSink sink;
    RunSpec spec = PendulumSpec(model, 0.5, 0.05);
    plumb::Run(model, data, spec, sink);
    if (repeat == 0)
      first = sink.rows;
    else
      EXPECT_EQ(first, sink.rows);
  }
}

TEST_F(RunTest, ARunStopsOnItsOwnRequestAndNoOther) {
  // one caller's request does not stop another caller's run (a notebook stopping one call
  // while another thread's goes on); a default token never stops
  Model model = Model::Load(testing::kPendulum);
  Data data(model);
  RunSpec spec;
  spec.until = 1;
  NullSink sink;
  StopSource mine, theirs;
  mine.RequestStop();
  spec.stop = mine.token();
  EXPECT_THROW(plumb::Run(model, data, spec, sink), Interrupted);
  Data other(model);
  spec.stop = theirs.token();
  EXPECT_NO_THROW(plumb::Run(model, other, spec, sink));
  spec.stop = StopToken();
  EXPECT_NO_THROW(plumb::Run(model, other, spec, sink));
  mine.Clear();  // withdrawn: the caller goes on
  spec.stop = mine.token();
  EXPECT_NO_THROW(plumb::Run(model, data, spec, sink));
}

}  // namespace
}  // namespace plumb
