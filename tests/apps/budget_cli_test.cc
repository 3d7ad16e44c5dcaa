// plumb run's cost before it is spent: the estimate a long run prints, and the --max-seconds
// and --max-rows budgets, which stop cleanly and keep every row written so far.

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

}  // namespace
}  // namespace plumb
