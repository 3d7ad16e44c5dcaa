#include "plumb/model.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <type_traits>

#include "fixture.h"
#include "plumb/error.h"

namespace plumb {
namespace {

using testing::kPendulum;
using testing::MujocoTest;
using testing::TempDir;
using testing::WriteFile;

static_assert(!std::is_copy_constructible_v<Model> && std::is_nothrow_move_constructible_v<Model>);
static_assert(!std::is_copy_constructible_v<Data> && std::is_nothrow_move_constructible_v<Data>);

using ModelTest = MujocoTest;

TEST_F(ModelTest, LoadsTheChapterPendulum) {
  Model model = Model::Load(kPendulum);
  EXPECT_EQ(model->nbody, 2);
  EXPECT_EQ(model->njnt, 1);
  EXPECT_EQ(model->nq, 1);
  EXPECT_EQ(model->nv, 1);
  EXPECT_EQ(model->nu, 0);
  EXPECT_EQ(model->opt.timestep, 0.002);
  EXPECT_EQ(model.file(), kPendulum);
  EXPECT_TRUE(model.compile_warnings().empty()) << model.compile_warnings();
}

TEST_F(ModelTest, MissingFileNamesTheFile) {
  try {
    Model::Load("no/such/model.xml");
    FAIL() << "expected LoadError";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("no/such/model.xml"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("No such file"), std::string::npos) << e.what();
  }
}

TEST_F(ModelTest, MalformedXmlKeepsTheParserLine) {
  TempDir dir;
  WriteFile(dir.File("bad.xml"), "<mujoco>\n<worldbody>\n<body>\n<geom size=\"0.1\"\n</body>\n");
  try {
    Model::Load(dir.File("bad.xml"));
    FAIL() << "expected LoadError";
  } catch (const LoadError& e) {
    std::string what = e.what();
    EXPECT_NE(what.find(dir.File("bad.xml")), std::string::npos) << what;
    EXPECT_NE(what.find("Line number=4"), std::string::npos) << what;
  }
}

TEST_F(ModelTest, NegativeGeomSizeKeepsObjectAndLine) {
  // the chapter's exercise 5: the whole compiler message reaches the user
  TempDir dir;
  WriteFile(
      dir.File("neg.xml"),
      "<mujoco>\n<worldbody>\n<body name=\"b\">\n<joint name=\"j\"/>\n"
      "<geom name=\"rod\" type=\"sphere\" size=\"-0.1\"/>\n</body>\n</worldbody>\n</mujoco>\n");
  try {
    Model::Load(dir.File("neg.xml"));
    FAIL() << "expected LoadError";
  } catch (const LoadError& e) {
    std::string what = e.what();
    EXPECT_NE(what.find("rod"), std::string::npos) << what;
    EXPECT_TRUE(testing::NamesLine(what, 5)) << what;
    EXPECT_NE(what.find("size"), std::string::npos) << what;
  }
}

TEST_F(ModelTest, RangeWithoutLimitedExplainsAutolimits) {
  const char* xml = R"(<mujoco><worldbody><body name="b">
      <joint name="j" type="hinge" range="-1 1"/><geom size="0.1"/>
    </body></worldbody></mujoco>)";
  if (mjVERSION_HEADER >= 300) {
    // MuJoCo 3 turns autolimits on by default: the range limits the joint
    Model model = Model::FromXmlString(xml);
    EXPECT_EQ(model->jnt_limited[0], 1);
    return;
  }
  try {
    Model::FromXmlString(xml, "limits.xml");
    FAIL() << "expected LoadError";
  } catch (const LoadError& e) {
    EXPECT_NE(e.hint().find("autolimits"), std::string::npos) << e.hint();
    EXPECT_NE(e.hint().find("MuJoCo 3"), std::string::npos) << e.hint();
  }
  // and the advice works
  std::string fixed = std::string(xml).replace(8, 0, "<compiler autolimits=\"true\"/>");
  Model model = Model::FromXmlString(fixed);
  EXPECT_EQ(model->jnt_limited[0], 1);
}

// A misspelled attribute in a file the model includes: MuJoCo says "line 0" of no file; plumb
// names the included file and the attribute's line, and the attribute meant.
TEST_F(ModelTest, ASchemaErrorInAnIncludedFileNamesThatFileItsLineAndTheAttributeMeant) {
  TempDir dir;
  const std::string top = dir.path() + "/robot.xml", part = dir.path() + "/leg.xml";
  WriteFile(top, "<mujoco>\n  <worldbody>\n    <include file=\"leg.xml\"/>\n  </worldbody>\n"
                 "</mujoco>\n");
  WriteFile(part, "<mujoco>\n  <body name=\"leg\">\n    <joint type=\"hinge\"/>\n"
                  "    <geom type=\"sphere\" sise=\"0.1\"/>\n  </body>\n</mujoco>\n");
  try {
    Model::Load(top);
    FAIL() << "expected LoadError";
  } catch (const LoadError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'sise' stands on line 4 of '" + part + "' (included by '" + top + "')"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("did you mean: size?"), std::string::npos) << what;
  }
  // the model's own file: its line, and the same suggestion
  WriteFile(top, "<mujoco>\n  <worldbody>\n    <geom type=\"sphere\" sise=\"0.1\"/>\n"
                 "  </worldbody>\n</mujoco>\n");
  try {
    Model::Load(top);
    FAIL() << "expected LoadError";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("'sise' stands on line 3 of '" + top +
                                         "'; did you mean: size?"),
              std::string::npos)
        << e.what();
  }
}

// dexterity's Shadow hand keeps its servos in a file it includes: a misspelled gain there is
// named in that file, at its line, with the gain meant.
TEST_F(ModelTest, AMisspelledGainInTheShadowHandsIncludedActuatorsIsFoundThere) {
  namespace fs = std::filesystem;
  const std::string hand =
      testing::RequireCorpusModel("dexterity-0.0.15/mjcf/shadow_hand_series_e.xml");
  if (hand.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  const fs::path folder = fs::path(hand).parent_path();
  TempDir dir;
  const fs::path copy = fs::path(dir.path()) / folder.filename();
  fs::create_directories(copy);
  for (const auto& entry : fs::directory_iterator(folder.parent_path())) {  // meshes beside it
    if (entry.path() != folder) fs::create_symlink(entry.path(), dir.File(entry.path().filename()));
  }
  fs::create_symlink(hand, copy / "shadow_hand_series_e.xml");
  const std::string included = "shadow_hand_position_actuators.xml";
  std::string actuators = testing::ReadFile((folder / included).string());
  actuators.replace(actuators.find(R"(kp="20")"), 2, "kpp");  // line 25: A_WRJ1
  WriteFile((copy / included).string(), actuators);
  try {
    Model::Load((copy / "shadow_hand_series_e.xml").string());
    FAIL() << "expected LoadError";
  } catch (const LoadError& e) {
    const std::string where = "'kpp' stands on line 25 of '" + (copy / included).string() +
                              "' (included by '";
    EXPECT_NE(std::string(e.what()).find(where), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("did you mean: kp?"), std::string::npos) << e.what();
  }
}

// A flex model written for 3.x (MuJoCo 3.12's own samples set <contact internal>, which 4.0
// removed): the error says what changed, which build loads it, and the advice works
TEST_F(ModelTest, ASchemaRemovalBetweenReleasesIsExplained) {
#if mjVERSION_HEADER >= 4000000
  const std::string xml = R"(<mujoco><worldbody>
      <flexcomp name="cloth" type="grid" count="4 4 1" spacing=".1 .1 .1" radius=".01" dim="2">
        <contact internal="false" selfcollide="none"/><edge equality="true"/></flexcomp>
      </worldbody></mujoco>)";
  try {
    Model::FromXmlString(xml, "cloth.xml");
    FAIL() << "expected LoadError";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("unrecognized attribute: 'internal'"), std::string::npos);
    EXPECT_NE(e.hint().find("MuJoCo 4.0 removed the internal attribute"), std::string::npos)
        << e.hint();
    EXPECT_NE(e.hint().find("MuJoCo 3.11.0 loads the model"), std::string::npos) << e.hint();
  }
  std::string fixed = xml;
  fixed.erase(fixed.find(R"( internal="false")"), std::string(R"( internal="false")").size());
  EXPECT_GT(Model::FromXmlString(fixed)->nflex, 0);
#else
  GTEST_SKIP() << "MuJoCo before 4.0 accepts it";
#endif
}

TEST_F(ModelTest, UnrelatedLoadErrorsGetNoAutolimitsHint) {
  try {
    Model::FromXmlString("<mujoco><worldbody><geom size=\"-1\"/></worldbody></mujoco>");
    FAIL() << "expected LoadError";
  } catch (const LoadError& e) {
    EXPECT_TRUE(e.hint().empty()) << e.hint();
  }
}

// mjcb_control runs inside mj_forward, so an error raised there unwinds through
// MuJoCo's C frames: the case plumb's error handler must survive.
void ControlThatFails(const mjModel*, mjData*) { mju_error("deliberate failure in a callback"); }

TEST_F(ModelTest, MujocoErrorInsideStepBecomesAnExceptionNotExit) {
  Model model = Model::Load(kPendulum);
  Data data(model);
  mjcb_control = ControlThatFails;
  EXPECT_THROW(data.Step(), MujocoError);
  mjcb_control = nullptr;
  // the data is usable again after a reset
  data.Reset();
  data->qpos[0] = 0.7;
  data.Step();
  EXPECT_GT(data->time, 0);
}

TEST_F(ModelTest, MujocoErrorMessageIsKept) {
  InstallMujocoHandlers();
  try {
    mju_error("something specific");
    FAIL() << "mju_error returned";
  } catch (const MujocoError& e) {
    EXPECT_NE(std::string(e.what()).find("something specific"), std::string::npos);
  }
}

TEST(ModelWarningTest, WarningsAreCollectedNotPrinted) {
  InstallMujocoHandlers();
  TakeMujocoWarnings();
  ::testing::internal::CaptureStdout();
  mju_warning("a warning for the test");
  EXPECT_EQ(::testing::internal::GetCapturedStdout(), "");
  std::vector<std::string> warnings = TakeMujocoWarnings();
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], "a warning for the test");
  EXPECT_TRUE(TakeMujocoWarnings().empty());
}

// MuJoCo's first-party plugins ship as libraries beside libmujoco (bin/mujoco_plugin of a
// release folder); plumb loads them, so a model using the PID actuator plugin compiles
// and its servo pulls the slider towards the target.
TEST_F(ModelTest, FirstPartyPluginsLoad) {
  if (mjVERSION_HEADER < 300) GTEST_SKIP() << "MuJoCo 2.x has no plugins";
  ASSERT_FALSE(MujocoPluginPath().empty()) << "no plugin folder beside " << MujocoLibraryPath();
  Model model = Model::Load(testing::kSourceDir + "/tests/models/pid_servo.xml");
  Data data(model);
  data->ctrl[0] = 0.5;
  for (int i = 0; i < 1000; ++i) mj_step(model.get(), data.get());
  EXPECT_NEAR(data->qpos[0], 0.5, 0.1);
}

TEST_F(ModelTest, VersionsAndLibraryAreReported) {
  EXPECT_EQ(CompiledMujocoVersion(), MujocoVersion());  // the start-up check holds
  EXPECT_NE(MujocoLibraryPath().find("libmujoco"), std::string::npos) << MujocoLibraryPath();
}

TEST_F(ModelTest, CloneIsIndependent) {
  Model model = Model::Load(kPendulum);
  Model copy = model.Clone();
  copy.get_mutable()->dof_damping[0] = 1.0;
  EXPECT_EQ(model->dof_damping[0], 0.05);
  EXPECT_EQ(copy->dof_damping[0], 1.0);
}

TEST_F(ModelTest, DataCloneCopiesTheState) {
  Model model = Model::Load(kPendulum);
  Data data(model);
  data->qpos[0] = 0.3;
  data.Step();
  Data copy = data.Clone();
  EXPECT_EQ(copy->qpos[0], data->qpos[0]);
  EXPECT_EQ(copy->time, data->time);
  copy.Step();
  EXPECT_NE(copy->time, data->time);
}

TEST_F(ModelTest, BinaryRoundTripKeepsEdits) {
  TempDir dir;
  Model model = Model::Load(kPendulum);
  model.get_mutable()->body_mass[1] = 2.5;
  model.SaveBinary(dir.File("p.mjb"));
  Model loaded = Model::Load(dir.File("p.mjb"));
  EXPECT_EQ(loaded->nq, 1);
  EXPECT_EQ(loaded->body_mass[1], 2.5);
}

TEST_F(ModelTest, CorruptBinaryIsALoadError) {
  TempDir dir;
  WriteFile(dir.File("junk.mjb"), "not a model");
  EXPECT_THROW(Model::Load(dir.File("junk.mjb")), LoadError);
}

TEST_F(ModelTest, SaveXmlWritesThisModelEvenAfterAnotherLoad) {
  TempDir dir;
  Model pendulum = Model::Load(kPendulum);
  pendulum.get_mutable()->dof_damping[0] = 0.25;
  Model other = Model::FromXmlString(
      "<mujoco model=\"other\"><worldbody><geom size=\"1\"/></worldbody></mujoco>");
  pendulum.SaveXml(dir.File("saved.xml"));
  Model reloaded = Model::Load(dir.File("saved.xml"));
  EXPECT_EQ(reloaded->njnt, 1);
  EXPECT_EQ(reloaded->dof_damping[0], 0.25);
}

TEST_F(ModelTest, SaveToUnwritablePathIsAnIoError) {
  Model model = Model::Load(kPendulum);
  EXPECT_THROW(model.SaveBinary("/nonexistent-dir/p.mjb"), IoError);
  EXPECT_THROW(model.SaveXml("/nonexistent-dir/p.xml"), IoError);
}

}  // namespace
}  // namespace plumb
