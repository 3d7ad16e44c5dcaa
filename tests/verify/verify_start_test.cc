// Verify drives each robot the way its authors use it (issue 45): every run starts at the
// reference pose (keyframe "home", else "test", else qpos0) with the caller's assignments on
// top, the report says which, and a start outside a joint's range is a row of its own; the
// energy check honours the model's disable flags. On real robots of the corpus.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "corpus_robots.h"
#include "fixture.h"
#include "plumb/check_table.h"
#include "plumb/error.h"
#include "plumb/keyframe.h"
#include "plumb/result_json.h"
#include "plumb/verify.h"
#include "verify/verify_rows.h"

namespace plumb {
namespace {

using testing::Find;

// The model's qpos0, as a whole qpos assignment: the start MuJoCo's own reset gives.
Assignment Qpos0(const Model& model) {
  std::vector<std::string> values;
  for (int i = 0; i < model->nq; ++i) values.push_back(fmt::format("{:.17g}", model->qpos0[i]));
  return QposAssignment(model, fmt::format("{}", fmt::join(values, " ")));
}

class VerifyStartTest : public testing::MujocoTest {};

// The Panda's qpos0 puts joint4 at 0, outside its range [-3.07, -0.07]: its authors start it
// from keyframe 'home'. Verify does too, and says so in the report, its table and its JSON.
TEST_F(VerifyStartTest, PandaStartsFromHomeAndSaysSo) {
  std::string path =
      testing::RequireCorpusModel(testing::robots::kPanda);
  if (path.empty()) GTEST_SKIP() << "robot corpus missing (make corpus)";
  Model panda = Model::Load(path);
  VerifyReport report = Verify(panda, {});
  EXPECT_EQ(report.start, "keyframe 'home'");
  const CheckRow& start = Find(report, "start");
  EXPECT_EQ(start.status, CheckStatus::kPass) << start.explanation;
  EXPECT_NE(start.explanation.find("keyframe 'home'"), std::string::npos) << start.explanation;
  std::string table = VerifyTable(report, TableDetail::kAll, "");
  EXPECT_NE(table.find("tol 0.01, from keyframe 'home')"), std::string::npos) << table;
  EXPECT_NE(VerifyToJson(report).find("\"start\": \"keyframe 'home'\""), std::string::npos);
  // the runs start there: the pictures' start is the keyframe's state
  std::vector<Assignment> sets = VerifyStart(panda, {});
  ASSERT_FALSE(sets.empty());
  EXPECT_EQ(sets.front().text.rfind("keyframe 'home'", 0), 0u) << sets.front().text;
}

// From qpos0 (given as a whole qpos on top of 'home'), the start row names joint4, its value
// and its range; the rest of the protocol still runs.
TEST_F(VerifyStartTest, PandaFromQpos0NamesJoint4) {
  std::string path =
      testing::RequireCorpusModel(testing::robots::kPanda);
  if (path.empty()) GTEST_SKIP() << "robot corpus missing (make corpus)";
  Model panda = Model::Load(path);
  VerifyOptions options;
  options.sets = {Qpos0(panda)};
  VerifyReport report = Verify(panda, options);
  EXPECT_EQ(report.start, "keyframe 'home' with qpos=0,0,0,0,0,0,0,0,0");
  const CheckRow& start = Find(report, "start");
  EXPECT_EQ(start.status, CheckStatus::kWarn);
  EXPECT_NE(start.measured_text.find("joint4"), std::string::npos) << start.measured_text;
  EXPECT_NE(start.measured_text.find("at 0 rad outside [-3.072, -0.0698]"), std::string::npos)
      << start.measured_text;
  EXPECT_NE(start.explanation.find("joint4"), std::string::npos) << start.explanation;
  EXPECT_FALSE(start.fix.empty());
  EXPECT_EQ(Find(report, "determinism").status, CheckStatus::kPass);
}

// The Allegro hand has no keyframe: it starts at qpos0, where thj0 sits at 0, below its range.
TEST_F(VerifyStartTest, AllegroFromQpos0NamesThj0ItsValueAndRange) {
  std::string path =
      testing::RequireCorpusModel(testing::robots::kAllegro);
  if (path.empty()) GTEST_SKIP() << "robot corpus missing (make corpus)";
  Model hand = Model::Load(path);
  VerifyReport report = Verify(hand, {});
  EXPECT_EQ(report.start.rfind("qpos0", 0), 0u) << report.start;
  const CheckRow& start = Find(report, "start");
  EXPECT_EQ(start.status, CheckStatus::kWarn);
  EXPECT_NE(start.measured_text.find("thj0"), std::string::npos) << start.measured_text;
  EXPECT_NE(start.explanation.find("joint 'thj0' (id 13) at 0 rad outside [0.263, 1.396]"),
            std::string::npos)
      << start.explanation;
  std::string table = VerifyTable(report, TableDetail::kFindings, "");
  EXPECT_NE(table.find("tol 0.01, from qpos0"), std::string::npos) << table;
}

// A keyframe the caller names wins over 'home'; one the model lacks is refused by name.
TEST_F(VerifyStartTest, TheCallersKeyframeIsTheStart) {
  Model model = Model::FromXmlString(R"(<mujoco><compiler angle="radian"/><worldbody><body>
      <joint name="a" axis="0 1 0" range="-1 1"/><geom type="capsule" fromto="0 0 0 0.3 0 0"
      size="0.02"/></body></worldbody>
      <keyframe><key name="home" qpos="0.5"/><key name="away" qpos="2"/></keyframe></mujoco>)");
  VerifyOptions options;
  options.until = 0.1;
  EXPECT_EQ(Find(Verify(model, options), "start").status, CheckStatus::kPass);
  options.keyframe = "away";
  VerifyReport away = Verify(model, options);
  EXPECT_EQ(away.start, "keyframe 'away' (named by the caller)");
  EXPECT_EQ(Find(away, "start").status, CheckStatus::kWarn);
  EXPECT_NE(Find(away, "start").measured_text.find("joint 'a' (id 0) at 2 rad outside [-1, 1]"),
            std::string::npos)
      << Find(away, "start").measured_text;
  options.keyframe = "nowhere";
  EXPECT_THROW(Verify(model, options), ValueError);
}

// With actuation disabled (opt.disableflags), the iiwa14's position servos exert nothing: the
// run from 'home' is passive and its energy is judged, not skipped as "pushes at ctrl = 0".
TEST_F(VerifyStartTest, Iiwa14WithActuationDisabledHasItsEnergyJudged) {
  std::string path =
      testing::RequireCorpusModel(testing::robots::kIiwa14);
  if (path.empty()) GTEST_SKIP() << "robot corpus missing (make corpus)";
  Model iiwa = Model::Load(path);
  // as its authors drive it, the servos hold it: no energy bound
  const CheckRow driven = Find(Verify(iiwa, {}), "energy");
  EXPECT_EQ(driven.status, CheckStatus::kSkip);
  EXPECT_NE(driven.explanation.find("pushes even at ctrl = 0"), std::string::npos);
  for (const char* flag : {"opt.disableflags.actuation=1",
                           "opt.disableflags=2048"}) {  // mjDSBL_ACTUATION, the whole field
    VerifyOptions options;
    options.sets = {ParseAssignment(iiwa, flag)};
    VerifyReport report = Verify(iiwa, options);
    EXPECT_EQ(report.start, std::string("keyframe 'home' with ") + flag);
    const CheckRow& energy = Find(report, "energy");
    EXPECT_NE(energy.status, CheckStatus::kSkip) << flag << ": " << energy.explanation;
    EXPECT_TRUE(energy.measured.known()) << flag << ": " << energy.measured_text;
    EXPECT_NE(energy.status, CheckStatus::kFail) << flag << ": " << energy.explanation;
  }
}

// The same flag set in the model's own MJCF.
TEST_F(VerifyStartTest, Iiwa14WithItsOwnActuationFlagHasItsEnergyJudged) {
  std::string path =
      testing::RequireCorpusModel(testing::robots::kIiwa14);
  if (path.empty()) GTEST_SKIP() << "robot corpus missing (make corpus)";
  testing::TempDir dir;
  std::string copy = testing::EditedModelCopy(
      path,
      {{R"(<option integrator="implicitfast"/>)",
        R"(<option integrator="implicitfast"><flag actuation="disable"/></option>)"}},
      dir.path());
  VerifyReport report = Verify(Model::Load(copy), {});
  const CheckRow& energy = Find(report, "energy");
  EXPECT_NE(energy.status, CheckStatus::kSkip) << energy.explanation;
  EXPECT_TRUE(energy.measured.known()) << energy.measured_text;
}

}  // namespace
}  // namespace plumb
