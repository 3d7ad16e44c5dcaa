// The step response of audit's actuator layer (src/audit/audit_step.cc) on small planted
// models: a position servo's step stays inside its joint's range, the joints an equality ties
// to the driven one move with it, and a response a limit, a spring or a force bound decided
// says so instead of blaming the gains.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "audit/step_rows.h"
#include "fixture.h"
#include "plumb/audit.h"

namespace plumb {
namespace {

class AuditStepTest : public testing::MujocoTest {
 protected:
  static AuditReport AuditXml(const std::string& xml) {
    AuditReport report = Audit(Model::FromXmlString(xml, "planted.xml"), AuditOptions{});
    TakeMujocoWarnings();
    return report;
  }
};

// A servo whose ctrlrange (+-6.28 rad, as ANYmal's) is far wider than its joint's range
// [-0.5, 0.5], starting at 0.4: 10% of ctrlrange would be 1.256 rad, past the range. The step
// is a quarter of the range width (0.25 rad), toward the side with room, and says so in joint
// units.
TEST_F(AuditStepTest, AStepWiderThanTheJointRangeIsClippedToIt) {
  AuditReport r = AuditXml(R"(<mujoco><compiler angle="radian" autolimits="true"/><option gravity="0 0 0"/>
    <worldbody><body><joint name="hip" axis="1 0 0" range="-0.5 0.5" damping="1"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.3" size="0.03" mass="1"/></body></worldbody>
    <actuator><general name="hip" joint="hip" gainprm="50" biastype="affine" biasprm="0 -50 -2"
      ctrlrange="-6.28 6.28"/></actuator>
    <keyframe><key name="home" qpos="0.4"/></keyframe></mujoco>)");
  AuditCurve c = testing::StepCurve(r, "hip");
  EXPECT_DOUBLE_EQ(c.start, 0.4);
  EXPECT_NEAR(c.target, 0.15, 1e-9);  // down: up has no room left inside 0.5 - 10%
  CheckRow row = testing::StepRow(r, "hip");
  EXPECT_EQ(row.status, CheckStatus::kPass) << row.measured_text;
  EXPECT_NE(row.measured_text.find("step 0.25 rad: 0.4 -> 0.15 rad of joint 'hip' [-0.5, 0.5]"),
            std::string::npos)
      << row.measured_text;
}

// A four-bar linkage closed by a connect constraint: the crank's servo moves the coupler and
// the rocker with it; the unrelated joint stays held.
TEST_F(AuditStepTest, JointsALoopTiesToTheDrivenOneMoveWithIt) {
  AuditReport r = AuditXml(R"(<mujoco><compiler angle="radian" autolimits="true"/><option gravity="0 0 0"/>
    <worldbody>
      <body name="crank"><joint name="crank" axis="0 1 0" range="-1 1" damping="0.1"/>
        <geom type="capsule" fromto="0 0 0 0.1 0 0" size="0.01" mass="0.1"/>
        <body name="coupler" pos="0.1 0 0"><joint name="coupler" axis="0 1 0" damping="0.1"/>
          <geom type="capsule" fromto="0 0 0 0 0 0.3" size="0.01" mass="0.1"/></body></body>
      <body name="rocker" pos="0.3 0 0"><joint name="rocker" axis="0 1 0" damping="0.1"/>
        <geom type="capsule" fromto="0 0 0 -0.2 0 0.3" size="0.01" mass="0.1"/></body>
      <body name="other" pos="1 0 0"><joint name="other" axis="0 1 0"/>
        <geom type="sphere" size="0.05" mass="0.1"/></body>
    </worldbody>
    <equality><connect body1="coupler" body2="rocker" anchor="0 0 0.3"/></equality>
    <actuator><general name="crank" joint="crank" gainprm="5" biastype="affine" biasprm="0 -5 -0.5"
      ctrlrange="-1 1"/></actuator>
    </mujoco>)");
  CheckRow row = testing::StepRow(r, "crank");
  EXPECT_NE(row.measured_text.find("moves crank, coupler, rocker; held: 1 other joint;"),
            std::string::npos)
      << row.measured_text;
}

// A joint that starts 0.5 m below its range: the limit throws it in, far past the soft
// servo's target. That overshoot is the limit's: a WARN naming it, never a FAIL of the gains.
TEST_F(AuditStepTest, AnOvershootALimitDecidedIsNotBlamedOnTheGains) {
  AuditReport r = AuditXml(R"(<mujoco><compiler autolimits="true"/><option gravity="0 0 0"/><worldbody>
      <body><joint name="slide" type="slide" axis="1 0 0" range="0 1"/>
        <geom type="sphere" size="0.05" mass="1"/></body></worldbody>
    <actuator><position name="slide" joint="slide" kp="1" ctrlrange="0 1"/></actuator>
    <keyframe><key name="home" qpos="-0.5"/></keyframe></mujoco>)");
  CheckRow row = testing::StepRow(r, "slide");
  EXPECT_NE(row.status, CheckStatus::kFail) << row.measured_text;
  EXPECT_EQ(row.fix.find("lower kp"), std::string::npos) << row.fix;
  EXPECT_NE(row.fix.find("the limit of joint 'slide' [0, 1] acted from the first step"),
            std::string::npos)
      << row.fix;
}

// A servo on a sprung joint that cannot reach its target because its force bound saturates
// (kp 100 against stiffness 40 would stop at 71% of the step; 2 N of force stops it at 25%),
// and one held back by a spring twice as stiff as kp: each says what held it.
TEST_F(AuditStepTest, AnErrorSaysWhatHeldTheServoBack) {
  AuditReport r = AuditXml(R"(<mujoco><compiler autolimits="true"/><option gravity="0 0 0"/><worldbody>
      <body><joint name="a" type="slide" axis="1 0 0" range="-1 1" damping="5" stiffness="40"/>
        <geom type="sphere" size="0.05" mass="1"/></body>
      <body pos="0 1 0"><joint name="b" type="slide" axis="1 0 0" range="-1 1" damping="5"
          stiffness="200"/>
        <geom type="sphere" size="0.05" mass="1"/></body></worldbody>
    <actuator>
      <position name="weak" joint="a" kp="100" ctrlrange="-1 1" forcerange="-2 2"/>
      <position name="sprung" joint="b" kp="100" ctrlrange="-1 1"/>
    </actuator></mujoco>)");
  CheckRow weak = testing::StepRow(r, "weak");
  EXPECT_EQ(weak.status, CheckStatus::kWarn) << weak.measured_text;
  EXPECT_NE(weak.fix.find("its force sits at forcerange [-2, 2]"), std::string::npos) << weak.fix;
  CheckRow sprung = testing::StepRow(r, "sprung");
  EXPECT_EQ(sprung.status, CheckStatus::kWarn) << sprung.measured_text;
  EXPECT_NE(sprung.fix.find("a spring on its joints"), std::string::npos) << sprung.fix;
}

}  // namespace
}  // namespace plumb
