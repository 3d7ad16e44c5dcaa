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

// A folder with a model, a copy and its snapshot, an empty and a binary file.
class DiffArgumentsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::copy_file(kPendulum, dir_.File("a.xml"));
    fs::copy_file(kPendulum, dir_.File("b.xml"));
    ASSERT_EQ(Plumb("snapshot a.xml -o a.json").exit_code, 0);
    WriteFile(dir_.File("empty.xml"), "");
    WriteFile(dir_.File("binary.xml"), std::string("\x7f"
                                                   "ELF\x02\x01\x01\x00\x00",
                                                   9));
  }
  CommandResult Plumb(const std::string& args) { return RunPlumb(args, dir_.path()); }
  // Expects exit 2 and `text` in the message, and no raw MuJoCo parser error.
  void ExpectRefused(const std::string& args, const std::string& text) {
    CommandResult r = Plumb(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(text), std::string::npos) << args << "\n" << r.err;
    EXPECT_EQ(r.err.find("XML Error"), std::string::npos) << args << "\n" << r.err;
  }
  TempDir dir_;
};

TEST_F(DiffArgumentsTest, SwappedArgumentsSayTheRightOrder) {
  ExpectRefused("diff a.xml a.json", "the arguments are swapped");
  ExpectRefused("diff a.xml a.json", "plumb diff a.json a.xml");
}

TEST_F(DiffArgumentsTest, TwoModelsSayHowToTakeASnapshot) {
  ExpectRefused("diff a.xml b.xml", "'a.xml' is an MJCF model (XML), not a plumb snapshot");
  ExpectRefused("diff a.xml b.xml", "plumb snapshot a.xml -o");
}

TEST_F(DiffArgumentsTest, EmptyOrBinaryFilesAreNamed) {
  ExpectRefused("diff empty.xml a.xml", "'empty.xml' is empty, not a plumb snapshot");
  ExpectRefused("diff binary.xml a.xml", "'binary.xml' is a binary file, not a plumb snapshot");
  ExpectRefused("diff a.json empty.xml", "model file 'empty.xml' is empty");
  ExpectRefused("diff a.json binary.xml", "model file 'binary.xml' is a binary file");
  ExpectRefused("diff a.json a.json", "is a plumb snapshot (JSON), not a model");
  // every command loads models the same way
  ExpectRefused("run empty.xml", "model file 'empty.xml' is empty");
  ExpectRefused("inspect binary.xml", "model file 'binary.xml' is a binary file");
}

TEST(OutputCliTest, SnapshotWithSetDiffsIdenticalAgainstTheSameModel) {
  TempDir dir;
  ASSERT_EQ(RunPlumb("snapshot " + kPendulum + kSet + "-o p.json", dir.path()).exit_code, 0);
  CommandResult same = RunPlumb("diff p.json " + kPendulum, dir.path());
  EXPECT_EQ(same.exit_code, 0) << same.out << same.err;
  EXPECT_NE(same.out.find("--set 'qpos[hinge]=0.7'"), std::string::npos) << same.out;
}

TEST(OutputCliTest, DiffJsonGivesStructuredChanges) {
  TempDir dir;
  ASSERT_EQ(RunPlumb("snapshot " + kPendulum + kSet + "-o p.json", dir.path()).exit_code, 0);
  CommandResult r = RunPlumb(
      "diff p.json " + kPendulum + " --set 'dof_damping[hinge]=0.1' --format json", dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["snapshot"], "p.json");
  EXPECT_FALSE(j["identical"].get<bool>());
  EXPECT_EQ(j["snapshot_sets"], nlohmann::json({"qpos[hinge]=0.7"}));
  ASSERT_GE(j["changes"].size(), 2u) << r.out;
  const nlohmann::json& damping = j["changes"][0];
  EXPECT_EQ(damping["path"], "dof_damping[hinge]");
  EXPECT_EQ(damping["old"], 0.05);
  EXPECT_EQ(damping["new"], 0.1);
  EXPECT_EQ(damping["kind"], "parameter");
  const nlohmann::json& departs = j["changes"].back();
  EXPECT_EQ(departs["kind"], "trajectory") << r.out;
  EXPECT_TRUE(departs["old"].is_number() && departs["new"].is_number()) << r.out;
}

const std::string kCartpole = testing::kSuite + "/cartpole.xml";

TEST(OutputCliTest, InspectShowsCtrlAndJointForceOfAGearedMotor) {
  CommandResult r = RunPlumb("inspect " + kCartpole);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string row = r.out.substr(r.out.find("joint:slider"));
  row = row.substr(0, row.find('\n'));
  EXPECT_NE(row.find("[-1, 1] N/gear"), std::string::npos) << row;
  EXPECT_NE(row.find("[-10, 10] N"), std::string::npos) << row;
}

TEST(OutputCliTest, AuditStepResponseGivesTheLengthsUnit) {
  CommandResult r = RunPlumb("audit --all " + kCartpole);
  std::size_t at = r.out.find("moves the actuator length by");
  ASSERT_NE(at, std::string::npos) << r.out;
  std::string text = r.out.substr(at, r.out.find('\n', at) - at);
  EXPECT_NE(text.find("(gear 10 x "), std::string::npos) << text;
  EXPECT_NE(text.find(" m at the joint)"), std::string::npos) << text;
  EXPECT_NE(text.find(" m/s at the joint)"), std::string::npos) << text;
}

}  // namespace
}  // namespace plumb
