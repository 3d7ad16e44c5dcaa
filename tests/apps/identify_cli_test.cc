// plumb replay and plumb identify as a user runs them: logs from plumb run, bad logs and
// options refused with exit 2 and nothing written, the fitted model saved and loadable.

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "core/mujoco_compat.h"
#include "fixture.h"
#include "plumb/model.h"
#include "plumb/model_edit.h"
#include "plumb/path.h"
#include "sim/log_maker.h"

namespace plumb {
namespace {

class CliIdentifyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // the robot: more damping than the model says
    auto r = testing::RunPlumb("run '" + testing::kPendulum +
                                   "' --set 'qpos[hinge]=0.7' --set 'dof_damping[hinge]=0.2' "
                                   "--format csv --until 3 --every 0.01 -o decay.csv",
                               dir_.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  testing::TempDir dir_;
};

TEST_F(CliIdentifyTest, ReplayShowsTheMismatchAndWindowsBoundIt) {
  auto r = testing::RunPlumb("replay '" + testing::kPendulum + "' --log decay.csv --format json",
                             dir_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["signals"].size(), 2u);
  EXPECT_EQ(j["signals"][0]["column"], "qpos[hinge]");
  EXPECT_EQ(j["signals"][0]["samples"], 301);
  EXPECT_GT(j["signals"][0]["rms"].get<double>(), 0.05);
  EXPECT_LT(j["fit"].get<double>(), 90);
  r = testing::RunPlumb(
      "replay '" + testing::kPendulum + "' --log decay.csv --set 'dof_damping[hinge]=0.2'",
      dir_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("overall fit 100.00 %"), std::string::npos) << r.out;
}

// A log of an actuated model written by plumb run carries its controls by default, so its
// replay on the same model fits exactly; a log without them gets a note, not a silent 0
TEST_F(CliIdentifyTest, ARunLogCarriesItsControlsAndReplayNamesTheirAbsence) {
  testing::WriteFile(dir_.File("pushed.xml"), testing::TwoHingeArm(R"(
      <motor name="shoulder" joint="a" ctrlrange="-1 1" ctrllimited="true"/>)"));
  auto r = testing::RunPlumb(
      "run pushed.xml --set 'ctrl[shoulder]=0.3' --format csv --until 1 --every 0.01 -o log.csv",
      dir_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(testing::ReadFile(dir_.File("log.csv")).find(",ctrl[shoulder]"), std::string::npos);
  r = testing::RunPlumb("replay pushed.xml --log log.csv", dir_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("inputs: ctrl[shoulder]"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("overall fit 100.00 %"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("holds no inputs"), std::string::npos) << r.out;

  r = testing::RunPlumb(
      "run pushed.xml --set 'ctrl[shoulder]=0.3' --format csv --until 1 --every 0.01 "
      "--columns 'time,qpos[a],qvel[a]' -o bare.csv",
      dir_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = testing::RunPlumb("replay pushed.xml --log bare.csv", dir_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("inputs: none"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("note: the model has 1 control(s) but the log holds no inputs"),
            std::string::npos)
      << r.out;
}

TEST_F(CliIdentifyTest, IdentifyRecoversTheDampingAndSavesTheModel) {
  auto r = testing::RunPlumb("identify '" + testing::kPendulum +
                                 "' --log decay.csv --fit 'dof_damping[hinge]' -o fitted.xml",
                             dir_.path());
  if (!CanSaveEditedXml()) {
    EXPECT_EQ(r.exit_code, 5) << r.err;
    EXPECT_NE(r.err.find("mjSpec"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir_.File("fitted.xml")));
    return;
  }
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("dof_damping[hinge]: 0.05 -> 0.2"), std::string::npos) << r.out;
  Model fitted = Model::Load(dir_.File("fitted.xml"));
  Data d(fitted);
  EXPECT_NEAR(ReadValue(fitted, d, ResolvePath(fitted, "dof_damping[hinge]")), 0.2, 1e-9);
  // the saved model replays the log exactly
  r = testing::RunPlumb("replay fitted.xml --log decay.csv", dir_.path());
  EXPECT_NE(r.out.find("overall fit 100.00 %"), std::string::npos) << r.out;
}

TEST_F(CliIdentifyTest, AFittedMassIsSavedWithItsInertia) {
  if (!CanSaveEditedXml()) GTEST_SKIP() << "this MuJoCo has no mjSpec";
  std::string arm = testing::kSourceDir + "/tests/models/arm2.xml";
  testing::LogSpec spec;
  spec.model = arm;
  spec.set = {"body_mass[payload]=0.8"};
  spec.input = "ctrl[shoulder]";
  spec.u = [](double t) { return std::fmod(t, 1.0) < 0.5 ? 12.0 : 4.0; };
  spec.measured = {"qpos[shoulder]", "qpos[elbow]", "qvel[shoulder]", "qvel[elbow]"};
  spec.until = 2;
  testing::MakeLog(dir_.File("steps.csv"), spec);
  auto r = testing::RunPlumb(
      "identify '" + arm + "' --log steps.csv --fit 'body_mass[payload]' -o arm-fitted.xml",
      dir_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Model fitted = Model::Load(dir_.File("arm-fitted.xml"));
  Model truth = Model::Load(arm);
  Data d(truth);
  WriteValues(truth, d, ResolvePath(truth, "body_mass[payload]"), {0.8});
  int b = mj_name2id(fitted.get(), mjOBJ_BODY, "payload");
  EXPECT_NEAR(fitted->body_mass[b], 0.8, 1e-6);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(fitted->body_inertia[3 * b + k], truth->body_inertia[3 * b + k], 1e-8);
}

TEST_F(CliIdentifyTest, BadInputIsExit2AndWritesNothing) {
  testing::WriteFile(dir_.File("back.csv"), "time,qpos[hinge]\n0,0.7\n0.01,0.69\n0.005,0.68\n");
  auto r = testing::RunPlumb(
      "identify '" + testing::kPendulum + "' --log back.csv --fit 'dof_damping[hinge]' --report out.html",
      dir_.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("back.csv: row 4, column 'time': goes backwards"), std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir_.File("out.html")));
  r = testing::RunPlumb(
      "identify '" + testing::kPendulum + "' --log decay.csv --fit 'qpos[hinge]' --report out.html",
      dir_.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("not a model parameter"), std::string::npos) << r.err;
  r = testing::RunPlumb("identify '" + testing::kPendulum +
                            "' --log decay.csv --fit 'dof_damping[hinge]' --bounds "
                            "'dof_damping[hinge]=1:2'",
                        dir_.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("lies outside"), std::string::npos) << r.err;
  r = testing::RunPlumb("identify '" + testing::kPendulum +
                            "' --log decay.csv --fit 'dof_damping[hinge]' --delay ctrl",
                        dir_.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("no input column"), std::string::npos) << r.err;
  r = testing::RunPlumb("replay '" + testing::kPendulum + "' --log nosuch.csv", dir_.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("nosuch.csv"), std::string::npos) << r.err;
  r = testing::RunPlumb("replay '" + testing::kPendulum + "' --log decay.csv --window -1",
                        dir_.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_FALSE(std::filesystem::exists(dir_.File("out.html")));
}

TEST_F(CliIdentifyTest, AValidationLogIsReported) {
  auto make = testing::RunPlumb("run '" + testing::kPendulum +
                                    "' --set 'qpos[hinge]=-0.4' --set 'dof_damping[hinge]=0.2' "
                                    "--format csv --until 2 --every 0.01 -o other.csv",
                                dir_.path());
  ASSERT_EQ(make.exit_code, 0) << make.err;
  auto r = testing::RunPlumb("identify '" + testing::kPendulum +
                                 "' --log decay.csv --fit 'dof_damping[hinge]' --validate "
                                 "other.csv --format json",
                             dir_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_LT(j["validation"]["fit_nominal"].get<double>(), 95);
  EXPECT_GT(j["validation"]["fit_fitted"].get<double>(), 99.9);
}

// A model that lacks the log's spring, its damping fitted: the table warns, names the evidence
// and never reassures with the residual variance; the JSON and the report say the same, and
// which standard errors are given. The right model gets the reassurance and classical ones.
TEST_F(CliIdentifyTest, AMisspecifiedFitWarnsAndSaysWhichStandardErrors) {
  testing::LogSpec spec;
  spec.set = {"qpos[hinge]=0.7", "jnt_stiffness[hinge]=3"};
  spec.noise = {0.002, 0.01};
  spec.until = 4;
  spec.every = 5;
  testing::MakeLog(dir_.File("spring.csv"), spec);
  spec.set = {"qpos[hinge]=0.7"};
  testing::MakeLog(dir_.File("right.csv"), spec);
  const std::string identify =
      "identify '" + testing::kPendulum + "' --fit 'dof_damping[hinge]' --log ";
  auto r = testing::RunPlumb(identify + "spring.csv --report spring.html", dir_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("WARN misspecified: the model cannot explain the logs up to their noise: "
                       "2 of 2 signals' residuals have structure over time"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("lag-1 autocorrelation 0.9"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("about 1 when"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("standard errors: "), std::string::npos) << r.out;
  std::string html = testing::ReadFile(dir_.File("spring.html"));
  EXPECT_NE(html.find("WARN misspecified"), std::string::npos);
  EXPECT_NE(html.find("Standard errors: "), std::string::npos);
  EXPECT_EQ(html.find("about 1 when"), std::string::npos);

  r = testing::RunPlumb(identify + "spring.csv --format json", dir_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["misspecification"]["detected"].get<bool>());
  EXPECT_EQ(j["misspecification"]["signals"].size(), 2u);
  EXPECT_GT(j["misspecification"]["signals"][0]["autocorrelation"].get<double>(), 0.5);
  EXPECT_NE(j["std_errors"]["kind"], "classical");
  EXPECT_FALSE(j["std_errors"]["why"].get<std::string>().empty());
  EXPECT_TRUE(j["estimates"][0]["classical_std_error"].is_number());

  r = testing::RunPlumb(identify + "right.csv", dir_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("(about 1 when the model explains all but the noise"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("standard errors: classical"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("WARN"), std::string::npos) << r.out;
}

// A held-out flight log whose last line a kill cut: the command says so on stderr (as replay
// does) and its JSON carries the note (issue 47: the identify job says it, both front ends
// present it).
TEST_F(CliIdentifyTest, ACutLogIsNotedOnStderrAndInTheJson) {
  std::string flight;
  for (const std::string& line : testing::Lines(testing::ReadFile(dir_.File("decay.csv")))) {
    std::size_t comma = line.find(',');
    flight +=
        line.substr(0, comma) + (flight.empty() ? ",kind" : ",state") + line.substr(comma) + "\n";
  }
  testing::WriteFile(dir_.File("cut.csv"), flight.substr(0, flight.size() - 4));
  const std::string identify = "identify '" + testing::kPendulum +
                               "' --fit 'dof_damping[hinge]' --log decay.csv --validate cut.csv";
  auto r = testing::RunPlumb(identify, dir_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("plumb: note: cut.csv: the last line is cut short"), std::string::npos)
      << r.err;
  r = testing::RunPlumb(identify + " --format json", dir_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto notices = nlohmann::json::parse(r.out)["notices"];
  ASSERT_EQ(notices.size(), 1u) << r.out;
  EXPECT_EQ(notices[0]["topic"], "log");
  EXPECT_EQ(notices[0]["subject"], "cut.csv");
}

// The commands of a --help text's "Examples" block, each on one line (a line ending in " \\"
// goes on with the next).
std::vector<std::string> HelpExamples(const std::string& help) {
  std::vector<std::string> out;
  std::size_t at = help.find("\nExamples");
  if (at == std::string::npos) return out;
  std::istringstream lines(help.substr(help.find('\n', at + 1) + 1));
  bool more = false;
  for (std::string line; std::getline(lines, line) && line.rfind("  ", 0) == 0;) {
    std::string text = line.substr(line.find_first_not_of(' '));
    bool next = text.size() >= 2 && text.compare(text.size() - 2, 2, " \\") == 0;
    if (next) text.erase(text.size() - 2);
    if (more) {
      out.back() += " " + text;
    } else {
      out.push_back(text);
    }
    more = next;
  }
  return out;
}

// Every example of plumb identify --help and plumb replay --help runs as written, in order, in
// a folder that has the repository's models/ (the first example writes the log the others
// read). Before, they named logs and a robot nobody has and a delay of inputs the pendulum's
// log lacks.
TEST(CliHelpExamplesTest, IdentifyAndReplayRunEachExampleOfTheirHelp) {
  for (const std::string command : {"identify", "replay"}) {
    testing::TempDir dir;
    std::filesystem::create_directory_symlink(testing::kSourceDir + "/models",
                                              dir.File("models"));
    auto help = testing::RunPlumb(command + " --help", dir.path());
    ASSERT_EQ(help.exit_code, 0) << help.err;
    const std::vector<std::string> examples = HelpExamples(help.out);
    ASSERT_GE(examples.size(), 3u) << help.out;
    for (const std::string& example : examples) {
      ASSERT_EQ(example.rfind("plumb ", 0), 0u) << example;
      // -o writes MJCF, which needs MuJoCo 3.10 (exit 5 before, as the help says)
      const bool writes_model = example.rfind("plumb identify", 0) == 0 &&
                                example.find(" -o ") != std::string::npos;
      const int expected = writes_model && !compat::CompiledAtLeast(3010000) ? 5 : 0;
      auto r = testing::RunPlumb(example.substr(6), dir.path());
      EXPECT_EQ(r.exit_code, expected) << example << "\n" << r.err;
    }
  }
}

}  // namespace
}  // namespace plumb
