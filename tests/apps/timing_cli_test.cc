// One timing rule for every command (the timestep a run uses, whole numbers of steps),
// the default sampling, verify's run length, audit's repro folders and --keyframe.

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "fixture.h"
#include "keyed_model.h"

namespace plumb {
namespace {

using testing::CommandResult;
using testing::CsvRow;
using testing::kPendulum;
using testing::ReadFile;
using testing::RunPlumb;
using testing::RunShell;
using testing::TempDir;
using testing::WriteFile;

// dm_control's lqr.xml uses this timestep, which 0.1 s is not a whole number of.
constexpr char kCoarse[] = R"(
<mujoco model="coarse">
  <option timestep="0.03"/>
  <worldbody>
    <body name="link">
      <joint name="hinge" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.02" mass="1"/>
    </body>
  </worldbody>
</mujoco>)";

// Semi-implicit Euler is unstable once omega * dt > 2; here omega * dt = 2.01, so gravity's
// small push grows by about 1.2 per step and the run diverges after a hundred steps or
// so: past audit's first settle piece (50 steps).
constexpr char kSlowlyUnstable[] = R"(
<mujoco model="unstable">
  <option timestep="0.01"/>
  <worldbody>
    <body name="mass">
      <joint name="slider" type="slide" axis="0 0 1" stiffness="40401"/>
      <geom type="sphere" size="0.05" mass="1" contype="0" conaffinity="0"/>
    </body>
  </worldbody>
</mujoco>)";


TEST(TimingCliTest, EveryIsCheckedAgainstTheTimestepSet) {
  CommandResult r = RunPlumb("run " + kPendulum +
                             " --set opt.timestep=0.001 --every 0.001 --until 0.002 --format csv");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 4) << r.out;  // header + 3 samples
}

TEST(TimingCliTest, DefaultSamplingAdaptsToTheTimestep) {
  TempDir dir;
  WriteFile(dir.File("coarse.xml"), kCoarse);
  CommandResult r = RunPlumb("run coarse.xml --until 0.3 --format csv", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // 3 steps of 0.03 s, the whole number of steps nearest to 0.1 s
  ASSERT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 5) << r.out;  // t = 0 ... 0.27
  EXPECT_NEAR(CsvRow(r.out, 2)[0], 0.09, 1e-12) << r.out;
  EXPECT_NE(r.err.find("sampling every 0.09 s"), std::string::npos) << r.err;
  // an explicit --every keeps the strict check
  r = RunPlumb("run coarse.xml --every 0.1", dir.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("not a whole number of timesteps of 0.03 s"), std::string::npos) << r.err;
}

TEST(TimingCliTest, DefaultSamplingOfLqrRuns) {
  std::string lqr = testing::kSuite + "/lqr.xml";
  if (!std::ifstream(lqr)) GTEST_SKIP() << "no dm_control suite at " << lqr;
  CommandResult r = RunPlumb("run '" + lqr + "' --until 0.3");
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST(TimingCliTest, RolloutRefusesARandomTimestepWithAMetricAtAFixedTime) {
  // sweep refuses a timestep that does not divide the metric's time; so must rollout
  CommandResult r = RunPlumb("rollout " + kPendulum +
                             " --randomize 'opt.timestep=U(0.001,0.003)' --metric "
                             "'qpos[hinge]@1' --count 2");
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_NE(r.err.find("opt.timestep=U(0.001,0.003)"), std::string::npos) << r.err;
}

TEST(TimingCliTest, SweepAndRolloutRefuseTheSameTimeWithTheSameWords) {
  std::string wording = "0.1 s is not a whole number of timesteps of 0.003 s";
  CommandResult sweep = RunPlumb("sweep " + kPendulum +
                                 " --set opt.timestep=0.003 --vary 'dof_damping[hinge]=0,0.1' "
                                 "--metric 'qpos[hinge]@0.1'");
  EXPECT_EQ(sweep.exit_code, 2);
  EXPECT_NE(sweep.err.find(wording), std::string::npos) << sweep.err;
  CommandResult rollout = RunPlumb("rollout " + kPendulum +
                                   " --set opt.timestep=0.003 --metric 'qpos[hinge]@0.1' "
                                   "--count 2");
  EXPECT_EQ(rollout.exit_code, 2);
  EXPECT_NE(rollout.err.find(wording), std::string::npos) << rollout.err;
}

TEST(TimingCliTest, VerifyRefusesARunOfZeroSteps) {
  CommandResult r = RunPlumb("verify " + kPendulum + " --set 'qpos[hinge]=0.7' --until 0");
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_EQ(r.out.find("PASS  determinism"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("--until 0"), std::string::npos) << r.err;
}

TEST(TimingCliTest, AuditReproStepAgreesWithTimeAndItsCommandRunsAsWritten) {
  TempDir dir;
  WriteFile(dir.File("unstable.xml"), kSlowlyUnstable);
  CommandResult r = RunPlumb("audit unstable.xml --repro rep", dir.path());
  ASSERT_EQ(r.exit_code, 1) << r.out << r.err;
  for (const char* file : {"rep/bad.json", "rep/last_good.json"}) {
    auto state = nlohmann::json::parse(ReadFile(dir.File(file)));
    long step = state["step"];
    double time = state["time"];
    EXPECT_GT(step, 50) << file;  // past the first piece of the settle run
    EXPECT_NEAR(time, step * 0.01, 1e-9) << file;
  }
  // the command line is the last line and runs with sh as written, comments and all
  std::string command = ReadFile(dir.File("rep/command.txt"));
  ASSERT_FALSE(command.empty());
  std::string last = command.substr(command.rfind('\n', command.size() - 2) + 1);
  EXPECT_EQ(last.find('#'), std::string::npos) << command;
  CommandResult again = RunShell("sh rep/command.txt", dir.path());
  EXPECT_EQ(again.exit_code, r.exit_code) << again.err;
  EXPECT_EQ(ReadFile(dir.File("rep-2/bad.json")), ReadFile(dir.File("rep/bad.json")));
}

TEST(KeyframeCliTest, RunStartsFromTheKeyframeWithSetOnTop) {
  TempDir dir;
  WriteFile(dir.File("keyed.xml"), testing::kKeyed);
  CommandResult r = RunPlumb(
      "run keyed.xml --keyframe home --set 'qvel[slider]=0' --until 0 --format csv "
      "--columns 'time,qpos[slider],qvel[slider],ctrl[push],mocap_pos[0][0]'",
      dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // time, qpos, ctrl and mocap from the keyframe; qvel from --set, applied after it
  std::vector<double> row = CsvRow(r.out, 1);
  std::vector<double> expected = {1, 0.5, 0, 0.3, 2};
  ASSERT_EQ(row.size(), expected.size()) << r.out;
  for (std::size_t i = 0; i < row.size(); ++i) EXPECT_NEAR(row[i], expected[i], 1e-12) << r.out;
}

TEST(KeyframeCliTest, UnknownKeyframeListsTheModelsKeyframes) {
  TempDir dir;
  WriteFile(dir.File("keyed.xml"), testing::kKeyed);
  CommandResult r = RunPlumb("run keyed.xml --keyframe hom", dir.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("home, away"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("did you mean: home"), std::string::npos) << r.err;
  r = RunPlumb("run " + kPendulum + " --keyframe home");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("no keyframes"), std::string::npos) << r.err;
}

TEST(KeyframeCliTest, EveryCommandStartsFromTheKeyframe) {
  TempDir dir;
  WriteFile(dir.File("keyed.xml"), testing::kKeyed);
  // the keyframe's qpos is -0.5 and nothing moves it: every command must see it
  CommandResult sweep = RunPlumb(
      "sweep keyed.xml --keyframe away --vary 'dof_damping[slider]=0,1' "
      "--metric 'qpos[slider]@0.1' --format csv",
      dir.path());
  ASSERT_EQ(sweep.exit_code, 0) << sweep.err;
  EXPECT_NE(sweep.out.find(",-0.5"), std::string::npos) << sweep.out;
  CommandResult rollout = RunPlumb(
      "rollout keyed.xml --keyframe away --randomize 'dof_damping[slider]=U(0,1)' "
      "--metric 'qpos[slider]@0.1' --count 1 --format csv",
      dir.path());
  ASSERT_EQ(rollout.exit_code, 0) << rollout.err;
  EXPECT_NE(rollout.out.find(",-0.5,"), std::string::npos) << rollout.out;
  CommandResult converge = RunPlumb(
      "converge keyed.xml --keyframe away --metric 'qpos[slider]@0.1' --format json", dir.path());
  ASSERT_EQ(converge.exit_code, 0) << converge.err;
  EXPECT_NEAR(nlohmann::json::parse(converge.out)["levels"][0]["value"].get<double>(), -0.5, 1e-12);
  CommandResult verify =
      RunPlumb("verify keyed.xml --keyframe home --format json --until 0.02", dir.path());
  EXPECT_NE(verify.exit_code, 2) << verify.err;
  CommandResult audit = RunPlumb("audit keyed.xml --keyframe away --format json", dir.path());
  EXPECT_NE(audit.exit_code, 2) << audit.err;
  EXPECT_EQ(RunPlumb("audit keyed.xml --keyframe nope", dir.path()).exit_code, 2);
}

}  // namespace
}  // namespace plumb
