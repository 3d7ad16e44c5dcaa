// Every exit code in docs/exit-codes.md's table, each from the situation it names (130 and 141 are in
// signals_cli_test.cc: they need a signal or a closed pipe).

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <string>

#include "fixture.h"
#include "plumb/model.h"

namespace plumb {
namespace {

using testing::RunPlumb;
using testing::TempDir;
using testing::WriteFile;

TEST(ExitCodesTest, SuccessIsZero) {
  testing::CommandResult r = RunPlumb("verify " + testing::kPendulum + " --set 'qpos[hinge]=0.7'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST(ExitCodesTest, AFailedCheckIsOne) {
  // negative damping adds energy: verify's energy check fails
  testing::CommandResult r = RunPlumb("verify " + testing::kPendulum +
                                      " --set 'qpos[hinge]=0.7' --set 'dof_damping[hinge]=-0.05'");
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
}

TEST(ExitCodesTest, BadInputIsTwo) {
  testing::CommandResult r = RunPlumb("run " + testing::kPendulum + " --set 'qpos[nowhere]=1'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("plumb: error:"), std::string::npos) << r.err;
}

TEST(ExitCodesTest, ADivergedRunIsThree) {
  TempDir dir;
  WriteFile(dir.File("stiff.xml"), R"(<mujoco><option timestep="0.01" gravity="0 0 0"/><worldbody>
      <body><joint name="spring" type="slide" axis="1 0 0" stiffness="1e6" ref="0.01"/>
      <geom type="sphere" size="0.05" mass="1"/></body></worldbody></mujoco>)");
  testing::CommandResult r = RunPlumb("run stiff.xml --until 2", dir.path());
  EXPECT_EQ(r.exit_code, 3) << r.err;
}

// A fatal MuJoCo error during a run (the arena too small for the implicit integrator's
// derivatives) is its own code, not "diverged".
TEST(ExitCodesTest, AFatalMujocoErrorIsFour) {
  if (MujocoVersion().rfind("2.", 0) == 0) GTEST_SKIP() << "MuJoCo 2.x has no <size memory>";
  TempDir dir;
  WriteFile(dir.File("small.xml"), R"(<mujoco><size memory="2K"/><worldbody>
      <geom type="plane" size="5 5 .1"/>
      <body pos="0 0 1"><freejoint/><geom type="box" size=".1 .1 .1"/></body>
      <body pos="0 0 1.5"><freejoint/><geom type="box" size=".1 .1 .1"/></body>
      </worldbody></mujoco>)");
  testing::CommandResult r =
      RunPlumb("run small.xml --set opt.integrator=implicit --until 1", dir.path());
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_NE(r.err.find("MuJoCo stopped with a fatal error"), std::string::npos) << r.err;
}

// A store row edited or damaged on disk is bad input named to the row and column (it was an
// internal error, exit 70, until fuzz_store showed that other edits crashed the reader).
// A build without CycloneDDS (PLUMB_WITH_DDS=OFF; the TSan leg is one): the bridge is an
// optional part that says what to install, as the renderer does, and the exit code is 5.
TEST(ExitCodesTest, AMissingBridgeIsFive) {
  if (PLUMB_TEST_BRIDGE_BUILT) GTEST_SKIP() << "this build has the DDS bridge";
  testing::TempDir dir;
  testing::WriteFile(dir.File("b.toml"), "motors = [\"hinge\"]\n");
  testing::CommandResult r =
      RunPlumb("bridge " + testing::kPendulum + " --config b.toml --until 0.01", dir.path());
  EXPECT_EQ(r.exit_code, 5) << r.err;
  EXPECT_NE(r.err.find("built without the DDS bridge"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("apt-get install cyclonedds-dev cyclonedds-tools"), std::string::npos)
      << r.err;
}

TEST(ExitCodesTest, ADamagedStoreRowIsExit2NamingTheStoreRowAndColumn) {
  TempDir dir;
  testing::CommandResult made =
      RunPlumb("rollout " + testing::kPendulum +
                   " --count 3 --until 0.2 --randomize 'dof_damping[hinge]=U(0,0.1)' "
                   "--metric 'qpos[hinge]@0.2' --db r.sqlite --format csv",
               dir.path());
  ASSERT_EQ(made.exit_code, 0) << made.err;
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(dir.File("r.sqlite").c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, "UPDATE results SET metrics = '[1, oops' WHERE idx = 1;", nullptr,
                         nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  testing::CommandResult r = RunPlumb("results r.sqlite --format csv", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("plumb: error: results store 'r.sqlite': run 1 case 1 column 'metrics' "
                       "is not a JSON array (not JSON)"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.out, "") << "a half-printed table";
}

}  // namespace
}  // namespace plumb
