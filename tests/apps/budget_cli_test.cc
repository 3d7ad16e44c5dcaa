// Cost before it is spent: the estimate a long plumb run prints; run's --max-seconds and
// --max-rows, and sweep's and rollout's --max-seconds, which stop cleanly and keep every row
// that finished.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "fixture.h"

namespace plumb {
namespace {

using testing::CommandResult;
using testing::kPendulum;
using testing::ReadFile;
using testing::RunPlumb;
using testing::TempDir;

const std::string kRun =
    "run " + kPendulum + " --set 'qpos[hinge]=0.7' --format csv --every 0.002 ";

// `count` pendulum rollouts of 5 steps each, one metric.
std::string Rollouts(long count) {
  return "rollout " + kPendulum + " --count " + std::to_string(count) +
         " --until 0.01 --set 'qpos[hinge]=0.7' --randomize 'dof_damping[hinge]=U(0,0.1)' "
         "--metric 'qpos[hinge]@0.01' --format csv";
}

long Lines(const std::string& text) { return std::count(text.begin(), text.end(), '\n'); }

TEST(BudgetCliTest, MaxRowsKeepsExactlyThoseRowsAndExits0) {
  TempDir dir;
  CommandResult r = RunPlumb(kRun + "--until 100 --max-rows 5 -o out.csv", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string csv = ReadFile(dir.File("out.csv"));
  EXPECT_EQ(Lines(csv), 6) << csv;  // the header and five rows
  EXPECT_EQ(csv.back(), '\n');
  EXPECT_NE(csv.find("\n0.008,"), std::string::npos) << csv;
  EXPECT_NE(r.err.find("--max-rows 5 spent: stopped at t = 0.008 s (step 4 of 50000) with 5 rows"),
            std::string::npos)
      << r.err;
  // the same rows as the run without a budget
  CommandResult full = RunPlumb(kRun + "--until 0.008", dir.path());
  EXPECT_EQ(csv, full.out);
}

TEST(BudgetCliTest, MaxSecondsStopsALongRunWithWholeRowsAndSaysSo) {
  TempDir dir;
  // 10^8 steps: about a minute of work; the estimate is printed, the budget ends it early
  CommandResult r = RunPlumb(kRun + "--until 200000 --max-seconds 0.5 -o out.csv", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("plumb: this run: 100000000 steps and 100000001 rows: about"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("--max-seconds 0.5 spent: stopped at t = "), std::string::npos) << r.err;
  std::string csv = ReadFile(dir.File("out.csv"));
  ASSERT_GT(Lines(csv), 100);
  EXPECT_EQ(csv.back(), '\n');  // no torn last row
  std::string last = csv.substr(csv.rfind('\n', csv.size() - 2) + 1);
  EXPECT_EQ(std::count(last.begin(), last.end(), ','), 2) << last;
}

TEST(BudgetCliTest, BadBudgetsAreRefusedNamingTheOption) {
  for (const char* bad : {"--max-rows 0", "--max-rows -3", "--max-seconds 0", "--max-seconds x"}) {
    TempDir dir;
    CommandResult r = RunPlumb(kRun + "--until 1 -o out.csv " + bad, dir.path());
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.err.find(std::string(bad).substr(0, std::string(bad).find(' '))), std::string::npos)
        << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir.File("out.csv"))) << bad;
  }
}

TEST(BudgetCliTest, RolloutMaxSecondsKeepsWhatFinishedStoredAndResumable) {
  TempDir dir;
  // two million rollouts: far more than 0.3 s holds in any build
  std::string args = Rollouts(2000000) + " --db r.sqlite";
  CommandResult r = RunPlumb(args + " --max-seconds 0.3", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  long printed = Lines(r.out) - 1;
  EXPECT_GT(printed, 0);
  EXPECT_LT(printed, 2000000);
  EXPECT_NE(r.err.find("plumb: --max-seconds 0.3 spent: " + std::to_string(printed) +
                       " rollouts finished and stored in 'r.sqlite': --resume goes on"),
            std::string::npos)
      << r.err;
  // every printed rollout is stored, and the run is not marked finished
  CommandResult stored = RunPlumb("results r.sqlite --format csv", dir.path());
  ASSERT_EQ(stored.exit_code, 0) << stored.err;
  EXPECT_EQ(Lines(stored.out) - 1, printed);
  CommandResult again = RunPlumb(args, dir.path());
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_NE(again.err.find("--resume"), std::string::npos) << again.err;
}

TEST(BudgetCliTest, SweepMaxSecondsPrintsEveryFinishedCaseWhole) {
  TempDir dir;
  CommandResult r = RunPlumb("sweep " + kPendulum +
                                 " --vary 'dof_damping[hinge]=0:0.1:1000000' --set "
                                 "'qpos[hinge]=0.7' --metric 'qpos[hinge]@0.01' --format csv "
                                 "--max-seconds 0.3",
                             dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  long printed = Lines(r.out) - 1;
  EXPECT_GT(printed, 0);
  EXPECT_LT(printed, 1000000);
  EXPECT_EQ(r.out.back(), '\n');
  EXPECT_NE(r.err.find("plumb: --max-seconds 0.3 spent: the " + std::to_string(printed) +
                       " finished cases were printed"),
            std::string::npos)
      << r.err;
}

TEST(BudgetCliTest, AHugeRolloutSaysHowLongTheRestTakesAndHowToStopIt) {
  TempDir dir;
  CommandResult r = RunPlumb(Rollouts(100000000) + " --max-seconds 2.5", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find(" rollouts/s the rest takes about "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("Ctrl-C or --max-seconds stops it and keeps what finished"),
            std::string::npos)
      << r.err;
}

}  // namespace
}  // namespace plumb
