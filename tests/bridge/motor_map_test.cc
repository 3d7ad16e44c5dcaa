// Motors bound to actuators or joints, read from sensors or state, driven by the PD law.

#include "bridge/motor_map.h"

#include <gtest/gtest.h>

#include "bridge/pd_law.h"
#include "fixture.h"
#include "plumb/error.h"

namespace plumb::bridge {
namespace {

const char* kArm = R"(
  <mujoco><worldbody><body><joint name="shoulder" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.03" mass="1"/>
      <body pos="0.5 0 0"><joint name="elbow" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.03" mass="0.5"/></body></body>
    </worldbody>
    <actuator>
      <motor name="elbow_motor" joint="elbow" gear="2" ctrlrange="-5 5" ctrllimited="true"/>
      <motor name="shoulder_motor" joint="shoulder" gear="1" ctrlrange="-10 10" ctrllimited="true"
             forcerange="-8 8" forcelimited="true"/>
      <position name="servo" joint="shoulder" kp="10"/>
    </actuator>
    <sensor><jointpos name="elbow_q" joint="elbow"/><actuatorfrc actuator="elbow_motor"/></sensor>
  </mujoco>)";

TEST(MotorMapTest, BindsActuatorsAndJointsByName) {
  Model model = Model::FromXmlString(kArm, "arm.xml");
  MotorMap map = MotorMap::Bind(model, {"shoulder_motor", "elbow_motor", "elbow"});
  ASSERT_EQ(map.size(), 3u);
  const Motor& shoulder = map.motors()[0];
  EXPECT_EQ(shoulder.actuator, 1);
  EXPECT_DOUBLE_EQ(shoulder.torque_lo, -8);  // forcerange x gear is tighter than ctrlrange
  EXPECT_DOUBLE_EQ(shoulder.torque_hi, 8);
  const Motor& elbow = map.motors()[1];
  EXPECT_DOUBLE_EQ(elbow.torque_per_ctrl, 2);
  EXPECT_DOUBLE_EQ(elbow.torque_hi, 10);  // ctrl 5 x gear 2
  EXPECT_GE(elbow.sensor_q, 0);
  EXPECT_GE(elbow.sensor_tau, 0);
  EXPECT_EQ(map.motors()[2].actuator, -1);  // the joint itself, through qfrc_applied
}

// "" is a slot of the robot's the model has no motor for: it reads 0 and drives nothing.
TEST(MotorMapTest, AnEmptySlotReadsZeroAndDrivesNothing) {
  Model model = Model::FromXmlString(kArm, "arm.xml");
  MotorMap map = MotorMap::Bind(model, {"", "elbow_motor", ""});
  ASSERT_EQ(map.size(), 3u);
  EXPECT_TRUE(map.motors()[0].empty());
  EXPECT_FALSE(map.motors()[1].empty());
  EXPECT_TRUE(map.motors()[2].empty());
  EXPECT_EQ(map.EmptySlots(), (std::vector<bool>{true, false, true}));
  Data data(model);
  data->qpos[0] = 0.2;
  data->qvel[0] = 0.4;
  EXPECT_DOUBLE_EQ(map.Apply(data.get(), 0, 4), 0);
  EXPECT_DOUBLE_EQ(map.Apply(data.get(), 1, 4), 4);
  data.Forward();
  for (std::size_t slot : {0u, 2u}) {
    EXPECT_EQ(map.Q(data.get(), slot), 0);
    EXPECT_EQ(map.Dq(data.get(), slot), 0);
    EXPECT_EQ(map.TauEst(data.get(), slot), 0);
  }
  for (int i = 0; i < model->nv; ++i) EXPECT_EQ(data->qfrc_applied[i], 0);
  EXPECT_DOUBLE_EQ(data->ctrl[0], 2);  // the elbow's 4 N*m; nothing else
  EXPECT_EQ(data->ctrl[1], 0);
  std::string why = testing::ValueErrorOf([&] { MotorMap::Bind(model, {"", ""}); });
  EXPECT_NE(why.find("every slot in motors = [...] is empty"), std::string::npos) << why;
}

TEST(MotorMapTest, ReadsAndAppliesTorque) {
  Model model = Model::FromXmlString(kArm, "arm.xml");
  MotorMap map = MotorMap::Bind(model, {"shoulder_motor", "elbow_motor", "elbow"});
  Data data(model);
  data->qpos[1] = 0.3;
  data->qvel[1] = -0.5;
  EXPECT_DOUBLE_EQ(map.Apply(data.get(), 1, 4), 4);
  EXPECT_DOUBLE_EQ(data->ctrl[0], 2);                  // 4 N*m / gear 2
  EXPECT_DOUBLE_EQ(map.Apply(data.get(), 1, 50), 10);  // clipped
  EXPECT_DOUBLE_EQ(map.Apply(data.get(), 2, 0.7), 0.7);
  EXPECT_DOUBLE_EQ(data->qfrc_applied[1], 0.7);
  map.Apply(data.get(), 1, 4);
  data.Forward();
  EXPECT_DOUBLE_EQ(map.Q(data.get(), 1), 0.3);     // from the jointpos sensor
  EXPECT_DOUBLE_EQ(map.Dq(data.get(), 1), -0.5);   // from qvel: no jointvel sensor
  EXPECT_DOUBLE_EQ(map.TauEst(data.get(), 1), 4);  // actuatorfrc 2 x gear 2
}

// MuJoCo 3.x: a jointactuatorfrc sensor measures the torque at the joint (gear included), and
// tau_est reads it rather than the actuator's own force
TEST(MotorMapTest, TauEstReadsAJointActuatorFrcSensor) {
  if (!(mjVERSION_HEADER >= 3011000)) GTEST_SKIP() << "no jointactuatorfrc in this MuJoCo";
  Model model = Model::FromXmlString(testing::TwoHingeArm(R"(
      <motor name="m" joint="b" gear="2" ctrlrange="-3 3" ctrllimited="true"/>
    </actuator><sensor><jointactuatorfrc name="tau_b" joint="b"/></sensor><actuator>)"));
  MotorMap map = MotorMap::Bind(model, {"m"});
  const Motor& motor = map.motors()[0];
  EXPECT_TRUE(motor.tau_at_joint);
  EXPECT_EQ(motor.sensor_tau, model->sensor_adr[0]);
  Data data(model);
  map.Apply(data.get(), 0, 4);
  data.Forward();
  data->sensordata[motor.sensor_tau] = 3.25;  // read from the sensor, not from the force
  EXPECT_DOUBLE_EQ(map.TauEst(data.get(), 0), 3.25);
  data.Forward();
  EXPECT_DOUBLE_EQ(map.TauEst(data.get(), 0), 4);  // ctrl 2 x gear 2, measured at the joint
}

TEST(MotorMapTest, RefusesWhatIsNotATorqueMotor) {
  Model model = Model::FromXmlString(kArm, "arm.xml");
  try {
    MotorMap::Bind(model, {"servo"});
    FAIL() << "no error";
  } catch (const ValueError& e) {
    EXPECT_NE(std::string(e.what()).find("not a torque motor"), std::string::npos) << e.what();
  }
  EXPECT_THROW(MotorMap::Bind(model, {"knee"}), ValueError);
  Model pendulum = Model::Load(testing::kPendulum);
  EXPECT_THROW(MotorMap::Bind(pendulum, {}), ValueError);  // no actuators: name the joints
  EXPECT_EQ(MotorMap::Bind(pendulum, {"hinge"}).size(), 1u);
}

// MuJoCo 3.12+: a pid before the motor takes two controls, so the motor's control and force
// rows are not its actuator id
TEST(MotorMapTest, AMotorAfterAPidDrivesItsOwnControl) {
  if (!(mjVERSION_HEADER >= 3012000)) GTEST_SKIP() << "pid actuators came with MuJoCo 3.12";
  Model model = Model::FromXmlString(testing::TwoHingeArm(R"(<pid name="p" joint="a" kp="10" kv="1"/>
      <motor name="m" joint="b" gear="2" ctrlrange="-3 3" ctrllimited="true"/>)"));
  MotorMap map = MotorMap::Bind(model, {"m"});
  const Motor& motor = map.motors()[0];
  EXPECT_EQ(motor.actuator, 1);
  EXPECT_EQ(motor.ctrl, 2);  // after the pid's position and velocity setpoints
  EXPECT_DOUBLE_EQ(motor.torque_hi, 6);  // its own ctrlrange 3 x gear 2
  Data data(model);
  EXPECT_DOUBLE_EQ(map.Apply(data.get(), 0, 4), 4);
  EXPECT_DOUBLE_EQ(data->ctrl[2], 2);
  EXPECT_DOUBLE_EQ(data->ctrl[1], 0);  // the pid's velocity setpoint is untouched
  data.Forward();
  EXPECT_DOUBLE_EQ(map.TauEst(data.get(), 0), 4);
  // bound by default, the pid is refused by name, not mistaken for the motor
  try {
    MotorMap::Bind(model, {});
    FAIL() << "no error";
  } catch (const ValueError& e) {
    EXPECT_NE(std::string(e.what()).find("actuator 'p'"), std::string::npos) << e.what();
  }
}

TEST(PdLawTest, IsUnitreesLawAndModeZeroIsLimp) {
  MotorCommand c;
  c.mode = 1;
  c.q = 0.5;
  c.dq = 0;
  c.tau = 0.2;
  c.kp = 50;
  c.kd = 3.5;
  EXPECT_DOUBLE_EQ(PdTorque(c, 0.4, 0.1), 0.2 + 50 * 0.1 - 3.5 * 0.1);
  c.mode = 0;
  EXPECT_DOUBLE_EQ(PdTorque(c, 0.4, 0.1), 0);
  c.kp = NAN;
  EXPECT_FALSE(c.finite());
}

// Issue 46: a motor the model lacks is reported at the line of the configuration that named it.
TEST(MotorMapTest, AnUnknownNameIsReportedAtItsLine) {
  Model model = Model::FromXmlString(kArm, "arm.xml");
  BridgePositions positions = {{"motors[1]", "b.toml:3:22"}};
  EXPECT_EQ(testing::ValueErrorOf([&] { MotorMap::Bind(model, {"elbow", "knee"}, positions); }),
            "b.toml:3:22: motor 1: 'knee' is neither an actuator nor a joint of 'arm.xml'");
  EXPECT_EQ(testing::ValueErrorOf([&] { MotorMap::Bind(model, {"servo"}, {{"motors[0]", "b:1:2"}}); })
                .rfind("b:1:2: motor 0 (actuator 'servo'", 0),
            0u);
  // without positions (a configuration built in code) as before
  EXPECT_EQ(testing::ValueErrorOf([&] { MotorMap::Bind(model, {"knee"}); }),
            "motor 0: 'knee' is neither an actuator nor a joint of 'arm.xml'");
}

}  // namespace
}  // namespace plumb::bridge
