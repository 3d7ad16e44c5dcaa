// The numbers the command line prints must be the ones asked for: no path reads as 0
// because MuJoCo skipped computing it, no value is silently changed (issue 9).

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "fixture.h"

namespace plumb {
namespace {

using testing::CommandResult;
using testing::kPendulum;
using testing::RunPlumb;
using testing::CsvColumn;
using testing::TempDir;
using testing::WriteFile;

const std::string kCartpole = testing::kSuite + "/cartpole.xml";


TEST(ValuesCliTest, EnergyColumnsAreComputedWithoutTheEnergyFlag) {
  CommandResult r = RunPlumb("run " + kPendulum +
                             " --set 'qpos[hinge]=0.7' --columns 'time,energy' --until 0.5 "
                             "--format csv");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::vector<double> potential = CsvColumn(r.out, 1), kinetic = CsvColumn(r.out, 2);
  ASSERT_EQ(potential.size(), 6u);
  // 1 kg, com 0.5 m below the hinge at 1.5 m, tilted 0.7 rad: m g h about z = 0
  EXPECT_NEAR(potential[0], 9.81 * (1.5 - 0.5 * std::cos(0.7)), 1e-3);
  EXPECT_EQ(kinetic[0], 0);
  EXPECT_GT(kinetic.back(), 0.5);
}

TEST(ValuesCliTest, SweepOnEnergyIsNotZeroWithoutTheFlag) {
  CommandResult r = RunPlumb("sweep " + kPendulum +
                             " --vary 'qpos[hinge]=0.2:0.4:2' --metric 'energy[0]@0.1' "
                             "--format csv");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (double v : CsvColumn(r.out, 2)) EXPECT_GT(v, 5) << r.out;  // m g h, about 10 J
}

TEST(ValuesCliTest, EfcForceBeyondNefcIsRefused) {
  TempDir dir;
  WriteFile(dir.File("box.xml"), R"(<mujoco><worldbody>
      <geom name="floor" type="plane" size="5 5 0.1"/>
      <body name="box" pos="0 0 0.1"><freejoint/><geom type="box" size="0.1 0.1 0.1"/></body>
    </worldbody></mujoco>)");
  CommandResult r = RunPlumb("run box.xml --columns 'time,efc_force[200]' --until 0.1", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_NE(r.err.find("efc_force[200]"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("nefc = "), std::string::npos) << r.err;
}

TEST(ValuesCliTest, SettingAFreeJointBlockNeedsAllSevenValues) {
  CommandResult r = RunPlumb("run " + testing::kHumanoid + " --set 'qpos[root]=1' --until 0");
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_NE(r.err.find("a block of 7 values"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("qpos[root][0]="), std::string::npos) << r.err;
  CommandResult z = RunPlumb("run " + testing::kHumanoid +
                             " --set 'qpos[root][2]=2' --columns 'qpos[root]' --until 0 "
                             "--format csv");
  ASSERT_EQ(z.exit_code, 0) << z.err;
  EXPECT_EQ(CsvColumn(z.out, 2)[0], 2);
  EXPECT_EQ(CsvColumn(z.out, 3)[0], 1);  // the quaternion kept its w
}

TEST(ValuesCliTest, CtrlBeyondCtrlrangeWarns) {
  if (!std::filesystem::exists(kCartpole)) GTEST_SKIP() << "no dm_control models";
  CommandResult r = RunPlumb("run " + kCartpole + " --set 'ctrl[slide]=5' --until 0.1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("plumb: warning: --set 'ctrl[slide]=5': 5 is outside the ctrlrange "
                       "[-1, 1] of actuator 'slide'"),
            std::string::npos)
      << r.err;
  CommandResult inside = RunPlumb("run " + kCartpole + " --set 'ctrl[slide]=0.5' --until 0.1");
  EXPECT_EQ(inside.err.find("warning"), std::string::npos) << inside.err;
}

// the hint on dm_control's cartpole suggested the slider; following it printed it again
TEST(ValuesCliTest, CartpoleHintIsFollowedByMotion) {
  if (!std::filesystem::exists(kCartpole)) GTEST_SKIP() << "no dm_control models";
  CommandResult r = RunPlumb("run " + kCartpole + " --until 0.1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::size_t at = r.err.find("--set '");
  ASSERT_NE(at, std::string::npos) << r.err;
  std::string advice = r.err.substr(at + 7, r.err.find('\'', at + 7) - at - 7);
  EXPECT_EQ(advice.rfind("qpos[hinge_1]=", 0), 0u) << r.err;
  for (const std::string& start : {std::string(), std::string(" --set 'qpos[slider]=0.7'")}) {
    CommandResult followed = RunPlumb("run " + kCartpole + start + " --set '" + advice +
                                      "' --columns 'time,qpos[hinge_1]' --until 1 --format csv");
    ASSERT_EQ(followed.exit_code, 0) << followed.err;
    EXPECT_EQ(followed.err.find("hint"), std::string::npos) << followed.err;
    std::vector<double> pole = CsvColumn(followed.out, 1);
    EXPECT_GT(std::fabs(pole.back() - pole.front()), 0.1) << followed.out;
  }
}

// *U() on a body's mass kept its inertia; scaled together, a pendulum's period cannot
// change (I and m g d both scale with the mass)
TEST(ValuesCliTest, RandomizedMassKeepsTheShapeSoThePeriodStays) {
  TempDir dir;
  WriteFile(dir.File("swing.xml"), R"(<mujoco><option timestep="0.002"/><worldbody>
      <body name="link" pos="0 0 1.5"><joint name="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0 0 -1" size="0.05" mass="1"/></body>
    </worldbody></mujoco>)");
  CommandResult r = RunPlumb(
      "rollout swing.xml --count 4 --until 6 --set 'qpos[hinge]=0.5' "
      "--randomize 'body_mass[link]=*U(0.2,5)' --metric 'period(qpos[hinge])' --format csv",
      dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string header = r.out.substr(0, r.out.find('\n'));
  std::istringstream cells(header);
  std::string cell;
  int period = -1, mass = -1;
  for (int c = 0; std::getline(cells, cell, ','); ++c) {
    if (cell.find("period") != std::string::npos) period = c;
    if (cell.find("body_mass") != std::string::npos) mass = c;
  }
  ASSERT_GE(period, 0) << header;
  ASSERT_GE(mass, 0) << header;
  std::vector<double> periods = CsvColumn(r.out, period), masses = CsvColumn(r.out, mass);
  ASSERT_EQ(periods.size(), 4u);
  for (std::size_t i = 1; i < periods.size(); ++i) {
    EXPECT_NE(masses[i], masses[0]);
    EXPECT_NEAR(periods[i], periods[0], 1e-9 * periods[0]) << r.out;
  }
}

// issue 46: CLI11 reads "nan" as a number, and NaN passes every `x < 0` check: --ctrl-noise
// nan ran as no noise, --max-seconds nan and sweep --until nan ran. Every floating-point option
// of every command, read from its --help, refuses it naming the option.
TEST(ValuesCliTest, EveryNumericOptionRefusesNaN) {
  TempDir dir;
  int tried = 0;
  for (const char* command :
       {"run", "rollout", "sweep", "verify", "converge", "audit", "crosscheck", "render", "bridge",
        "replay", "identify", "snapshot", "diff", "inspect", "merge", "results"}) {
    CommandResult help = RunPlumb(std::string(command) + " --help");
    ASSERT_EQ(help.exit_code, 0) << command << ": " << help.err;
    std::istringstream lines(help.out);
    for (std::string line; std::getline(lines, line);) {
      std::size_t at = line.find("--"), type = line.find(" FLOAT");
      if (at == std::string::npos || type == std::string::npos || type < at) continue;
      std::string flag = line.substr(at, type - at);
      if (flag.find(' ') != std::string::npos) continue;  // not an option's own line
      ++tried;
      CommandResult r =
          RunPlumb(std::string(command) + " '" + kPendulum + "' " + flag + " nan", dir.path());
      EXPECT_EQ(r.exit_code, 2) << command << " " << flag << " nan: " << r.err;
      EXPECT_NE(r.err.find(flag), std::string::npos) << command << " " << flag << ": " << r.err;
    }
  }
  EXPECT_GE(tried, 25);  // the help was read: --until, --every, --tol, --ctrl-noise, ...
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

// issue 46: one rule turns a time into steps: a time beyond 2^53 steps is refused naming the
// option the user typed (render --at 1e17 said "--until -1.84467e+16"; crosscheck blamed the
// engine adapter with exit 6; verify suggested its own input, "Use 1e+30")
TEST(ValuesCliTest, ATimeBeyondCountableStepsIsRefusedByItsOwnName) {
  TempDir dir;
  const std::string m = " '" + kPendulum + "' ";
  struct Case {
    std::string args, flag;
  } cases[] = {
      {"run" + m + "--until 1e17", "--until 1e+17"},
      {"rollout" + m + "--count 2 --until 1e17", "--until 1e+17"},
      {"sweep" + m + "--vary 'qpos[hinge]=0.1,0.2' --metric 'maxabs(qpos[hinge])' --until 1e17",
       "--until 1e+17"},
      {"converge" + m + "--metric 'maxabs(qpos[hinge])' --until 1e17", "--until 1e+17"},
      {"verify" + m + "--until 1e30", "--until 1e+30"},
      {"crosscheck" + m + "--until 1e17", "--until 1e+17"},
      {"render" + m + "--at 1e17 -o p.png", "--at 1e+17"},
      {"render" + m + "--until 1e17 -o v.mp4", "--until 1e+17"},
  };
  for (const Case& c : cases) {
    CommandResult r = RunPlumb(c.args, dir.path());
    if (r.exit_code == 5 && c.args.rfind("render", 0) == 0) continue;  // no renderer here
    EXPECT_EQ(r.exit_code, 2) << c.args << ": " << r.err;
    EXPECT_EQ(r.err.rfind("plumb: error: " + c.flag + ":", 0), 0u) << c.args << ": " << r.err;
    EXPECT_NE(r.err.find("up to 2^53"), std::string::npos) << c.args << ": " << r.err;
    EXPECT_EQ(r.err.find("Use 1e"), std::string::npos) << c.args << ": " << r.err;
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

// issue 46: --until -1 ran the bridge for no steps and exit 0, while until = -1 in its file is
// exit 2: the same rule for both
TEST(ValuesCliTest, TheBridgeRefusesANegativeUntilAsItsFileDoes) {
  TempDir dir;
  WriteFile(dir.File("bridge.toml"), "until = -1\n");
  CommandResult file =
      RunPlumb("bridge '" + testing::kSourceDir + "/tests/models/arm2.xml' --config bridge.toml",
               dir.path());
  EXPECT_EQ(file.exit_code, 2) << file.err;
  CommandResult r =
      RunPlumb("bridge '" + testing::kSourceDir + "/tests/models/arm2.xml' --until -1", dir.path());
  if (r.exit_code == 5) GTEST_SKIP() << "no DDS bridge in this build: " << r.err;
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--until -1: must be in [0, inf]"), std::string::npos) << r.err;
}

// issue 46: every index of --count was listed before the first rollout: --count 2^53 ran out of
// memory, or sat deaf to --max-seconds and SIGTERM. The count is counted, not listed.
TEST(ValuesCliTest, AHugeCountStartsAtOnceAndKeepsItsBudget) {
  CommandResult r = testing::RunShell(std::string("timeout -s KILL 60 '") + PLUMB_CLI +
                                      "' rollout '" + kPendulum +
                                      "' --count 9007199254740992 --until 0.002 --max-seconds 1 "
                                      "--format csv >/dev/null");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("--max-seconds 1 spent"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace plumb
