// The plumb command line as a user meets it: outputs, bad input, exit codes.

#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <thread>

#include "fixture.h"
#include "plumb/run.h"

namespace plumb {
namespace {

namespace fs = std::filesystem;
using testing::CommandResult;
using testing::kPendulum;
using testing::ReadFile;
using testing::RunPlumb;
using testing::TempDir;
using testing::WriteFile;

const std::string kSet = " --set 'qpos[hinge]=0.7' ";

TEST(CliRunTest, TableReproducesTheChapter) {
  CommandResult r = RunPlumb("run " + kPendulum + kSet + "--until 2 --every 0.1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("time  qpos[hinge]  qvel[hinge]"), std::string::npos) << r.out;
  // every one of the chapter's printed lines, as printed (5 decimals)
  const char* lines[] = {
      "     0.10000      0.65403     -0.89118\n", "     0.20000      0.52386     -1.66939\n",
      "     0.30000      0.32596     -2.23353\n", "     0.40000      0.08646     -2.49511\n",
      "     0.50000     -0.16156     -2.40852\n"};
  for (const char* line : lines) EXPECT_NE(r.out.find(line), std::string::npos) << line << r.out;
  EXPECT_NE(r.out.find("     2.00000"), std::string::npos) << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 22);  // header + t = 0 ... 2
  EXPECT_EQ(r.err, "");
}

// A delay longer than its history buffer is silently shortened by MuJoCo: loading says so
TEST(CliRunTest, LoadingWarnsOfAShortenedDelay) {
  if (!(mjVERSION_HEADER >= 3005000)) GTEST_SKIP() << "delays came with MuJoCo 3.5";
  testing::TempDir dir;
  std::string model = dir.File("late.xml");
  testing::WriteFile(model, testing::TwoHingeArm(R"(<motor name="late" joint="a" delay="0.5"
      nsample="20"/>)"));
  CommandResult r = RunPlumb("run " + model + " --until 0.01");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("plumb: warning: '" + model +
                       "': actuator 'late' (id 0): delay 0.5 s is "
                       "longer than its buffer of 20 samples x timestep = 0.04 s"),
            std::string::npos)
      << r.err;
}

// What a command says on stderr its JSON document carries too, as "notices": a start value
// MuJoCo clamps, a delay MuJoCo shortened; the stderr lines are unchanged.
TEST(CliRunTest, TheJsonDocumentCarriesTheNotices) {
  testing::TempDir dir;
  std::string model = dir.File("arm.xml");
  testing::WriteFile(model, testing::TwoHingeArm(R"(<motor name="m" joint="a" ctrlrange="-1 1"
      ctrllimited="true"/>)"));
  CommandResult r = RunPlumb("inspect " + model + " --set 'ctrl[m]=5' --format json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("plumb: warning: --set 'ctrl[m]=5': 5 is outside the ctrlrange"),
            std::string::npos)
      << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["notices"].size(), 1u) << r.out;
  EXPECT_EQ(j["notices"][0]["level"], "warning");
  EXPECT_EQ(j["notices"][0]["topic"], "start");
  EXPECT_EQ(j["notices"][0]["subject"], "--set 'ctrl[m]=5'");
  EXPECT_NE(j["notices"][0]["text"].get<std::string>().find("ctrlrange"), std::string::npos);
  CommandResult quiet = RunPlumb("verify " + testing::kPendulum + " --format json --quiet");
  ASSERT_EQ(quiet.exit_code, 0) << quiet.err;
  EXPECT_EQ(nlohmann::json::parse(quiet.out)["notices"], nlohmann::json::array()) << quiet.out;
}

// MuJoCo 4 gives settotalmass's deprecation both in the compiler's message and to its
// warning handler: plumb printed it twice.
TEST(CliRunTest, ACompilerWarningIsPrintedOnce) {
  testing::TempDir dir;
  testing::WriteFile(dir.File("total.xml"), R"(<mujoco><compiler settotalmass="5"/><worldbody>
      <body><freejoint/><geom size="0.1"/></body></worldbody></mujoco>)");
  CommandResult r = RunPlumb("run total.xml --until 0.002", dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::size_t said = 0;
  for (std::size_t at = r.err.find("settotalmass"); at != std::string::npos;
       at = r.err.find("settotalmass", at + 1)) {
    ++said;
  }
  EXPECT_LE(said, 1u) << r.err;
  if (mjVERSION_HEADER >= 4000000) {
    EXPECT_EQ(said, 1u) << r.err;
  }
}

TEST(CliRunTest, CsvToFileHasExactHeader) {
  TempDir dir;
  CommandResult r = RunPlumb(
      "run " + kPendulum + kSet + "--until 2 --every 0.1 --format csv -o traj.csv", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "");
  std::string csv = ReadFile(dir.File("traj.csv"));
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "time,qpos[hinge],qvel[hinge]");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 22);
}

TEST(CliRunTest, ColumnsChooseAnyPaths) {
  CommandResult r = RunPlumb("run " + kPendulum + kSet +
                             "--until 0.2 --format csv --columns 'time,xpos[link][2],qacc[hinge]'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.substr(0, r.out.find('\n')), "time,xpos[link][2],qacc[hinge]");
}

TEST(CliRunTest, JsonLinesOnePerSample) {
  CommandResult r = RunPlumb("run " + kPendulum + kSet + "--until 0.5 --format jsonl");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream lines(r.out);
  std::string line;
  int n = 0;
  while (std::getline(lines, line)) {
    nlohmann::json row = nlohmann::json::parse(line);
    EXPECT_TRUE(row.contains("qvel[hinge]"));
    ++n;
  }
  EXPECT_EQ(n, 6);
}

TEST(CliRunTest, AtRestPendulumGetsAHintOnStderr) {
  CommandResult r = RunPlumb("run " + kPendulum + " --until 0.2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("will not move"), std::string::npos) << r.err;
}

TEST(CliInspectTest, TableShowsTheChaptersFields) {
  CommandResult r = RunPlumb("inspect " + kPendulum);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* text :
       {"nbody", "njnt", "opt.timestep", "0.002", "hinge", "link", "parameter", "derived", "rad"}) {
    EXPECT_NE(r.out.find(text), std::string::npos) << text;
  }
}

TEST(CliInspectTest, JsonUsesMujocoNames) {
  CommandResult r = RunPlumb("inspect " + kPendulum + " --format json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["sizes"]["nbody"], 2);
  EXPECT_EQ(j["sizes"]["njnt"], 1);
  EXPECT_EQ(j["sizes"]["nq"], 1);
  EXPECT_EQ(j["sizes"]["nv"], 1);
  EXPECT_EQ(j["sizes"]["nu"], 0);
  EXPECT_EQ(j["options"]["opt.timestep"], 0.002);
  EXPECT_EQ(j["joints"][0]["name"], "hinge");
}

// Newer sensor types by their MJCF names, in a column as wide as the longest
TEST(CliInspectTest, NamesEverySensorType) {
  if (!(mjVERSION_HEADER >= 3011000)) GTEST_SKIP() << "the newer sensors came after MuJoCo 2.x";
  testing::TempDir dir;
  testing::WriteFile(dir.File("arm.xml"), testing::TwoHingeArm(R"(<motor name="m" joint="b"/>
    </actuator><sensor><jointactuatorfrc name="tau" joint="b"/><e_kinetic name="energy"/>
    </sensor><actuator>)"));
  CommandResult r = RunPlumb("inspect arm.xml", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("tau              jointactuatorfrc  sensordata[0..0]"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("e_kinetic"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("type 1"), std::string::npos) << r.out;
}

TEST(CliInspectTest, HumanoidHasNqDifferentFromNv) {
  CommandResult r = RunPlumb("inspect " + testing::kHumanoid + " --format json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["sizes"]["nq"], 28);
  EXPECT_EQ(j["sizes"]["nv"], 27);
  CommandResult table = RunPlumb("inspect " + testing::kHumanoid);
  EXPECT_NE(table.out.find("nq != nv"), std::string::npos);
}

// Every bad input: a message on stderr saying what and where, exit 2, no output file.
class CliBadInputTest : public ::testing::Test {
 protected:
  CommandResult Expect2(const std::string& args, const std::string& must_mention) {
    CommandResult r = RunPlumb(args + " -o out.csv", dir_.path());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find(must_mention), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "");
    EXPECT_TRUE(fs::is_empty(dir_.path())) << "output left behind";
    return r;
  }
  TempDir dir_;
};

TEST_F(CliBadInputTest, MissingFile) { Expect2("run missing.xml", "missing.xml"); }

TEST_F(CliBadInputTest, MalformedXml) {
  TempDir models;
  WriteFile(models.File("bad.xml"), "<mujoco>\n<worldbody>\n<body>\n<geom size=\"1\"\n");
  Expect2("run " + models.File("bad.xml"), "Line number=4");
}

TEST_F(CliBadInputTest, NegativeGeomSizeGivesObjectAndLine) {
  TempDir models;
  WriteFile(
      models.File("neg.xml"),
      "<mujoco>\n<worldbody>\n<body name=\"b\">\n<joint name=\"j\"/>\n"
      "<geom name=\"rod\" type=\"sphere\" size=\"-0.1\"/>\n</body>\n</worldbody>\n</mujoco>\n");
  CommandResult r = Expect2("run " + models.File("neg.xml"), "neg.xml");
  EXPECT_NE(r.err.find("'rod'"), std::string::npos) << r.err;
  EXPECT_TRUE(testing::NamesLine(r.err, 5)) << r.err;
}

TEST_F(CliBadInputTest, RangeWithoutLimitedExplainsAutolimits) {
  TempDir models;
  WriteFile(models.File("lim.xml"),
            "<mujoco><worldbody><body><joint name=\"j\" range=\"-1 1\"/><geom size=\"1\"/></body>"
            "</worldbody></mujoco>");
  if (mjVERSION_HEADER >= 300) {
    // MuJoCo 3 turned autolimits on by default: the range limits the joint
    CommandResult r = RunPlumb("inspect " + models.File("lim.xml") + " --format json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    return;
  }
  Expect2("run " + models.File("lim.xml"), "autolimits");
}

// Syntax only MuJoCo 3 reads: the implicitfast integrator and a range without limited.
// It loads and runs on the newer legs; on 2.2.2 it is a load error with the chapter
// table's advice for the range (the first error MuJoCo meets).
TEST_F(CliBadInputTest, MujocoThreeSyntaxLoadsOrIsExplained) {
  TempDir models;
  WriteFile(models.File("new.xml"),
            "<mujoco><option integrator=\"implicitfast\"/><worldbody><body>"
            "<joint name=\"j\" range=\"-1 1\"/><geom size=\"0.1\" pos=\"0 0 -1\"/></body>"
            "</worldbody></mujoco>");
  if (mjVERSION_HEADER < 300) {
    WriteFile(models.File("range.xml"),
              "<mujoco><worldbody><body><joint name=\"j\" range=\"-1 1\"/>"
              "<geom size=\"0.1\" pos=\"0 0 -1\"/></body></worldbody></mujoco>");
    Expect2("run " + models.File("range.xml"), "autolimits");
    Expect2("run " + models.File("new.xml"), "new.xml");
    return;
  }
  CommandResult r = RunPlumb("run " + models.File("new.xml") +
                             " --set 'qpos[j]=0.5' --until 0.2 --every 0.1 --format csv");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 4) << r.out;  // header, 0, 0.1, 0.2 s
  CommandResult info = RunPlumb("inspect " + models.File("new.xml") + " --format json");
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_NE(info.out.find("implicitfast"), std::string::npos) << info.out;
}

TEST_F(CliBadInputTest, UnknownPath) {
  CommandResult r = Expect2("run " + kPendulum + " --set 'qpos[hnge]=0.7'", "qpos[hnge]");
  EXPECT_NE(r.err.find("did you mean: hinge"), std::string::npos) << r.err;
  Expect2("run " + kPendulum + " --columns 'time,qpso[hinge]'", "qpso");
}

TEST_F(CliBadInputTest, NonNumericValue) {
  Expect2("run " + kPendulum + " --set 'qpos[hinge]=abc'", "not a number");
}

TEST_F(CliBadInputTest, NanValue) {
  Expect2("run " + kPendulum + " --set 'qpos[hinge]=nan'", "nan");
}

TEST_F(CliBadInputTest, EveryNotAMultipleOfTheTimestep) {
  Expect2("run " + kPendulum + " --every 0.003", "--every 0.003");
}

TEST_F(CliBadInputTest, NegativeUntil) { Expect2("run " + kPendulum + " --until -1", "--until"); }

TEST_F(CliBadInputTest, UnknownOption) { Expect2("run " + kPendulum + " --untill 2", "untill"); }

TEST(CliRunTest, AnUnknownColumnNamesTheOption) {
  CommandResult r = RunPlumb("run " + kPendulum + " --columns 'time,qpos[hing]'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--columns"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("hinge"), std::string::npos) << r.err;
}

TEST(CliOutputTest, UnwritableOutputPathIsBadInput) {
  TempDir dir;
  CommandResult r = RunPlumb("run " + kPendulum + " -o /nonexistent-dir/traj.csv");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("/nonexistent-dir/traj.csv"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists("/nonexistent-dir/traj.csv"));
}

// A spring so stiff that the model's timestep makes explicit Euler blow up in a few steps.
const char* const kStiff = R"(<mujoco model="stiff">
    <option timestep="0.01" gravity="0 0 0"/>
    <worldbody><body name="mass">
      <joint name="slider" type="slide" axis="1 0 0" stiffness="1e6"/>
      <geom type="sphere" size="0.05" mass="1"/>
    </body></worldbody></mujoco>)";

TEST(CliDivergenceTest, DivergenceExits3WithAReproFolder) {
  TempDir dir;
  WriteFile(dir.File("stiff.xml"), kStiff);
  CommandResult r = RunPlumb(
      "run stiff.xml --set 'qpos[slider]=0.01' --until 10 --every 0.01 "
      "-o traj.csv",
      dir.path());
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("diverged"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("plumb-repro-stiff"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir.File("traj.csv")));
  std::string repro = dir.File("plumb-repro-stiff");
  for (const char* name : {"model.xml", "model.mjb", "last_good.json", "bad.json", "command.txt"}) {
    EXPECT_TRUE(fs::exists(repro + "/" + name)) << name;
  }
  EXPECT_NE(ReadFile(repro + "/command.txt").find("'qpos[slider]=0.01'"), std::string::npos);
  nlohmann::json good = nlohmann::json::parse(ReadFile(repro + "/last_good.json"));
  EXPECT_TRUE(good["qpos"][0].is_number());
  // the saved model reproduces the divergence on its own
  CommandResult again = RunPlumb("run " + repro +
                                     "/model.mjb --set 'qpos[slider]=0.01' "
                                     "--until 10 --every 0.01 --repro again",
                                 dir.path());
  EXPECT_EQ(again.exit_code, 3);
}

// MuJoCo 4.0: a model with a delayed motor (its history buffer) and a plastic spring. The repro
// folder's last good state holds every part of the state (mjSTATE_INTEGRATION), and put back
// into the saved model it diverges on the very next step, as the run did.
TEST(CliDivergenceTest, AReproWithDelaysAndPlasticSpringsReproducesItsDivergence) {
#if mjVERSION_HEADER >= 4000000
  TempDir dir;
  WriteFile(dir.File("stiff.xml"), R"(<mujoco model="stiff_plastic">
      <option timestep="0.01" gravity="0 0 0"/><worldbody>
        <body name="mass"><joint name="slider" type="slide" axis="1 0 0" stiffness="1e6"/>
          <geom type="sphere" size="0.05" mass="1"/></body>
        <body name="arm" pos="0 1 0"><joint name="bend" axis="0 1 0" stiffness="10" springyield="1"/>
          <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03" mass="1"/></body></worldbody>
      <actuator><motor name="push" joint="slider" delay="0.03" nsample="3"/></actuator></mujoco>)");
  CommandResult r = RunPlumb(
      "run stiff.xml --set 'ctrl[push]=50' --set 'qpos[slider]=0.01' --set 'plastic[0]=0.4' "
      "--until 10 --repro r",
      dir.path());
  ASSERT_EQ(r.exit_code, 3) << r.err;
  nlohmann::json good = nlohmann::json::parse(ReadFile(dir.File("r/last_good.json")));
  EXPECT_EQ(good["format"], "plumb.state");
  EXPECT_EQ(good["format_version"], 2);
  EXPECT_EQ(good["integration_layout"], "mjSTATE_INTEGRATION");
  Model model = Model::Load(dir.File("r/model.mjb"));
  ASSERT_GT(model->nhistory, 0);
  ASSERT_GT(model->nplastic, 0);
  StateSnapshot state;
  state.integration = good["integration"].get<std::vector<double>>();
  Data data(model);
  Restore(model, data, state);
  EXPECT_EQ(data->time, good["time"].get<double>());
  std::vector<double> history(data->history, data->history + model->nhistory);
  EXPECT_NE(std::count(history.begin(), history.end(), 50.0), 0);  // the delayed ctrl
  mj_step(model.get(), data.get());
  EXPECT_GT(data->warning[mjWARN_BADQACC].number, 0);  // diverged on the same step
  // a state of another model is refused, not pasted
  state.integration.pop_back();
  EXPECT_THROW(Restore(model, data, state), ValueError);
#else
  GTEST_SKIP() << "plastic springs came with MuJoCo 4.0";
#endif
}

TEST(CliDivergenceTest, AnUnwritableReproFolderDoesNotHideTheDivergence) {
  TempDir dir;
  WriteFile(dir.File("stiff.xml"), kStiff);
  CommandResult r = RunPlumb(
      "run stiff.xml --set 'qpos[slider]=0.01' --until 10 --repro stiff.xml/repro", dir.path());
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("diverged at t = 0.04 s"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("joint 'slider'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("no repro folder"), std::string::npos) << r.err;
}

TEST(CliDivergenceTest, TheBadStateIsTheOneMujocoRejected) {
  TempDir dir;
  WriteFile(dir.File("stiff.xml"), kStiff);
  CommandResult r =
      RunPlumb("run stiff.xml --set 'qpos[slider]=0.01' --until 10 --repro r", dir.path());
  ASSERT_EQ(r.exit_code, 3) << r.err;
  nlohmann::json good = nlohmann::json::parse(ReadFile(dir.File("r/last_good.json")));
  nlohmann::json bad = nlohmann::json::parse(ReadFile(dir.File("r/bad.json")));
  // MuJoCo reset the data to qpos0 = 0 at t = 0; the repro keeps what it found bad
  EXPECT_EQ(bad["time"], good["time"]);
  EXPECT_GT(bad["time"].get<double>(), 0.0);
  EXPECT_NE(bad["qpos"][0].get<double>(), 0.0);
  EXPECT_GT(std::fabs(bad["qacc"][0].get<double>()), 1e10);
  EXPECT_NE(bad["note"].get<std::string>().find("reset"), std::string::npos);
  nlohmann::json warnings = nlohmann::json::parse(ReadFile(dir.File("r/warnings.json")));
  EXPECT_EQ(warnings[0]["first_time"], good["time"]);
  // each MuJoCo warning is printed once
  EXPECT_EQ(r.err.find("QACC at DOF 0"), r.err.rfind("QACC at DOF 0")) << r.err;
}

TEST(CliRunTest, AFinalTimeTooLargeToCountIsRefused) {
  TempDir dir;
  CommandResult r = RunPlumb("run " + kPendulum + " --until 1e17 -o t.csv", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--until"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir.File("t.csv")));
}

TEST(CliRunTest, DerivedColumnsAgreeWithTheStateInTheSameRow) {
  TempDir dir;
  WriteFile(dir.File("sensed.xml"), R"(<mujoco model="sensed">
    <worldbody><body name="arm" pos="0 0 1">
      <joint name="elbow" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.05" mass="1"/>
    </body></worldbody>
    <sensor><jointpos name="elbow_pos" joint="elbow"/></sensor></mujoco>)");
  CommandResult r = RunPlumb("run sensed.xml --until 0.1 --every 0.01 --format csv", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream lines(r.out);
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "time,qpos[elbow],qvel[elbow],sensordata[elbow_pos]");
  int rows = 0;
  while (std::getline(lines, line)) {
    std::string q = line.substr(line.find(',') + 1);
    q = q.substr(0, q.find(','));
    EXPECT_EQ(line.substr(line.rfind(',') + 1), q) << line;
    ++rows;
  }
  EXPECT_EQ(rows, 11);
}

TEST(CliSignalTest, InterruptedRunLeavesNoOutputFile) {
  TempDir dir;
  // a long run in the background, interrupted once it has started writing
  std::string command = std::string("'") + PLUMB_CLI + "' run " + kPendulum + kSet +
                        "--until 100000 --every 0.002 --format csv -o traj.csv";
  std::string script = command +
                       " 2>err.txt & pid=$!; "
                       "for i in $(seq 100); do ls -a | grep -q 'traj.csv.tmp' && break; "
                       "sleep 0.05; done; sleep 0.2; kill -INT $pid; wait $pid; echo $? >rc.txt";
  WriteFile(dir.File("interrupt.sh"), script + "\n");
  testing::RunShell("bash interrupt.sh", dir.path());
  EXPECT_EQ(ReadFile(dir.File("rc.txt")), "130\n") << ReadFile(dir.File("err.txt"));
  EXPECT_NE(ReadFile(dir.File("err.txt")).find("interrupted"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir.File("traj.csv")));
  for (const auto& entry : fs::directory_iterator(dir.path())) {
    EXPECT_EQ(entry.path().filename().string().find("traj.csv"), std::string::npos) << entry.path();
  }
}

TEST(CliVerifyTest, PendulumPassesAndPrintsEveryCheck) {
  CommandResult r = RunPlumb("verify " + kPendulum + kSet + "--all");  // PASS rows need --all
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  for (const char* id : {"load", "determinism", "warnings", "convergence", "energy",
                         "analytic.period", "experiment.A", "experiment.B", "experiment.C",
                         "exercise.moon_gravity", "exercise.density", "exercise.radians"}) {
    EXPECT_NE(r.out.find(std::string("PASS  ") + id), std::string::npos) << id << "\n" << r.out;
  }
  EXPECT_NE(r.out.find("0 failed"), std::string::npos);
}

TEST(CliVerifyTest, JsonHasTheDocumentedShape) {
  CommandResult r = RunPlumb("verify " + kPendulum + kSet + "--format json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["model"], kPendulum);
  ASSERT_TRUE(j["checks"].is_array());
  for (const nlohmann::json& c : j["checks"]) {
    for (const char* key :
         {"id", "title", "status", "measured", "reference", "rel_error", "explanation"}) {
      EXPECT_TRUE(c.contains(key)) << key;
    }
  }
  EXPECT_EQ(j["summary"]["fail"], 0);
  EXPECT_GE(j["summary"]["pass"], 12);
  EXPECT_EQ(j["horizon"]["until"], 2.0);
  EXPECT_EQ(j["horizon"]["shortened"], false);
}

TEST(CliVerifyTest, CoarseTimestepExits1) {
  CommandResult r = RunPlumb("verify " + kPendulum + kSet + "--set opt.timestep=0.02");
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.out.find("FAIL  convergence"), std::string::npos) << r.out;
}

TEST(CliConvergeTest, EulerAndRk4Orders) {
  CommandResult euler = RunPlumb("converge " + kPendulum + kSet +
                                 "--metric 'qpos[hinge]@2' "
                                 "--format json");
  ASSERT_EQ(euler.exit_code, 0) << euler.err;
  nlohmann::json e = nlohmann::json::parse(euler.out);
  EXPECT_NEAR(e["observed_order"].get<double>(), 1.0, 0.05);
  EXPECT_EQ(e["levels"].size(), 5u);
  EXPECT_TRUE(e.contains("extrapolated"));
  EXPECT_TRUE(e.contains("recommended_dt"));
  CommandResult rk4 = RunPlumb("converge " + kPendulum + kSet +
                               "--set opt.integrator=RK4 "
                               "--metric 'qpos[hinge]@2' --dt 0.02 --format json");
  nlohmann::json k = nlohmann::json::parse(rk4.out);
  EXPECT_NEAR(k["observed_order"].get<double>(), 4.0, 0.3);
  CommandResult table = RunPlumb("converge " + kPendulum + kSet +
                                 "--set opt.integrator=RK4 "
                                 "--metric 'qpos[hinge]@2'");
  EXPECT_NE(table.out.find("round-off"), std::string::npos) << table.out;
}

TEST(CliConvergeTest, BadMetricIsBadInput) {
  CommandResult r = RunPlumb("converge " + kPendulum + " --metric 'qpos[hinge]@later'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("later"), std::string::npos) << r.err;
}

TEST(CliConvergeTest, BadOptionsNameTheOption) {
  const std::string base =
      "converge " + kPendulum + " --set 'qpos[hinge]=0.7' --metric 'qpos[hinge]@2' ";
  for (const char* option : {"--dt 0", "--dt -1", "--until -1", "--tol inf", "--tol nan",
                             "--tol -0.1", "--halvings 1"}) {
    CommandResult r = RunPlumb(base + option);
    EXPECT_EQ(r.exit_code, 2) << option << ": " << r.err;
    std::string name = std::string(option).substr(0, std::string(option).find(' '));
    EXPECT_NE(r.err.find(name), std::string::npos) << option << ": " << r.err;
  }
}

TEST(CliConvergeTest, AMetricThatCannotBeMeasuredIsBadInputNotDivergence) {
  // at rest the pendulum never crosses its mid-range: no period at any dt
  CommandResult r = RunPlumb("converge " + kPendulum + " --metric 'period(qpos[hinge])'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--metric"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("fewer than twice"), std::string::npos) << r.err;
}

TEST(CliConvergeTest, ADivergedLevelShowsNoValue) {
  TempDir dir;
  WriteFile(dir.File("stiff.xml"), kStiff);
  CommandResult r = RunPlumb(
      "converge stiff.xml --set 'qpos[slider]=0.01' --metric 'qpos[slider]@1' --format json",
      dir.path());
  EXPECT_EQ(r.exit_code, 3) << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["levels"][0]["value"].is_null()) << r.out;
}

TEST(CliVerifyTest, BadOptionsAreRefused) {
  for (const char* option : {"--until 1.003", "--until -1", "--tol -1", "--tol inf"}) {
    CommandResult r = RunPlumb("verify " + kPendulum + " " + option);
    EXPECT_EQ(r.exit_code, 2) << option << ": " << r.err;
    std::string name = std::string(option).substr(0, std::string(option).find(' '));
    EXPECT_NE(r.err.find(name), std::string::npos) << option << ": " << r.err;
  }
}

TEST(CliSweepTest, RangesHitTheirEndpointsAndErrorsNameVary) {
  CommandResult r =
      RunPlumb("sweep " + kPendulum + " --vary 'qpos[hinge]=0.1:2.8:4' --metric 'qpos[hinge]@1'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  for (const char* label : {" 0.1 ", " 1 ", " 1.9 ", " 2.8 "}) {
    EXPECT_NE(r.out.find(label), std::string::npos) << label << "\n" << r.out;
  }
  CommandResult bad = RunPlumb("sweep " + kPendulum +
                               " --vary 'opt.integrator=Euler,Verlet' --metric 'qpos[hinge]@1'");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--vary"), std::string::npos) << bad.err;
  EXPECT_EQ(bad.err.find("--set"), std::string::npos) << bad.err;
  // a varied timestep that does not divide the metric's time is refused before any case runs
  CommandResult mismatch = RunPlumb("sweep " + kPendulum +
                                    " --vary 'opt.timestep=0.002,0.003' --metric 'qpos[hinge]@1'");
  EXPECT_EQ(mismatch.exit_code, 2);
  EXPECT_NE(mismatch.err.find("0.003"), std::string::npos) << mismatch.err;
  EXPECT_TRUE(mismatch.out.empty()) << mismatch.out;
}

TEST(CliSweepTest, UnmeasurableIsNotDiverged) {
  // from rest there is no period to measure: n/a, not diverged
  CommandResult r = RunPlumb("sweep " + kPendulum +
                             " --vary 'dof_damping[hinge]=0,0.1' --metric 'period(qpos[hinge])'");
  EXPECT_NE(r.out.find("n/a"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("diverged"), std::string::npos) << r.out;
}

TEST(CliSweepTest, RowsInCaseOrderWhateverTheThreads) {
  std::string args = "sweep " + kPendulum + kSet +
                     "--vary 'dof_damping[hinge]=0,0.05,1' --vary opt.integrator=Euler,RK4 "
                     "--metric 'qpos[hinge]@2' --format csv --threads ";
  CommandResult one = RunPlumb(args + "1");
  CommandResult two = RunPlumb(args + "2");
  ASSERT_EQ(one.exit_code, 0) << one.err;
  EXPECT_EQ(one.out, two.out);
  EXPECT_EQ(one.out.substr(0, one.out.find('\n')),
            "case,dof_damping[hinge],opt.integrator,qpos[hinge]@2");
  EXPECT_NE(one.out.find("\n2,0.05,0,0.31094769260023"), std::string::npos) << one.out;
}

TEST(CliAuditTest, HumanoidPassesWithSectionsPerLayer) {
  CommandResult r = RunPlumb("audit " + testing::kHumanoid + " --all");  // PASS rows need --all
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  for (const char* section :
       {"== structure", "== inertia", "== actuator", "== contact", "== behaviour", "== warnings"}) {
    EXPECT_NE(r.out.find(section), std::string::npos) << section;
  }
  // a warning alone (a motor with no limits) exits 0, and 1 with --strict
  TempDir dir;
  WriteFile(dir.File("motor.xml"), R"(<mujoco><worldbody>
      <body name="arm" pos="0 0 1"><joint name="shoulder" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.03" mass="1"/></body>
    </worldbody><actuator><motor name="strong" joint="shoulder" gear="50"/></actuator></mujoco>)");
  EXPECT_EQ(RunPlumb("audit motor.xml", dir.path()).exit_code, 0);
  EXPECT_EQ(RunPlumb("audit motor.xml --strict", dir.path()).exit_code, 1);
}

TEST(CliAuditTest, PlantedDefectExits1AndJsonMirrorsTheTable) {
  TempDir dir;
  WriteFile(dir.File("ghost.xml"), R"(<mujoco><worldbody>
      <geom name="floor" type="plane" size="5 5 0.1"/>
      <body name="ghost" pos="0 0 1"><freejoint/>
        <geom type="box" size="0.1 0.1 0.1" contype="0" conaffinity="0"/></body>
    </worldbody></mujoco>)");
  CommandResult r = RunPlumb("audit ghost.xml --format json", dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  bool found = false;
  for (const nlohmann::json& f : j["layers"]["contact"]) {
    found = found || (f["id"] == "contact.free_fall" && f["status"] == "FAIL" &&
                      f["element"].get<std::string>().find("ghost") != std::string::npos);
  }
  EXPECT_TRUE(found) << r.out;
  EXPECT_GE(j["summary"]["fail"], 1);
}

TEST(CliAuditTest, MissingScenarioIsBadInput) {
  CommandResult r = RunPlumb("audit " + kPendulum + " --scenario nowhere.toml");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("nowhere.toml"), std::string::npos) << r.err;
}

TEST(CliRegressionTest, SnapshotThenDiff) {
  TempDir dir;
  CommandResult snap = RunPlumb("snapshot " + kPendulum + " -o p.snap.json", dir.path());
  ASSERT_EQ(snap.exit_code, 0) << snap.err;
  CommandResult same = RunPlumb("diff p.snap.json " + kPendulum, dir.path());
  EXPECT_EQ(same.exit_code, 0) << same.out;
  EXPECT_NE(same.out.find("identical"), std::string::npos);
  CommandResult changed =
      RunPlumb("diff p.snap.json " + kPendulum + " --set 'dof_damping[hinge]=0.1'", dir.path());
  EXPECT_EQ(changed.exit_code, 1);
  EXPECT_NE(changed.out.find("dof_damping[hinge]: 0.05 → 0.1"), std::string::npos) << changed.out;
  nlohmann::json j = nlohmann::json::parse(
      RunPlumb("diff p.snap.json " + kPendulum + " --set 'dof_damping[hinge]=0.1' --format json",
               dir.path())
          .out);
  EXPECT_FALSE(j["identical"].get<bool>());
  EXPECT_EQ(j["changes"][0]["what"], "dof_damping[hinge]: 0.05 → 0.1");
}

// The upgrade question, "is it safe to move this model to another MuJoCo?": a snapshot
// taken under MuJoCo 3.11.0 (tests/data) diffed on every leg says which MuJoCo wrote it,
// finds the same structure, parameters and trajectory within cross-version round-off, and
// still names a real change of behaviour.
TEST(CliRegressionTest, SnapshotFromAnotherMujocoDiffsWithinRoundOff) {
  std::string snap = testing::kSourceDir + "/tests/data/pendulum-mujoco-3.11.0.snap.json";
  CommandResult same = RunPlumb("diff " + snap + " " + kPendulum + " --tol 1e-9");
  EXPECT_EQ(same.exit_code, 0) << same.out << same.err;
  EXPECT_NE(same.out.find("identical"), std::string::npos) << same.out;
  if (testing::CompiledMujocoVersion() != "3.11.0") {
    EXPECT_NE((same.out + same.err).find("written with MuJoCo 3.11.0"), std::string::npos)
        << same.out << same.err;
  }
  TempDir dir;
  std::ifstream in(kPendulum);
  std::string xml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string from = "damping=\"0.05\"";
  std::size_t at = xml.find(from);
  ASSERT_NE(at, std::string::npos);
  WriteFile(dir.File("damped.xml"), xml.replace(at, from.size(), "damping=\"0.06\""));
  CommandResult changed = RunPlumb("diff " + snap + " " + dir.File("damped.xml") + " --tol 1e-9");
  EXPECT_EQ(changed.exit_code, 1) << changed.out << changed.err;
  EXPECT_NE(changed.out.find("dof_damping[hinge]: 0.05"), std::string::npos) << changed.out;
}

TEST(CliRegressionTest, BadSnapshotsAndPathsAreBadInput) {
  TempDir dir;
  WriteFile(dir.File("junk.json"), "{ nope");
  CommandResult junk = RunPlumb("diff junk.json " + kPendulum, dir.path());
  EXPECT_EQ(junk.exit_code, 2);
  EXPECT_NE(junk.err.find("junk.json"), std::string::npos) << junk.err;
  CommandResult missing = RunPlumb("diff none.json " + kPendulum, dir.path());
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("none.json"), std::string::npos) << missing.err;
  CommandResult unwritable = RunPlumb("snapshot " + kPendulum + " -o /nonexistent-dir/s.json");
  EXPECT_EQ(unwritable.exit_code, 2);
  EXPECT_FALSE(fs::exists("/nonexistent-dir/s.json"));
  // a damaged snapshot: exit 2 naming the file and the entry, never a crash
  ASSERT_EQ(RunPlumb("snapshot " + kPendulum + " -o s.json", dir.path()).exit_code, 0);
  nlohmann::json j = nlohmann::json::parse(ReadFile(dir.File("s.json")));
  j["trajectory"]["qpos"][3] = nlohmann::json::array();
  WriteFile(dir.File("s.json"), j.dump());
  CommandResult damaged = RunPlumb("diff s.json " + kPendulum, dir.path());
  EXPECT_EQ(damaged.exit_code, 2) << damaged.err;
  EXPECT_NE(damaged.err.find("s.json: trajectory.qpos[3]: expected an array of 1 numbers"),
            std::string::npos)
      << damaged.err;
  // a model whose golden trajectory diverges gets no snapshot: exit 3
  WriteFile(dir.File("stiff.xml"), R"(<mujoco><option timestep="0.01" gravity="0 0 0"/>
    <worldbody><body><joint name="slider" type="slide" axis="1 0 0" stiffness="1e6" ref="0.01"/>
    <geom type="sphere" size="0.05" mass="1"/></body></worldbody></mujoco>)");
  CommandResult diverged = RunPlumb("snapshot stiff.xml -o stiff.snap.json", dir.path());
  EXPECT_EQ(diverged.exit_code, 3) << diverged.err;
  EXPECT_NE(diverged.err.find("diverges"), std::string::npos) << diverged.err;
  EXPECT_FALSE(fs::exists(dir.File("stiff.snap.json")));
}

TEST(CliUsageTest, HelpShowsExamplesAndExitCodes) {
  CommandResult r = RunPlumb("run --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("plumb run models/pendulum.xml"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Exit codes"), std::string::npos) << r.out;
  EXPECT_EQ(RunPlumb("").exit_code, 2);
  EXPECT_EQ(RunPlumb("frobnicate").exit_code, 2);
  EXPECT_NE(RunPlumb("--version").out.find("MuJoCo " + testing::CompiledMujocoVersion()),
            std::string::npos);
}

// plumb help prints the manual's pages as docs/ holds them, embedded at build time
TEST(CliHelpTest, PrintsACommandsPageExactly) {
  CommandResult r = RunPlumb("help verify");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, ReadFile(testing::kSourceDir + "/docs/verify.md"));
}

TEST(CliHelpTest, ListsThePagesWithoutAnArgument) {
  CommandResult r = RunPlumb("help");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("  verify\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  exit-codes\n"), std::string::npos) << r.out;
}

TEST(CliHelpTest, EveryCommandHasAPage) {
  for (const char* command :
       {"verify", "audit", "snapshot", "diff", "run", "inspect", "converge", "sweep", "rollout",
        "render", "bridge", "replay", "identify", "results", "merge"}) {
    CommandResult r = RunPlumb(std::string("help ") + command);
    EXPECT_EQ(r.exit_code, 0) << command << ": " << r.err;
    EXPECT_EQ(r.out, ReadFile(testing::kSourceDir + "/docs/" + command + ".md")) << command;
  }
}

TEST(CliHelpTest, AnUnknownPageIsBadInputNamingTheKnownOnes) {
  CommandResult r = RunPlumb("help nosuch");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("no page 'nosuch'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("verify"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("merge"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace plumb
