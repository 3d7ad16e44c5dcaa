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

std::string Mpirun(int ranks, const std::string& args, const std::string& dir = ".") {
  // CI runs as root, and this machine has fewer cores than ranks
  testing::CommandResult r = RunShell("mpirun --allow-run-as-root --oversubscribe -np " +
                                          std::to_string(ranks) + " '" + PLUMB_CLI + "' " + args,
                                      dir);
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

}  // namespace
}  // namespace plumb
