// The command line's outputs as a user meets them: where -o writes, how numbers are
// printed, what diff and snapshot say about the files they are given.

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>

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

// An output onto one of the command's inputs (issue 46): refused with exit 2 before anything is
// written, under every name that reaches the input. {IN} is the input, {OUT} the output,
// {M} the pendulum model when the input is another file; `flag` names the output.
struct OntoInput {
  const char* name;
  const char* command;
  const char* input;  // "p.xml" (a copy of the pendulum) or "in.toml" (another input)
  const char* flag;
};

const OntoInput kOntoInputs[] = {
    {"RunOutput", "run {IN} --until 0.1 -o {OUT}", "p.xml", "-o"},
    {"RunRepro", "run {IN} --until 0.1 --repro {OUT}", "p.xml", "--repro"},
    {"RunPose", "run {M} --pose {IN} --until 0.1 --format csv -o {OUT}", "in.toml", "-o"},
    {"Snapshot", "snapshot {IN} -o {OUT}", "p.xml", "-o"},
    {"Render", "render {IN} -o {OUT}", "p.xml", "-o"},
    {"IdentifyModel", "identify {IN} --log in.toml --fit 'dof_damping[hinge]' -o {OUT}", "p.xml",
     "-o"},
    {"IdentifyLog", "identify {M} --log {IN} --fit 'dof_damping[hinge]' --report {OUT}", "in.toml",
     "--report"},
    {"BridgeModel", "bridge {IN} --until 0.01 --log {OUT}", "p.xml", "--log"},
    {"BridgeConfig", "bridge {M} --config {IN} --log {OUT}", "in.toml", "--log"},
    {"AuditReport", "audit {IN} --report {OUT}", "p.xml", "--report"},
    {"AuditRepro", "audit {IN} --repro {OUT}", "p.xml", "--repro"},
    {"AuditAccept", "audit {M} --accept {IN} --report {OUT}", "in.toml", "--report"},
    {"Verify", "verify {IN} --report {OUT}", "p.xml", "--report"},
    {"Converge", "converge {IN} --metric 'qpos[hinge]@0.1' --report {OUT}", "p.xml", "--report"},
    {"Crosscheck", "crosscheck {IN} --report {OUT}", "p.xml", "--report"},
    {"SweepStore",
     "sweep {IN} --vary 'dof_damping[hinge]=0.1,0.2' --metric 'qpos[hinge]@0.1' --db {OUT}",
     "p.xml", "--db"},
    {"RolloutStore", "rollout {IN} --count 2 --until 0.1 --metric 'qpos[hinge]@0.1' --db {OUT}",
     "p.xml", "--db"},
    {"RolloutReport", "rollout {IN} --count 2 --until 0.1 --report {OUT}", "p.xml", "--report"},
    {"Merge", "merge {IN} -o {OUT}", "in.toml", "-o"},
    {"Replay", "replay {M} --log {IN} --report {OUT}", "in.toml", "--report"},
    {"Diff", "diff {IN} {M} --report {OUT}", "in.toml", "--report"},
};

// A case's name, not its bytes, in the test's description.
void PrintTo(const OntoInput& c, std::ostream* out) { *out << c.name; }

class OutputOntoInputTest : public ::testing::TestWithParam<OntoInput> {};

std::string Substituted(std::string text, const std::string& in, const std::string& out) {
  for (auto [key, value] :
       {std::pair<std::string, std::string>{"{IN}", in}, {"{OUT}", out}, {"{M}", kPendulum}}) {
    for (std::size_t at; (at = text.find(key)) != std::string::npos;) {
      text.replace(at, key.size(), value);
    }
  }
  return text;
}

std::set<std::string> Listing(const std::string& dir) {
  std::set<std::string> names;
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
    names.insert(e.path().filename().string());
  }
  return names;
}

TEST_P(OutputOntoInputTest, IsRefusedUnderEveryNameAndTheInputIsUntouched) {
  const OntoInput& c = GetParam();
  TempDir dir;
  fs::copy_file(kPendulum, dir.File("p.xml"));
  WriteFile(dir.File("in.toml"), "# an input, kept as it is\nuntil = 0.01\n");
  fs::create_symlink(c.input, dir.File("link"));
  fs::create_hard_link(dir.File(c.input), dir.File("hard"));
  const std::string bytes = ReadFile(dir.File(c.input));
  const std::set<std::string> before = Listing(dir.path());
  std::string input = c.input;
  // the output as the input is named, relative, absolute, through a symbolic and a hard link;
  // then the input through the link and the output by name
  std::vector<std::pair<std::string, std::string>> spellings = {
      {input, input},  {input, "./" + input}, {"./" + input, dir.File(input)},
      {input, "link"}, {input, "hard"},       {"link", input}};
  for (const auto& [in, out] : spellings) {
    std::string args = Substituted(c.command, in, out);
    CommandResult r = RunPlumb(args, dir.path());
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_EQ(r.err.rfind(std::string("plumb: error: ") + c.flag + " '" + out + "': ", 0), 0u)
        << args << "\n"
        << r.err;
    EXPECT_NE(r.err.find("is the same file"), std::string::npos) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("the output would destroy its input; write it elsewhere."),
              std::string::npos)
        << args << "\n"
        << r.err;
    EXPECT_EQ(ReadFile(dir.File(c.input)), bytes) << args << ": the input changed";
    EXPECT_TRUE(fs::is_symlink(dir.File("link"))) << args << ": the link was replaced";
    EXPECT_TRUE(fs::equivalent(dir.File("hard"), dir.File(c.input))) << args;
    EXPECT_EQ(Listing(dir.path()), before) << args << ": something was written";
  }
}

INSTANTIATE_TEST_SUITE_P(OutputCliTest, OutputOntoInputTest, ::testing::ValuesIn(kOntoInputs),
                         [](const ::testing::TestParamInfo<OntoInput>& info) {
                           return std::string(info.param.name);
                         });

TEST(OutputCliTest, BridgeLogOfTheConfigOntoTheConfigIsRefused) {
  TempDir dir;
  const std::string config = "log = \"b.toml\"\nuntil = 0.01\n";
  WriteFile(dir.File("b.toml"), config);
  CommandResult r = RunPlumb("bridge " + kPendulum + " --config b.toml", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("the --config file 'b.toml' is the same file"), std::string::npos) << r.err;
  EXPECT_EQ(ReadFile(dir.File("b.toml")), config);
}

TEST(OutputCliTest, OutputsBesideTheInputsAreWritten) {
  // the rule is about identity: a new file, an earlier output or a copy of the input is no input
  TempDir dir;
  fs::copy_file(kPendulum, dir.File("p.xml"));
  fs::copy_file(kPendulum, dir.File("copy.xml"));
  for (int i = 0; i < 2; ++i) {
    CommandResult r = RunPlumb("snapshot p.xml -o p.json", dir.path());
    EXPECT_EQ(r.exit_code, 0) << r.err;
  }
  CommandResult r = RunPlumb("run p.xml --until 0.1 --format csv -o copy.xml", dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(ReadFile(dir.File("copy.xml")).rfind("time,", 0), 0u);
}

}  // namespace
}  // namespace plumb
