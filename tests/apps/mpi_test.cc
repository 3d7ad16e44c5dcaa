// mpirun -np 2 (and 3) plumb rollout equals the single-process run, rows and store.

#include <gtest/gtest.h>

#include "fixture.h"

namespace plumb {
namespace {

using testing::RunPlumb;
using testing::RunShell;
using testing::TempDir;

const std::string kArgs =
    " --count 70 --until 0.3 --seed 9 --randomize 'body_mass[*]=*U(0.9,1.1)' "
    "--ctrl-noise 0.01 --metric 'xpos[torso][2]@0.3' --format csv";

testing::CommandResult MpirunResult(int ranks, const std::string& args,
                                    const std::string& dir = ".") {
  // CI runs as root, and this machine has fewer cores than ranks; `timeout` turns a hang
  // into a failure (exit 124) instead of a stuck test
  return RunShell("timeout 60 mpirun --allow-run-as-root --oversubscribe -np " +
                      std::to_string(ranks) + " '" + PLUMB_CLI + "' " + args,
                  dir);
}

std::string Mpirun(int ranks, const std::string& args, const std::string& dir = ".") {
  testing::CommandResult r = MpirunResult(ranks, args, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return r.out;
}

TEST(MpiTest, RanksGiveTheSameRowsAsOneProcess) {
  std::string single = RunPlumb("rollout " + testing::kHumanoid + kArgs).out;
  ASSERT_EQ(std::count(single.begin(), single.end(), '\n'), 71);
  EXPECT_EQ(Mpirun(2, "rollout " + testing::kHumanoid + kArgs), single);
  EXPECT_EQ(Mpirun(3, "rollout " + testing::kHumanoid + kArgs + " --threads 1"), single);
}

TEST(MpiTest, RankZeroWritesTheStore) {
  TempDir dir;
  Mpirun(2, "rollout " + testing::kHumanoid + kArgs + " --db mpi.sqlite", dir.path());
  RunPlumb("rollout " + testing::kHumanoid + kArgs + " --db one.sqlite", dir.path());
  std::string a = RunPlumb("results mpi.sqlite", dir.path()).out;
  std::string b = RunPlumb("results one.sqlite", dir.path()).out;
  EXPECT_EQ(std::count(a.begin(), a.end(), '\n'), 71);
  EXPECT_EQ(a, b);
}

TEST(MpiTest, AnErrorOnRankZeroEndsEveryRank) {
  // the store already holds this run: only rank 0 opens it, and the workers that wait for
  // its go-ahead must end too, promptly, with the same exit code
  TempDir dir;
  RunPlumb("rollout " + testing::kHumanoid + kArgs + " --db taken.sqlite", dir.path());
  testing::CommandResult r =
      MpirunResult(2, "rollout " + testing::kHumanoid + kArgs + " --db taken.sqlite", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("already holds this run"), std::string::npos) << r.err;
  // and an error every rank sees (a bad option value) ends them all the same way
  testing::CommandResult bad =
      MpirunResult(2, "rollout " + testing::kHumanoid + " --randomize 'body_mass[*]=W(1,2)'");
  EXPECT_EQ(bad.exit_code, 2) << bad.err;
}

}  // namespace
}  // namespace plumb
