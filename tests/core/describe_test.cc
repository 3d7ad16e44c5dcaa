#include "plumb/describe.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/mujoco_compat.h"
#include "corpus_robots.h"
#include "fixture.h"
#include "plumb/load.h"

namespace plumb {
namespace {

using testing::MujocoTest;

long Size(const ModelDescription& d, const std::string& name) {
  for (const auto& [key, value] : d.sizes) {
    if (key == name) return value;
  }
  return -1;
}

using DescribeTest = MujocoTest;

TEST_F(DescribeTest, PendulumMatchesTheChaptersTable) {
  ModelDescription d = Describe(Model::Load(testing::kPendulum));
  EXPECT_EQ(Size(d, "nbody"), 2);
  EXPECT_EQ(Size(d, "njnt"), 1);
  EXPECT_EQ(Size(d, "nq"), 1);
  EXPECT_EQ(Size(d, "nv"), 1);
  EXPECT_EQ(Size(d, "nu"), 0);
  EXPECT_EQ(d.timestep, 0.002);
  EXPECT_EQ(d.integrator, "Euler");
  EXPECT_EQ(d.gravity[2], -9.81);
  ASSERT_EQ(d.bodies.size(), 2u);
  EXPECT_EQ(d.bodies[1].name, "link");
  EXPECT_EQ(d.bodies[1].mass, 1);
  EXPECT_NEAR(d.bodies[1].com[2], -0.5, 1e-12);  // the capsule's middle
  ASSERT_EQ(d.joints.size(), 1u);
  EXPECT_EQ(d.joints[0].type, "hinge");
  EXPECT_EQ(d.joints[0].damping, 0.05);
  EXPECT_EQ(d.joints[0].position_unit, "rad");
  EXPECT_EQ(d.roles.size(), 4u);
}

TEST_F(DescribeTest, CapsuleInertiaIsTheCompilersAboutTheCom) {
  // a solid capsule (cylinder length 1, radius 0.05, two hemispheres) of mass 1 kg:
  // the moment about a transverse axis through the centre is well below m*L^2/12
  ModelDescription d = Describe(Model::Load(testing::kPendulum));
  double transverse = d.bodies[1].inertia[0];
  EXPECT_GT(transverse, 0.08);
  EXPECT_LT(transverse, 1.0 / 12 + 0.02);
  EXPECT_NEAR(d.bodies[1].inertia[0], d.bodies[1].inertia[1], 1e-12);
  EXPECT_LT(d.bodies[1].inertia[2], 0.01);  // about the capsule's own axis
}

TEST_F(DescribeTest, HumanoidShowsNqDiffersFromNv) {
  ModelDescription d = Describe(Model::Load(testing::kHumanoid));
  EXPECT_EQ(Size(d, "nq"), 28);
  EXPECT_EQ(Size(d, "nv"), 27);
  EXPECT_EQ(d.joints[0].type, "free");
  EXPECT_EQ(d.joints[0].nq, 7);
  EXPECT_EQ(d.joints[0].nv, 6);
  EXPECT_EQ(d.actuators.size(), 21u);
  EXPECT_FALSE(d.actuators[0].target.empty());
}

TEST_F(DescribeTest, GearedMotorShowsCtrlAndJointForceSeparately) {
  // dm_control's cartpole: a gear-10 motor on a slide with ctrlrange [-1, 1]
  Model model = Model::FromXmlString(R"(<mujoco><worldbody>
      <body name="cart"><joint name="slider" type="slide"/><geom size="0.1"/>
        <body name="pole"><joint name="hinge" axis="0 1 0"/>
          <geom type="capsule" fromto="0 0 0 0 0 1" size="0.05"/></body></body></worldbody>
    <actuator>
      <motor name="slide" joint="slider" gear="10" ctrllimited="true" ctrlrange="-1 1"/>
      <motor name="clipped" joint="hinge" gear="2" ctrllimited="true" ctrlrange="-5 5"
             forcelimited="true" forcerange="-3 1"/>
      <motor name="free" joint="hinge"/>
    </actuator></mujoco>)");
  ModelDescription d = Describe(model);
  ASSERT_EQ(d.actuators.size(), 3u);
  const ActuatorDescription& slide = d.actuators[0];
  EXPECT_EQ(slide.ctrl_unit, "N/gear");
  EXPECT_TRUE(slide.joint_force_limited);
  EXPECT_EQ(slide.joint_force_range, (std::array<double, 2>{-10, 10}));
  EXPECT_EQ(slide.joint_force_unit, "N");
  // ctrlrange x gain, then forcerange, then gear
  const ActuatorDescription& clipped = d.actuators[1];
  EXPECT_EQ(clipped.joint_force_range, (std::array<double, 2>{-6, 2}));
  EXPECT_EQ(clipped.joint_force_unit, "N*m");
  EXPECT_EQ(d.actuators[2].ctrl_unit, "N*m");  // gear 1: ctrl is the torque
  EXPECT_FALSE(d.actuators[2].joint_force_limited);
  EXPECT_EQ(ActuatorPositionUnit(model.get(), 0), "m");
  EXPECT_EQ(ActuatorPositionUnit(model.get(), 1), "rad");
}

TEST_F(DescribeTest, ActuatorsAndSensorsCarryTheirUnits) {
  Model model = Model::FromXmlString(R"(<mujoco><worldbody>
      <body name="arm"><joint name="shoulder" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
        <site name="tip" pos="0.3 0 0"/>
        <body name="slider"><joint name="rail" type="slide"/>
          <geom type="sphere" size="0.05"/></body></body></worldbody>
    <actuator>
      <motor name="torque" joint="shoulder" gear="5"/>
      <position name="servo" joint="shoulder" kp="10"/>
      <velocity name="speed" joint="rail" kv="3"/>
    </actuator>
    <sensor>
      <jointpos name="angle" joint="shoulder"/>
      <jointpos name="travel" joint="rail"/>
      <accelerometer name="imu" site="tip"/>
      <framequat name="orientation" objtype="site" objname="tip"/>
    </sensor></mujoco>)");
  ModelDescription d = Describe(model);
  ASSERT_EQ(d.actuators.size(), 3u);
  EXPECT_EQ(d.actuators[0].kind, "motor");
  EXPECT_EQ(d.actuators[0].ctrl_unit, "N*m/gear");  // gear 5: the joint feels 5 x ctrl
  EXPECT_EQ(d.actuators[1].kind, "position");
  EXPECT_EQ(d.actuators[1].ctrl_unit, "rad");
  EXPECT_EQ(d.actuators[2].kind, "velocity");
  EXPECT_EQ(d.actuators[2].ctrl_unit, "m/s");
  EXPECT_EQ(d.actuators[2].force_unit, "N");
  ASSERT_EQ(d.sensors.size(), 4u);
  EXPECT_EQ(d.sensors[0].unit, "rad");
  EXPECT_EQ(d.sensors[1].unit, "m");
  EXPECT_EQ(d.sensors[2].unit, "m/s^2");
  EXPECT_EQ(d.sensors[3].unit, "");
}

// Every sensor type this MuJoCo has reads as its MJCF name, never as "type 16"
TEST_F(DescribeTest, EverySensorTypeHasItsName) {
  for (int type = 0; type <= mjSENS_USER; ++type) {
    EXPECT_NE(compat::NameOf(compat::kSensorTypes, type).rfind("type ", 0), 0u) << type;
  }
  if (!(mjVERSION_HEADER >= 3011000)) GTEST_SKIP() << "the newer sensors came after MuJoCo 2.x";
  Model model = Model::FromXmlString(testing::TwoHingeArm(R"(<motor name="m" joint="b"/>
    </actuator><sensor><jointactuatorfrc name="tau" joint="b"/><e_kinetic name="energy"/>
    </sensor><actuator>)"));
  ModelDescription d = Describe(model);
  ASSERT_EQ(d.sensors.size(), 2u);
  EXPECT_EQ(d.sensors[0].type, "jointactuatorfrc");
  EXPECT_EQ(d.sensors[0].unit, "N*m");
  EXPECT_EQ(d.sensors[1].type, "e_kinetic");
}

// MuJoCo 3.12+: a pid takes two controls, so actuator and control indices part; a dcmotor after
// it is the second actuator, not a phantom third
TEST_F(DescribeTest, APidBeforeADcMotorIsTwoActuators) {
  if (!(mjVERSION_HEADER >= 3012000)) GTEST_SKIP() << "pid actuators came with MuJoCo 3.12";
  Model model = Model::FromXmlString(testing::TwoHingeArm(R"(<pid name="p" joint="a" kp="10" kv="1"/>
      <dcmotor name="m" joint="b" motorconst="0.05" resistance="1" ctrlrange="-12 12"/>)"));
  ModelDescription d = Describe(model);
  ASSERT_EQ(d.actuators.size(), 2u);
  EXPECT_EQ(d.actuators[0].kind, "pid");
  EXPECT_EQ(d.actuators[1].name, "m");
  EXPECT_EQ(d.actuators[1].kind, "dcmotor");
  EXPECT_EQ(d.actuators[1].target, "b");
  EXPECT_TRUE(d.actuators[1].ctrllimited);
  EXPECT_EQ(d.actuators[1].ctrlrange[1], 12);
}

// MuJoCo 3.5+ delays: every delayed actuator and sensor with its buffer, nsample x timestep;
// a delay longer than the buffer is shortened by MuJoCo, and the description says so
TEST_F(DescribeTest, DelaysShowTheirBufferAndWhenMujocoShortensThem) {
  if (!(mjVERSION_HEADER >= 3005000)) GTEST_SKIP() << "delays came with MuJoCo 3.5";
  Model model = Model::FromXmlString(testing::TwoHingeArm(R"(
      <motor name="late" joint="a" delay="0.5" nsample="20"/>
      <motor name="prompt" joint="b" delay="0.01" nsample="5"/>)"));
  ModelDescription d = Describe(model);
  ASSERT_EQ(d.delays.size(), 2u);
  const DelayDescription& late = d.delays[0];
  EXPECT_EQ(late.kind, "actuator");
  EXPECT_EQ(late.name, "late");
  EXPECT_NEAR(late.buffer, 0.04, 1e-12);
  EXPECT_TRUE(late.shortened());
  EXPECT_EQ(late.needed_nsample, 250);
  EXPECT_NE(late.Warning().find("so MuJoCo delays it by 0.04 s only"), std::string::npos)
      << late.Warning();
  EXPECT_FALSE(d.delays[1].shortened());  // 5 x 2 ms hold 10 ms
  EXPECT_EQ(d.delays[1].Warning(), "");
}

// Loading says once, on the call's channel, what MuJoCo said or did on the way: a delay it
// shortened (MuJoCo says nothing), and its compiler's warnings (MuJoCo 4 gives settotalmass's
// deprecation both to its handler and in the compiler's message: said once).
TEST_F(DescribeTest, LoadingAddsWhatMujocoSaidToTheCallsNotices) {
  testing::TempDir dir;
  std::string total = dir.File("total.xml");
  testing::WriteFile(total, R"(<mujoco><compiler settotalmass="5"/><worldbody>
      <body><freejoint/><geom size="0.1"/></body></worldbody></mujoco>)");
  Notices said;
  LoadModel(total, &said);
  int settotalmass = 0;
  for (const Notice& n : said.all()) {
    EXPECT_EQ(n.topic, NoticeTopic::kCompile) << n.Line();
    EXPECT_NE(n.subject.find("'" + total + "'"), std::string::npos) << n.Line();
    if (n.text.find("settotalmass") != std::string::npos) ++settotalmass;
  }
  EXPECT_LE(settotalmass, 1);
  EXPECT_TRUE(TakeMujocoWarnings().empty());  // taken, also when said

  if (!(mjVERSION_HEADER >= 3005000)) GTEST_SKIP() << "delays came with MuJoCo 3.5";
  std::string late = dir.File("late.xml");
  testing::WriteFile(late, testing::TwoHingeArm(R"(<motor name="late" joint="a" delay="0.5"
      nsample="20"/>)"));
  Notices notices;
  Model model = LoadModel(late, &notices);
  std::vector<Notice> said_late = notices.all();
  ASSERT_EQ(said_late.size(), 1u);
  const Notice& n = said_late[0];
  EXPECT_EQ(n.level, NoticeLevel::kWarning);
  EXPECT_EQ(n.topic, NoticeTopic::kCompile);
  EXPECT_EQ(n.subject, "'" + late + "'");
  EXPECT_EQ(n.text, Delays(model)[0].Warning() + ".");
  Notices wrapped;
  AddModelNotices(model, "<MjModel 'arm'>", &wrapped);  // a model compiled elsewhere
  ASSERT_EQ(wrapped.all().size(), 1u);
  EXPECT_EQ(wrapped.all()[0].subject, "<MjModel 'arm'>");
  LoadModel(late, nullptr);  // no channel: nothing said, nothing left behind
  EXPECT_TRUE(TakeMujocoWarnings().empty());
}

// An intvelocity actuator is a position servo behind an integrator: its ctrl is a velocity, so
// it is not shown as "position" (issue 49). A joint's actuatorfrcrange bounds its actuators'
// force, shown in the joint force column instead of "unlimited" (MuJoCo 3+).
TEST_F(DescribeTest, IntvelocityAndAJointsActuatorForceRangeAreShownAsTheyAre) {
  testing::TempDir dir;
  std::string arm = dir.File("arm.xml");
  testing::WriteFile(arm, testing::TwoHingeArm(R"(<general name="p" joint="b" gainprm="10"
      biastype="affine" biasprm="0 -10 -1"/><general name="iv" joint="a" dyntype="integrator"
      gainprm="10" biastype="affine" biasprm="0 -10"/>)"));  // position kp 10 kv 1 and
  // intvelocity kp 10 as they compile (MuJoCo 2.x's position has no kv, its intvelocity no
  // actrange; stateless actuators come first)
  ModelDescription d = Describe(Model::Load(arm));
  ASSERT_EQ(d.actuators.size(), 2u);
  EXPECT_EQ(d.actuators[1].kind, "intvelocity");
  EXPECT_EQ(d.actuators[1].ctrl_unit, "rad/s");
  EXPECT_EQ(d.actuators[0].kind, "position");  // a position servo with damping kv
  if (!(mjVERSION_HEADER >= 300)) GTEST_SKIP() << "actuatorfrcrange came with MuJoCo 3";
  std::string bounded = dir.File("bounded.xml");
  std::string xml = testing::TwoHingeArm(R"(<motor name="m" joint="a" gear="2"/>)");
  xml.replace(xml.find(R"(<joint name="a" axis="0 1 0"/>)"), 30,
              R"(<joint name="a" axis="0 1 0" actuatorfrcrange="-88 88"/>)");
  testing::WriteFile(bounded, xml);
  ModelDescription b = Describe(Model::Load(bounded));
  ASSERT_TRUE(b.actuators[0].joint_force_limited);
  EXPECT_EQ(b.actuators[0].joint_force_range[0], -88);
  EXPECT_EQ(b.actuators[0].joint_force_range[1], 88);
}

// The corpus G1 with its joints bounded at +-88 N*m, as mjlab writes them: inspect's table
// shows the bound, not "unlimited".
TEST_F(DescribeTest, TheG1sActuatorForceRangeIsItsJointForce) {
  testing::TempDir dir;
  std::string g1 = testing::robots::G1Servos(dir.path());
  if (g1.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  ModelDescription d = Describe(Model::Load(g1));
  ASSERT_EQ(d.actuators.size(), 29u);
  for (const ActuatorDescription& a : d.actuators) {
    EXPECT_EQ(a.kind, "position") << a.name;
    ASSERT_TRUE(a.joint_force_limited) << a.name;
    EXPECT_EQ(a.joint_force_range[0], -88) << a.name;
    EXPECT_EQ(a.joint_force_range[1], 88) << a.name;
  }
}

}  // namespace
}  // namespace plumb
