// The bridge's IMU: named sensors, the first sensor of each kind, or the base body.

#include "bridge/imu.h"

#include <gtest/gtest.h>

#include <cmath>

#include "fixture.h"
#include "plumb/error.h"
#include "plumb/run.h"

namespace plumb::bridge {
namespace {

// A box that falls freely (no floor), tilted and spinning, with two IMU sites whose sensors
// disagree on purpose: the second site is turned 90 degrees about z.
constexpr char kBox[] = R"(
<mujoco>
  <worldbody>
    <body name="box" pos="0 0 1" euler="0 20 0">
      <freejoint/>
      <geom type="box" size="0.1 0.2 0.05" mass="2"/>
      <site name="imu_a"/>
      <site name="imu_b" euler="0 0 90"/>
    </body>
    <body name="other" pos="1 0 1">
      <freejoint/>
      <geom type="sphere" size="0.1"/>
    </body>
  </worldbody>
  <sensor>
    <framequat name="quat_a" objtype="site" objname="imu_a"/>
    <framequat name="quat_b" objtype="site" objname="imu_b"/>
    <gyro name="gyro_a" site="imu_a"/>
    <gyro name="gyro_b" site="imu_b"/>
    <accelerometer name="acc_a" site="imu_a"/>
    <accelerometer name="acc_b" site="imu_b"/>
  </sensor>
</mujoco>)";

constexpr char kNoSensors[] = R"(
<mujoco>
  <worldbody>
    <body name="box" pos="0 0 1"><freejoint/><geom type="box" size="0.1 0.2 0.05"/></body>
    <body name="ball" pos="1 0 1"><freejoint/><geom type="sphere" size="0.1"/></body>
  </worldbody>
</mujoco>)";

// Sets the box spinning (its own frame) and lets it fall for 10 steps; the derived arrays
// then describe the state, as the bridge has them when it reads the IMU.
void Spin(const Model& model, Data& d) {
  d->qvel[3] = 0.3;
  d->qvel[5] = 1.5;
  for (int i = 0; i < 10; ++i) mj_step(model.get(), d.get());
  RefreshDerived(model, d);
}

TEST(ImuTest, TheFirstSensorOfEachKindByDefault) {
  Model model = Model::FromXmlString(kBox);
  Data d(model);
  Spin(model, d);
  ImuReading a = Imu::Bind(model).Read(model.get(), d.get());
  ImuReading b = Imu::Bind(model, {"quat_b", "gyro_b", "acc_b", ""}).Read(model.get(), d.get());
  // a free joint's angular velocity is in the body's frame, which is site a's; the site turned
  // 90 degrees about z sees the x rate on its -y axis and the y rate on its x axis
  EXPECT_NEAR(a.gyroscope[0], d->qvel[3], 1e-9);
  EXPECT_NEAR(a.gyroscope[1], d->qvel[4], 1e-9);
  EXPECT_NEAR(b.gyroscope[1], -d->qvel[3], 1e-9);
  EXPECT_NEAR(b.gyroscope[0], d->qvel[4], 1e-9);
  EXPECT_NEAR(a.gyroscope[2], b.gyroscope[2], 1e-9);
  mjtNum turn[4] = {std::sqrt(0.5), 0, 0, std::sqrt(0.5)}, expected[4];
  mju_mulQuat(expected, a.quaternion.data(), turn);
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(b.quaternion[k], expected[k], 1e-6) << k;
  // falling freely, an accelerometer reads (almost) nothing
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(a.accelerometer[k], 0, 1e-3) << k;
}

TEST(ImuTest, EachNamedSensorIsTakenOnItsOwn) {
  Model model = Model::FromXmlString(kBox);
  Data d(model);
  Spin(model, d);
  ImuReading mixed = Imu::Bind(model, {"", "gyro_b", "", ""}).Read(model.get(), d.get());
  ImuReading a = Imu::Bind(model).Read(model.get(), d.get());
  EXPECT_EQ(mixed.quaternion, a.quaternion);
  EXPECT_NEAR(mixed.gyroscope[1], -d->qvel[3], 1e-9);
}

TEST(ImuTest, WithoutSensorsTheBaseBodyIsRead) {
  Model model = Model::FromXmlString(kNoSensors);
  Data d(model);
  Spin(model, d);
  ImuReading base = Imu::Bind(model).Read(model.get(), d.get());
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(base.gyroscope[k], d->qvel[3 + k], 1e-9) << k;  // the first free body: the box
    EXPECT_NEAR(base.accelerometer[k], 0, 1e-3) << k;           // falling freely
  }
  EXPECT_NEAR(base.quaternion[0], d->qpos[3], 1e-12);
  ImuReading ball = Imu::Bind(model, {"", "", "", "ball"}).Read(model.get(), d.get());
  EXPECT_NEAR(ball.gyroscope[2], 0, 1e-12);  // the ball does not spin
  EXPECT_NEAR(ball.quaternion[0], 1, 1e-12);
}

TEST(ImuTest, ABodyAtRestReadsGravityAsUpwardSpecificForce) {
  Model model = Model::FromXmlString(R"(
<mujoco><worldbody><geom type="plane" size="5 5 0.1"/>
  <body name="box" pos="0 0 0.05"><freejoint/><geom type="box" size="0.1 0.1 0.05"/></body>
</worldbody></mujoco>)");
  Data d(model);
  for (int i = 0; i < 500; ++i) mj_step(model.get(), d.get());
  RefreshDerived(model, d);
  ImuReading reading = Imu::Bind(model).Read(model.get(), d.get());
  EXPECT_NEAR(reading.accelerometer[2], 9.81, 0.05);
  EXPECT_NEAR(reading.accelerometer[0], 0, 0.05);
}

TEST(ImuTest, AMissingOrWrongNameSaysWhatTheModelHas) {
  Model model = Model::FromXmlString(kBox);
  try {
    Imu::Bind(model, {"", "acc_a", "", ""});
    FAIL() << "no error";
  } catch (const ValueError& e) {
    EXPECT_STREQ(e.what(),
                 "[imu] gyroscope = 'acc_a': the model has no gyro sensor of that name (it has "
                 "'gyro_a', 'gyro_b')");
  }
  EXPECT_THROW(Imu::Bind(model, {"", "", "", "nosuch"}), ValueError);
  EXPECT_THROW(Imu::Bind(model, {"", "", "", "world"}), ValueError);
  Model plain = Model::FromXmlString(kNoSensors);
  try {
    Imu::Bind(plain, {"q", "", "", ""});
    FAIL() << "no error";
  } catch (const ValueError& e) {
    EXPECT_NE(std::string(e.what()).find("it has none"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace plumb::bridge
