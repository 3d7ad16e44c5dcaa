// The command line's outputs as a user meets them: where -o writes, how numbers are
// printed, what diff and snapshot say about the files they are given.

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "fixture.h"

namespace plumb {
namespace {

namespace fs = std::filesystem;
using testing::CommandResult;
using testing::kPendulum;
using testing::ReadFile;
using testing::RunPlumb;
using testing::RunShell;
using testing::TempDir;
using testing::WriteFile;

const std::string kSet = " --set 'qpos[hinge]=0.7' ";

TEST(OutputCliTest, RunOutputToFifoIsWrittenThroughNotReplaced) {
  TempDir dir;
  ASSERT_EQ(mkfifo(dir.File("pipe").c_str(), 0600), 0);
  // the reader in the background, as a user would start it; its own timeout so a
  // regression cannot hang the suite
  CommandResult r =
      RunShell("(timeout 60 cat pipe > got.csv & '" + std::string(PLUMB_CLI) + "' run " +
                   kPendulum + kSet + "--until 0.2 --format csv -o pipe; wait)",
               dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(dir.File("pipe")))) << "the FIFO was replaced";
  EXPECT_EQ(ReadFile(dir.File("got.csv")).rfind("time,qpos[hinge],qvel[hinge]\n0,0.7,0\n", 0), 0u)
      << ReadFile(dir.File("got.csv"));
}

TEST(OutputCliTest, SnapshotOutputThroughSymlinkKeepsTheLink) {
  TempDir dir;
  WriteFile(dir.File("real.json"), "old");
  fs::create_symlink("real.json", dir.File("link.json"));
  fs::create_symlink("new.json", dir.File("dangling.json"));
  ASSERT_EQ(RunPlumb("snapshot " + kPendulum + " -o link.json", dir.path()).exit_code, 0);
  ASSERT_EQ(RunPlumb("snapshot " + kPendulum + " -o dangling.json", dir.path()).exit_code, 0);
  EXPECT_TRUE(fs::is_symlink(dir.File("link.json"))) << "the link was replaced";
  EXPECT_TRUE(fs::is_symlink(dir.File("dangling.json"))) << "the link was replaced";
  EXPECT_TRUE(nlohmann::json::parse(ReadFile(dir.File("real.json"))).contains("plumb_snapshot"));
  EXPECT_TRUE(nlohmann::json::parse(ReadFile(dir.File("new.json"))).contains("plumb_snapshot"));
}

TEST(OutputCliTest, DashOutputIsStandardOutput) {
  TempDir dir;
  CommandResult run =
      RunPlumb("run " + kPendulum + kSet + "--until 0.2 --format csv -o -", dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.out.rfind("time,qpos[hinge],qvel[hinge]\n0,0.7,0\n", 0), 0u) << run.out;
  CommandResult snapshot = RunPlumb("snapshot " + kPendulum + " -o -", dir.path());
  ASSERT_EQ(snapshot.exit_code, 0) << snapshot.err;
  EXPECT_TRUE(nlohmann::json::parse(snapshot.out).contains("plumb_snapshot"));
  EXPECT_TRUE(fs::is_empty(dir.path())) << "a file named '-' was written";
}

TEST(OutputCliTest, MergeToDashIsRefused) {
  TempDir dir;
  CommandResult r = RunPlumb("merge a.sqlite b.sqlite -o -", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("cannot go to standard output"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(OutputCliTest, CsvPrintsTheShortestTextThatRoundTrips) {
  CommandResult r = RunPlumb("run " + kPendulum +
                             " --set 'qpos[hinge]=0.3' --until 0.1 --every 0.1 --format csv");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.substr(0, r.out.find('\n', r.out.find('\n') + 1)),
            "time,qpos[hinge],qvel[hinge]\n0,0.3,0")
      << r.out;
  EXPECT_NE(r.out.find("\n0.1,"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace plumb
