#include "plumb/audit.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "fixture.h"
#include "plumb/error.h"

namespace plumb {
namespace {

using testing::TempDir;
using testing::WriteFile;

// The first finding of `check` that names `element`, or nullptr.
const Finding* Find(const AuditReport& report, const std::string& check,
                    const std::string& element = "") {
  for (const Finding& f : report.findings) {
    if (f.check == check && f.element.find(element) != std::string::npos) return &f;
  }
  return nullptr;
}

std::string Failures(const AuditReport& report) {
  std::string out;
  for (const Finding& f : report.findings) {
    if (f.status == CheckStatus::kFail) out += f.check + " " + f.element + ": " + f.measured + "\n";
  }
  return out;
}

class AuditTest : public testing::MujocoTest {
 protected:
  AuditReport AuditXml(const std::string& xml, AuditOptions options = {}) {
    Model model = Model::FromXmlString(xml, "planted.xml");
    AuditReport report = Audit(model, options);
    TakeMujocoWarnings();
    return report;
  }
};

TEST_F(AuditTest, CollisionlessFreeBodyFallsForever) {
  AuditReport r = AuditXml(R"(<mujoco><worldbody>
      <geom name="floor" type="plane" size="5 5 0.1"/>
      <body name="ghost" pos="0 0 1"><freejoint/>
        <geom type="box" size="0.1 0.1 0.1" contype="0" conaffinity="0"/></body>
    </worldbody></mujoco>)");
  const Finding* f = Find(r, "contact.free_fall", "'ghost'");
  ASSERT_NE(f, nullptr) << Failures(r);
  EXPECT_EQ(f->layer, "contact");
  EXPECT_EQ(f->status, CheckStatus::kFail);
}

TEST_F(AuditTest, FeatherweightBodyOnAHeavyBaseIsFlagged) {
  AuditReport r = AuditXml(R"(<mujoco><worldbody>
      <body name="base" pos="0 0 1"><joint name="j1" axis="0 1 0"/>
        <geom type="box" size="0.2 0.2 0.2" mass="10"/>
        <body name="feather" pos="0.4 0 0"><joint name="j2" axis="0 1 0"/>
          <geom type="sphere" size="0.02" mass="1e-6"/></body>
      </body></worldbody></mujoco>)");
  const Finding* tiny = Find(r, "inertia.tiny_mass", "'feather'");
  ASSERT_NE(tiny, nullptr);
  EXPECT_EQ(tiny->layer, "inertia");
  EXPECT_EQ(tiny->status, CheckStatus::kWarn);
  const Finding* ratio = Find(r, "inertia.mass_ratio", "'feather'");
  ASSERT_NE(ratio, nullptr);
  EXPECT_EQ(ratio->status, CheckStatus::kFail);  // 1e7: beyond any conditioning
  EXPECT_NE(ratio->measured.find("'base'"), std::string::npos);
}

TEST_F(AuditTest, MotorWithoutLimitsIsFlagged) {
  AuditReport r = AuditXml(R"(<mujoco><worldbody>
      <body name="arm" pos="0 0 1"><joint name="shoulder" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.03" mass="1"/></body>
    </worldbody><actuator><motor name="strong" joint="shoulder" gear="50"/></actuator></mujoco>)");
  const Finding* f = Find(r, "actuator.limits", "'strong'");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->layer, "actuator");
  EXPECT_EQ(f->status, CheckStatus::kWarn);
  EXPECT_NE(f->measured.find("gear 50"), std::string::npos) << f->measured;
}

TEST_F(AuditTest, ActuatorTooWeakToHoldItsArm) {
  // a 2 kg, 1 m arm held horizontal needs 2 * 9.81 * 0.5 = 9.81 N*m; the motor gives 1
  AuditReport r = AuditXml(R"(<mujoco><worldbody>
      <body name="arm" pos="0 0 1"><joint name="shoulder" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 1 0 0" size="0.03" mass="2"/></body>
    </worldbody><actuator>
      <motor name="weak" joint="shoulder" gear="1" ctrllimited="true" ctrlrange="-1 1"/>
    </actuator></mujoco>)");
  const Finding* f = Find(r, "actuator.holding", "'weak'");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->status, CheckStatus::kWarn);
  EXPECT_NE(f->measured.find("9.81"), std::string::npos) << f->measured;
  EXPECT_EQ(Find(r, "actuator.limits", "'weak'"), nullptr);  // its ctrl is limited
}

TEST_F(AuditTest, RadiansWrittenWhereMjcfExpectsDegreesAreFlagged) {
  // MJCF angles default to degrees: range="-1.5 1.5" is +-1.5 degrees, not radians
  AuditReport r = AuditXml(R"(<mujoco><compiler autolimits="true"/><worldbody>
      <body name="arm" pos="0 0 1"><joint name="shoulder" axis="0 1 0" range="-1.5 1.5"/>
        <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.03" mass="1"/></body>
    </worldbody><actuator>
      <position name="servo" joint="shoulder" kp="50" ctrlrange="-1.5 1.5"/>
    </actuator></mujoco>)");
  const Finding* range = Find(r, "structure.joint_range", "'shoulder'");
  ASSERT_NE(range, nullptr);
  EXPECT_EQ(range->status, CheckStatus::kWarn);
  EXPECT_NE(range->fix.find("angle=\"radian\""), std::string::npos) << range->fix;
  const Finding* target = Find(r, "actuator.target_range", "'servo'");
  ASSERT_NE(target, nullptr);
  EXPECT_EQ(target->layer, "actuator");
}

TEST_F(AuditTest, DivergingTimestepIsCaughtWithARepro) {
  TempDir dir;
  AuditOptions options;
  options.repro_dir = dir.File("repro");
  AuditReport r = AuditXml(R"(<mujoco><option timestep="0.01" gravity="0 0 0"/><worldbody>
      <body name="mass"><joint name="spring" type="slide" axis="1 0 0" stiffness="1e6" ref="0.01"/>
        <geom type="sphere" size="0.05" mass="1"/></body></worldbody></mujoco>)",
                           options);
  const Finding* f = Find(r, "behaviour.passive_settle");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->status, CheckStatus::kFail);
  EXPECT_EQ(f->measured, "diverged");
  ASSERT_FALSE(r.repro_folders.empty());
  EXPECT_TRUE(std::filesystem::exists(r.repro_folders[0] + "/model.mjb"));
}

TEST_F(AuditTest, HumanoidHasNoFailure) {
  AuditReport r = Audit(Model::Load(testing::kHumanoid), {});
  TakeMujocoWarnings();
  EXPECT_EQ(r.Count(CheckStatus::kFail), 0) << Failures(r);
  for (const char* layer :
       {"structure", "inertia", "actuator", "contact", "behaviour", "warnings"}) {
    bool seen = false;
    for (const Finding& f : r.findings) seen = seen || f.layer == layer;
    EXPECT_TRUE(seen) << layer;
  }
  const Finding* nq = Find(r, "structure.nq_nv", "'root'");
  ASSERT_NE(nq, nullptr);
  EXPECT_NE(nq->measured.find("nq 28 != nv 27"), std::string::npos);
}

TEST_F(AuditTest, BoxComesToRestOnItsWeight) {
  AuditReport r = AuditXml(R"(<mujoco><worldbody>
      <geom name="floor" type="plane" size="5 5 0.1"/>
      <body name="box" pos="0 0 0.2"><freejoint/><geom type="box" size="0.1 0.1 0.1" mass="3"/></body>
    </worldbody></mujoco>)");
  const Finding* support = Find(r, "contact.support");
  ASSERT_NE(support, nullptr);
  EXPECT_EQ(support->status, CheckStatus::kPass) << support->measured;
  EXPECT_EQ(Find(r, "contact.slip")->status, CheckStatus::kPass);
  EXPECT_EQ(r.Count(CheckStatus::kFail), 0) << Failures(r);
}

constexpr char kArm[] = R"(<mujoco><worldbody>
    <body name="upper" pos="0 0 1"><joint name="shoulder" axis="0 1 0" damping="1"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.03" mass="1"/></body>
  </worldbody>
  <actuator><position name="servo" joint="shoulder" kp="50" ctrllimited="true" ctrlrange="-1 1"/></actuator>
  <keyframe><key name="home" qpos="0.3"/></keyframe>
</mujoco>)";

TEST_F(AuditTest, ScenarioAssertionsPassAndFailWhenTheyShould) {
  TempDir dir;
  Model model = Model::FromXmlString(kArm, "arm.xml");
  WriteFile(dir.File("lift.toml"), R"(
name = "lift"
duration = 3.0
keyframe = "home"
assertions = ["qpos[shoulder] > 0.5 during [2, 3]",
              "maxabs(qvel[*]) < 50",
              "qpos[shoulder] < 0.5 during [2, 3]"]
[[controls]]
actuator = "servo"
type = "step"
before = 0.3
value = 0.8
at = 0.5
)");
  AuditOptions options;
  options.scenario = LoadScenario(model, dir.File("lift.toml"));
  AuditReport r = Audit(model, options);
  std::vector<const Finding*> rows;
  for (const Finding& f : r.findings) {
    if (f.check == "behaviour.assertion") rows.push_back(&f);
  }
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0]->status, CheckStatus::kPass) << rows[0]->measured;
  EXPECT_EQ(rows[1]->status, CheckStatus::kPass) << rows[1]->measured;
  EXPECT_EQ(rows[2]->status, CheckStatus::kFail);
  EXPECT_NE(rows[2]->measured.find("at t = 2"), std::string::npos) << rows[2]->measured;
}

TEST_F(AuditTest, JsonScenarioWithRampAndSine) {
  TempDir dir;
  Model model = Model::FromXmlString(kArm, "arm.xml");
  WriteFile(dir.File("s.json"), R"({"name": "wave", "duration": 2,
    "initial": {"qpos[shoulder]": 0.1},
    "controls": [{"actuator": "servo", "type": "sine", "offset": 0, "amplitude": 0.2,
                  "frequency": 1}],
    "assertions": ["maxabs(qpos[shoulder]) < 0.5", "final(time) >= 2"]})");
  Scenario sc = LoadScenario(model, dir.File("s.json"));
  EXPECT_EQ(sc.controls[0].At(0.25), 0.2);
  EXPECT_EQ(sc.initial.size(), 1u);
  AuditOptions options;
  options.scenario = sc;
  AuditReport r = Audit(model, options);
  TakeMujocoWarnings();
  for (const Finding& f : r.findings) {
    if (f.check == "behaviour.assertion") {
      EXPECT_EQ(f.status, CheckStatus::kPass) << f.element;
    }
  }
}

TEST_F(AuditTest, BadScenariosNameTheFileAndEntry) {
  TempDir dir;
  Model model = Model::FromXmlString(kArm, "arm.xml");
  WriteFile(dir.File("a.json"), R"({"controls": [{"actuator": "srvo"}]})");
  try {
    LoadScenario(model, dir.File("a.json"));
    FAIL();
  } catch (const ValueError& e) {
    EXPECT_NE(std::string(e.what()).find("a.json"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("did you mean: servo"), std::string::npos) << e.what();
  }
  WriteFile(dir.File("b.toml"), "duration = \n");
  EXPECT_THROW(LoadScenario(model, dir.File("b.toml")), ValueError);
  WriteFile(dir.File("c.json"), R"({"assertions": ["qpos[shoulder] ~ 1"]})");
  EXPECT_THROW(LoadScenario(model, dir.File("c.json")), ValueError);
  WriteFile(dir.File("d.json"), R"({"durations": 1})");
  EXPECT_THROW(LoadScenario(model, dir.File("d.json")), ValueError);
  EXPECT_THROW(LoadScenario(model, dir.File("missing.json")), IoError);
}

TEST_F(AuditTest, AssertionsParse) {
  Model model = Model::FromXmlString(kArm, "arm.xml");
  Assertion a = ParseAssertion(model, "xpos[upper][2] >= 0.5 during [0.5, 1]");
  EXPECT_EQ(a.op, ">=");
  EXPECT_EQ(a.bound, 0.5);
  EXPECT_EQ(a.from, 0.5);
  EXPECT_EQ(a.to, 1);
  Assertion b = ParseAssertion(model, "maxabs(qvel[*]) < 50");
  EXPECT_EQ(b.reduce, "maxabs");
  EXPECT_EQ(b.paths.size(), 1u);
  EXPECT_LT(b.to, 0);
  EXPECT_THROW(ParseAssertion(model, "qvel[*] < fast"), ValueError);
  EXPECT_THROW(ParseAssertion(model, "qvel[elbow] < 1"), PathError);
}

}  // namespace
}  // namespace plumb
