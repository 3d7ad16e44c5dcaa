#include "plumb/analytic.h"

#include <gtest/gtest.h>

#include <cmath>

#include "fixture.h"
#include "plumb/error.h"

namespace plumb {
namespace {

TEST(EllipticKTest, MatchesTabulatedValues) {
  // Abramowitz & Stegun, table 17.1 (modulus k = sin(alpha)); K(0) = pi/2
  EXPECT_DOUBLE_EQ(EllipticK(0), M_PI / 2);
  EXPECT_NEAR(EllipticK(std::sin(M_PI / 4)), 1.8540746773013719, 1e-15);
  EXPECT_NEAR(EllipticK(0.5), 1.6857503548125961, 1e-15);
  EXPECT_NEAR(EllipticK(std::sin(80 * M_PI / 180)), 3.1533852519, 1e-10);  // table: 10 places
  EXPECT_THROW(EllipticK(1.0), ValueError);
  EXPECT_THROW(EllipticK(-0.1), ValueError);
}

TEST(PeriodFromCrossingsTest, RecoversASyntheticSine) {
  const double period = 1.2345, dt = 1e-3;
  std::vector<double> t, x;
  for (int i = 0; i < 10000; ++i) {
    t.push_back(i * dt);
    x.push_back(0.3 + std::sin(2 * M_PI * t.back() / period + 0.4));
  }
  std::optional<double> measured = PeriodFromCrossings(t, x, 0.3);
  ASSERT_TRUE(measured);
  // linear interpolation at a zero crossing, where the curvature vanishes, is O(dt^3)
  EXPECT_NEAR(*measured, period, 1e-9);
  EXPECT_NEAR(*PeriodFromCrossings(t, x, 0.3, 2), period, 1e-9);
  EXPECT_FALSE(PeriodFromCrossings({0, 1, 2}, {1, 2, 3}, 0));
}

TEST(PeaksTest, FindsLocalMaxima) {
  EXPECT_EQ(Peaks({0, 2, 1, 3, 3, 0, 1}), (std::vector<double>{2, 3}));
  EXPECT_TRUE(Peaks({1, 2, 3}).empty());
}

TEST(DampingTest, ClassifiesHandComputedCases) {
  // I = 1 kg*m^2, k = 4 N*m/rad: critical damping is c = 2*sqrt(I*k) = 4
  DampingAnalysis under = AnalyseDamping(1, 4, 1);
  EXPECT_DOUBLE_EQ(under.zeta, 0.25);
  EXPECT_DOUBLE_EQ(under.omega0, 2);
  EXPECT_DOUBLE_EQ(under.omega_d, 2 * std::sqrt(1 - 0.0625));
  EXPECT_EQ(under.kind, DampingClass::kUnderdamped);
  EXPECT_EQ(AnalyseDamping(1, 4, 4).kind, DampingClass::kCritical);
  EXPECT_EQ(AnalyseDamping(1, 4, 8).kind, DampingClass::kOverdamped);
  EXPECT_EQ(AnalyseDamping(1, 4, 0).kind, DampingClass::kUndamped);
  EXPECT_EQ(AnalyseDamping(1, 4, 8).damped_period, 0);
  EXPECT_STREQ(DampingClassName(DampingClass::kCritical), "critically damped");
}

using PendulumTest = testing::MujocoTest;

TEST_F(PendulumTest, DetectsTheChaptersPendulumFromTheCompiledModel) {
  Model model = Model::Load(testing::kPendulum);
  std::optional<PendulumParams> p = DetectPendulum(model);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->mass, 1);
  EXPECT_NEAR(p->distance, 0.5, 1e-12);
  EXPECT_NEAR(p->gravity, 9.81, 1e-12);
  EXPECT_NEAR(p->equilibrium, 0, 1e-12);
  // parallel axis: I = I_com + m*d^2, with the compiler's capsule inertia about the com
  EXPECT_NEAR(p->inertia, model->body_inertia[3] + 0.25, 1e-12);
  EXPECT_EQ(p->damping, 0.05);
  // T0 = 2*pi*sqrt(I/(m*g*d)) for I = 0.34557 kg*m^2: 1.6677 s
  EXPECT_NEAR(SmallAnglePeriod(*p), 2 * M_PI * std::sqrt(p->inertia / 4.905), 1e-12);
  EXPECT_GT(LargeAnglePeriod(*p, 2.8), 2 * SmallAnglePeriod(*p));
  EXPECT_THROW(LargeAnglePeriod(*p, M_PI), ValueError);
}

TEST_F(PendulumTest, FindsTheEquilibriumOfATiltedPendulum) {
  // a rod pointing along +x at qpos = 0 hangs down after a quarter turn about y
  Model model = Model::FromXmlString(R"(<mujoco><worldbody><body pos="0 0 2">
      <joint name="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 1 0 0" size="0.05" mass="2"/>
    </body></worldbody></mujoco>)");
  std::optional<PendulumParams> p = DetectPendulum(model);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->equilibrium, M_PI / 2, 1e-12);
  EXPECT_NEAR(p->stiffness, 2 * 9.81 * 0.5, 1e-9);
}

TEST_F(PendulumTest, RejectsWhatIsNotAPendulumWithAReason) {
  std::string why;
  EXPECT_FALSE(DetectPendulum(Model::Load(testing::kHumanoid), &why));
  EXPECT_NE(why.find("22 joints"), std::string::npos) << why;
  Model no_gravity = Model::FromXmlString(R"(<mujoco><option gravity="0 0 0"/><worldbody>
      <body><joint axis="0 1 0"/><geom size="0.1" pos="0 0 -1"/></body></worldbody></mujoco>)");
  EXPECT_FALSE(DetectPendulum(no_gravity, &why));
  EXPECT_NE(why.find("gravity"), std::string::npos) << why;
}

// The chapter's pendulum with `extra` inside <mujoco> and `joint` attributes on the hinge.
Model Variant(const std::string& extra, const std::string& joint = "",
              const std::string& world = "") {
  return Model::FromXmlString("<mujoco>" + extra + "<worldbody>" + world +
                              R"(<body name="link" pos="0 0 1.5">
        <joint name="hinge" axis="0 1 0" damping="0.05" )" +
                              joint + R"(/>
        <geom type="capsule" fromto="0 0 0 0 0 -1" size="0.05" mass="1"/></body>
      </worldbody></mujoco>)");
}

TEST_F(PendulumTest, RejectsWhatMakesTheFormulasWrong) {
  std::string why;
  EXPECT_TRUE(DetectPendulum(Variant(""), &why)) << why;
  // gravity switched off by flag, though opt.gravity still holds -9.81
  EXPECT_FALSE(DetectPendulum(Variant(R"(<option><flag gravity="disable"/></option>)"), &why));
  EXPECT_NE(why.find("gravity is disabled"), std::string::npos) << why;
  // a limit the swing can reach
  EXPECT_FALSE(DetectPendulum(
      Variant(R"(<compiler angle="radian"/>)", R"(limited="true" range="-0.3 0.3")"), &why));
  EXPECT_NE(why.find("limited to [-0.3, 0.3]"), std::string::npos) << why;
  // a wall within reach of the rod; a floor far below is not
  EXPECT_FALSE(DetectPendulum(
      Variant("", "", R"(<geom name="wall" type="box" pos="0.6 0 1" size="0.05 0.5 0.5"/>)"),
      &why));
  EXPECT_NE(why.find("geom 'wall'"), std::string::npos) << why;
  EXPECT_TRUE(
      DetectPendulum(Variant("", "", R"(<geom type="plane" pos="0 0 -1" size="5 5 1"/>)"), &why))
      << why;
  // the same wall with contacts disabled, or made unable to collide, is harmless
  EXPECT_TRUE(
      DetectPendulum(Variant(R"(<option><flag contact="disable"/></option>)", "",
                             R"(<geom name="wall" type="box" pos="0.6 0 1" size="0.05 0.5 0.5"/>)"),
                     &why))
      << why;
  EXPECT_TRUE(DetectPendulum(
      Variant(
          "", "",
          R"(<geom name="wall" type="box" pos="0.6 0 1" size="0.05 0.5 0.5" contype="0" conaffinity="0"/>)"),
      &why))
      << why;
}

TEST_F(PendulumTest, AMotorIsHarmlessAtZeroControlAServoIsNot) {
  std::string why;
  Model motor = Model::FromXmlString(R"(<mujoco><worldbody><body pos="0 0 1.5">
        <joint name="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0 0 -1" size="0.05" mass="1"/></body></worldbody>
      <actuator><motor joint="hinge" gear="2"/></actuator></mujoco>)");
  EXPECT_TRUE(DetectPendulum(motor, &why)) << why;
  EXPECT_EQ(ActuatorPushingAtZeroControl(motor), "");
  Model servo = Model::FromXmlString(R"(<mujoco><worldbody><body pos="0 0 1.5">
        <joint name="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0 0 -1" size="0.05" mass="1"/></body></worldbody>
      <actuator><position name="hold" joint="hinge" kp="20"/></actuator></mujoco>)");
  EXPECT_FALSE(DetectPendulum(servo, &why));
  EXPECT_NE(why.find("actuator 'hold'"), std::string::npos) << why;
}

}  // namespace
}  // namespace plumb
