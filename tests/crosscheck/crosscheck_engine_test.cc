// plumb crosscheck against the real engines on the CPU: MuJoCo Warp and MJX in their pinned
// environments (made from PyPI on first use, as a user's first crosscheck makes them). The
// pendulum and a box resting on a plane agree; the planted differences are each found by the
// right check and named by element; a killed adapter leaves no output and no process.

#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <thread>

#include "fixture.h"
#include "plumb/crosscheck.h"
#include "plumb/keyframe.h"
#include "plumb/path.h"
#include "plumb/result_json.h"

namespace plumb {
namespace {

using testing::kSourceDir;

std::string Scene(const std::string& name) {
  return kSourceDir + "/tests/models/crosscheck/" + name + ".xml";
}

// The MuJoCo the engines' locks pin (engines/requirements-*.txt): the checks expect the same
// MuJoCo on both sides, so the other legs of the version matrix leave these tests out.
#define SKIP_UNLESS_ENGINES_MUJOCO()                                                   \
  if (std::string(mj_versionString()) != "4.0.1") {                                    \
    GTEST_SKIP() << "the engines run MuJoCo 4.0.1, this build " << mj_versionString(); \
  }

CrosscheckReport Check(const std::string& engine, const std::string& path,
                       const std::vector<std::string>& sets = {},
                       const std::vector<std::string>& checks = {}, const std::string& key = "") {
  Model model = Model::Load(path);
  CrosscheckOptions o;
  o.engine = engine;
  o.setup = ReadyEngineSetup(engine);
  o.until = 0.5;
  o.worlds = 8;
  if (!key.empty()) o.sets = KeyframeAssignments(model, key);
  for (const std::string& s : sets) o.sets.push_back(ParseAssignment(model, s));
  if (!checks.empty()) o.checks = checks;
  return Crosscheck(model, o);
}

const CheckRow* Find(const CrosscheckReport& r, const std::string& id) {
  for (const CheckRow& row : r.rows) {
    if (row.id == id) return &row;
  }
  return nullptr;
}

std::string Rows(const CrosscheckReport& r) {
  std::string text;
  for (const CheckRow& row : r.rows) {
    text += std::string(CheckStatusName(row.status)) + " " + row.id + " " + row.About() + ": " +
            row.measured_text + " | " + row.explanation + "\n";
  }
  return text;
}

TEST(CrosscheckWarpTest, ThePendulumAgreesInAllFiveChecks) {
  SKIP_UNLESS_ENGINES_MUJOCO();
  CrosscheckReport r = Check("warp", testing::kPendulum, {"qpos[hinge]=0.7"});
  EXPECT_FALSE(r.failed()) << Rows(r);
  EXPECT_EQ(r.engine.engine, "warp");
  EXPECT_EQ(r.engine.mujoco_version, r.mujoco_version);  // the same MuJoCo on both sides
  EXPECT_EQ(r.engine.precision, "float32");
  EXPECT_EQ(r.Count(CheckStatus::kWarn), 0) << Rows(r);
  for (const char* id :
       {"support.versions", "stages.kinematics", "stages.mass_matrix", "stages.accelerations",
        "stages.next_state", "trajectory", "throughput"}) {
    const CheckRow* row = Find(r, id);
    ASSERT_NE(row, nullptr) << id << "\n" << Rows(r);
    EXPECT_EQ(row->status, CheckStatus::kPass) << id << "\n" << Rows(r);
  }
  // nothing randomized: the statistics of identical worlds say so rather than PASS
  ASSERT_NE(Find(r, "statistics"), nullptr) << Rows(r);
  EXPECT_EQ(Find(r, "statistics")->status, CheckStatus::kSkip) << Rows(r);
  // the pendulum never parts from CPU MuJoCo within the run, in the engine or the baseline
  ASSERT_EQ(r.divergence.size(), 1u);
  EXPECT_EQ(r.divergence[0].signal, "qpos[hinge]");
  EXPECT_EQ(r.divergence[0].engine.size(), 4u);
  EXPECT_GT(r.throughput.engine_steps_per_second, 0);
  EXPECT_GT(r.throughput.cpu_steps_per_second, 0);
  EXPECT_NE(r.model_transfer.find("edit"), std::string::npos) << r.model_transfer;
}

TEST(CrosscheckWarpTest, RandomizedWorldsRunAsTheSameWorldsInTheEngine) {
  SKIP_UNLESS_ENGINES_MUJOCO();
  Model model = Model::Load(testing::kPendulum);
  CrosscheckOptions o;
  o.setup = ReadyEngineSetup("warp");
  o.until = 1;
  o.worlds = 16;
  o.checks = {"statistics"};
  o.sets = {ParseAssignment(model, "qpos[hinge]=0.7")};
  // parameters (a mass, whose derived constants go over too), the start and the controls'
  // noise all differ from world to world
  for (const char* r :
       {"dof_damping[hinge]=U(0,0.5)", "body_mass[link]=*U(0.5,1.5)", "qpos[hinge]=U(0.3,1.2)"}) {
    o.randomize.push_back(ParseRandomization(model, r));
  }
  o.ctrl_noise = 0.1;
  CrosscheckReport r = Crosscheck(model, o);
  ASSERT_EQ(r.rows.size(), 1u) << Rows(r);  // nothing the engine could not vary
  const CheckRow& row = r.rows[0];
  EXPECT_EQ(row.status, CheckStatus::kPass) << Rows(r);
  // the worlds spread (0.26 rad at 1 s), and each engine world lands on its CPU twin
  EXPECT_GT(row.reference.value, 0.02);
  EXPECT_LT(std::abs(row.measured.value), 1e-5) << row.measured_text;
}

TEST(CrosscheckWarpTest, ABoxRestingOnAPlaneAgreesContactByContact) {
  SKIP_UNLESS_ENGINES_MUJOCO();
  CrosscheckReport r =
      Check("warp", Scene("box_on_plane"), {}, {"support", "stages", "trajectory"});
  EXPECT_FALSE(r.failed()) << Rows(r);
  for (const char* id : {"stages.contacts", "stages.constraint_rows", "stages.constraint_forces"}) {
    ASSERT_NE(Find(r, id), nullptr);
    EXPECT_EQ(Find(r, id)->status, CheckStatus::kPass) << id << "\n" << Rows(r);
  }
}

TEST(CrosscheckWarpTest, ARefusedSolverIsNamedAndTheOtherChecksSkip) {
  SKIP_UNLESS_ENGINES_MUJOCO();
  CrosscheckReport r = Check("warp", Scene("pgs_solver"));
  const CheckRow* refused = Find(r, "support.refused");
  ASSERT_NE(refused, nullptr) << Rows(r);
  EXPECT_EQ(refused->status, CheckStatus::kFail);
  EXPECT_EQ(ElementLabel(refused->element), "option 'solver'");
  EXPECT_NE(refused->measured_text.find("mjSOL_PGS"), std::string::npos) << refused->measured_text;
  for (const char* id : {"stages", "trajectory", "statistics", "throughput"}) {
    ASSERT_NE(Find(r, id), nullptr) << id;
    EXPECT_EQ(Find(r, id)->status, CheckStatus::kSkip);
  }
}

TEST(CrosscheckWarpTest, AnIgnoredActuatorGroupSettingIsNamedAndFoundInTheAccelerations) {
  SKIP_UNLESS_ENGINES_MUJOCO();
  CrosscheckReport r = Check("warp", Scene("actuator_group_disabled"), {}, {}, "pushing");
  const CheckRow* support = Find(r, "support.actuator_group");
  ASSERT_NE(support, nullptr) << Rows(r);
  EXPECT_EQ(support->status, CheckStatus::kWarn);
  EXPECT_EQ(ElementLabel(support->element), "actuator 'push' (id 0)");
  // the first stage that disagrees is the accelerations, at the slider's joint
  const CheckRow* acc = Find(r, "stages.accelerations");
  ASSERT_NE(acc, nullptr);
  EXPECT_EQ(acc->status, CheckStatus::kFail) << Rows(r);
  EXPECT_EQ(acc->element.name, "slide");
  EXPECT_EQ(Find(r, "stages.kinematics")->status, CheckStatus::kPass);
  // the trajectory parts long before rounding would part it, and the statistics see it
  EXPECT_EQ(Find(r, "trajectory")->status, CheckStatus::kFail) << Rows(r);
  EXPECT_EQ(Find(r, "trajectory")->element.name, "slide");
  EXPECT_EQ(Find(r, "statistics")->status, CheckStatus::kFail) << Rows(r);
}

TEST(CrosscheckWarpTest, ABoxBoxContactSetThatDiffersIsNamedByGeomPair) {
  SKIP_UNLESS_ENGINES_MUJOCO();
  CrosscheckReport r = Check("warp", Scene("box_on_box"), {}, {"support", "stages"});
  const CheckRow* support = Find(r, "support.box_box");
  ASSERT_NE(support, nullptr) << Rows(r);
  EXPECT_EQ(support->status, CheckStatus::kWarn);
  const CheckRow* contacts = Find(r, "stages.contacts");
  ASSERT_NE(contacts, nullptr);
  EXPECT_EQ(contacts->status, CheckStatus::kFail) << Rows(r);
  EXPECT_EQ(contacts->subject, "geom 'bottom' (id 0) / geom 'top' (id 1)");
  EXPECT_NE(contacts->measured_text.find("8 contact(s) on CPU MuJoCo, 4 on the engine"),
            std::string::npos)
      << contacts->measured_text;
  EXPECT_EQ(Find(r, "stages.kinematics")->status, CheckStatus::kPass);
}

TEST(CrosscheckMjxTest, AnIgnoredNoslipSolverIsNamedAndFoundInTheStages) {
  SKIP_UNLESS_ENGINES_MUJOCO();
  CrosscheckReport r = Check("mjx", Scene("noslip"), {}, {"support", "stages"});
  EXPECT_EQ(r.engine.engine, "mjx");
  const CheckRow* support = Find(r, "support.noslip");
  ASSERT_NE(support, nullptr) << Rows(r);
  EXPECT_EQ(support->status, CheckStatus::kWarn);
  EXPECT_EQ(ElementLabel(support->element), "option 'noslip_iterations'");
  EXPECT_TRUE(r.failed()) << Rows(r);
  // contacts themselves agree: the difference begins after the solver
  EXPECT_EQ(Find(r, "stages.contacts")->status, CheckStatus::kPass) << Rows(r);
  // without noslip, MJX's constraint forces and accelerations are CPU MuJoCo's on the same box
  CrosscheckReport plain =
      Check("mjx", Scene("noslip"), {"opt.noslip_iterations=0"}, {"support", "stages"});
  EXPECT_EQ(Find(plain, "support.noslip"), nullptr);
  EXPECT_EQ(Find(plain, "stages.constraint_forces")->status, CheckStatus::kPass) << Rows(plain);
  EXPECT_EQ(Find(plain, "stages.accelerations")->status, CheckStatus::kPass) << Rows(plain);
}

TEST(CrosscheckMjxTest, ThePendulumAgreesInAllFiveChecks) {
  SKIP_UNLESS_ENGINES_MUJOCO();
  CrosscheckReport r = Check("mjx", testing::kPendulum, {"qpos[hinge]=0.7"});
  EXPECT_FALSE(r.failed()) << Rows(r);
  EXPECT_EQ(r.Count(CheckStatus::kWarn), 0) << Rows(r);
  EXPECT_EQ(Find(r, "trajectory")->status, CheckStatus::kPass);
}

TEST(CrosscheckCliTest, JsonReportAndExitCodes) {
  SKIP_UNLESS_ENGINES_MUJOCO();
  ReadyEngineSetup("warp");
  testing::TempDir dir;
  testing::CommandResult ok =
      testing::RunPlumb("crosscheck '" + testing::kPendulum +
                        "' --set 'qpos[hinge]=0.7' --until 0.2 --worlds 4 "
                        "--check stages --check trajectory --format json --report '" +
                        dir.File("r.html") + "'");
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  nlohmann::json j = nlohmann::json::parse(ok.out);
  EXPECT_EQ(j["engine"]["engine"], "warp");
  EXPECT_EQ(j["summary"]["fail"], 0);
  EXPECT_TRUE(std::filesystem::exists(dir.File("r.html")));
  testing::CommandResult refused =
      testing::RunPlumb("crosscheck '" + Scene("pgs_solver") + "' --check support");
  EXPECT_EQ(refused.exit_code, 1) << refused.err;
  EXPECT_NE(refused.out.find("support.refused"), std::string::npos) << refused.out;
  testing::CommandResult unknown =
      testing::RunPlumb("crosscheck '" + testing::kPendulum + "' --engine physx");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("--engine"), std::string::npos) << unknown.err;
}

TEST(CrosscheckCliTest, NoEnvironmentAndNoNetworkIsExitFiveNamingWhatIsMissing) {
  SKIP_UNLESS_ENGINES_MUJOCO();
  testing::TempDir dir;
  // an empty folder for environments and a package index nobody answers on
  testing::CommandResult r =
      testing::RunShell("PLUMB_ENGINE_VENVS='" + dir.path() +
                        "' PIP_INDEX_URL=http://127.0.0.1:9/simple "
                        "PIP_RETRIES=0 PIP_TIMEOUT=2 '" +
                        PLUMB_CLI + "' crosscheck '" + testing::kPendulum + "'");
  EXPECT_EQ(r.exit_code, 5) << r.out << r.err;
  EXPECT_NE(r.err.find("plumb crosscheck --setup --engine warp"), std::string::npos) << r.err;
}

// The adapter's pid, once plumb has started it (a child of `parent` running adapter.py).
pid_t AdapterOf(pid_t parent) {
  for (const auto& entry : std::filesystem::directory_iterator("/proc")) {
    const std::string pid = entry.path().filename();
    if (pid.find_first_not_of("0123456789") != std::string::npos) continue;
    const std::string stat = testing::ReadFile(entry.path().string() + "/stat");
    const std::string cmd = testing::ReadFile(entry.path().string() + "/cmdline");
    const std::size_t close = stat.rfind(')');
    if (close == std::string::npos || cmd.find("adapter.py") == std::string::npos) continue;
    std::istringstream rest(stat.substr(close + 2));
    std::string state;
    long ppid = 0;
    rest >> state >> ppid;
    if (ppid == parent) return static_cast<pid_t>(std::stol(pid));
  }
  return -1;
}

TEST(CrosscheckCliTest, AKilledAdapterIsExitSixWithNoReportAndNoProcessLeft) {
  SKIP_UNLESS_ENGINES_MUJOCO();
  ReadyEngineSetup("warp");
  testing::TempDir dir;
  const std::string report = dir.File("r.html");
  const std::string cmd = std::string(PLUMB_CLI) + " crosscheck " + testing::kPendulum +
                          " --until 2 --worlds 64 --report " + report + " 2>" + dir.File("err");
  FILE* plumb = popen(("exec " + cmd).c_str(), "r");
  ASSERT_NE(plumb, nullptr);
  // popen's child is a shell that exec'd plumb: find plumb's adapter
  pid_t adapter = -1;
  for (int i = 0; i < 600 && adapter < 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    for (const auto& entry : std::filesystem::directory_iterator("/proc")) {
      const std::string pid = entry.path().filename();
      if (pid.find_first_not_of("0123456789") != std::string::npos) continue;
      if (testing::ReadFile(entry.path().string() + "/cmdline").find(report) == std::string::npos) {
        continue;
      }
      adapter = AdapterOf(static_cast<pid_t>(std::stol(pid)));
      if (adapter > 0) break;
    }
  }
  ASSERT_GT(adapter, 0) << "plumb never started its adapter";
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // mid-run
  ASSERT_EQ(kill(adapter, SIGKILL), 0);
  const int status = pclose(plumb);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 6) << testing::ReadFile(dir.File("err"));
  EXPECT_NE(testing::ReadFile(dir.File("err")).find("adapter"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(report));  // no half-written report
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    EXPECT_EQ(entry.path().filename(), "err") << "left behind: " << entry.path();
  }
  EXPECT_NE(kill(adapter, 0), 0);  // gone
}

}  // namespace
}  // namespace plumb
