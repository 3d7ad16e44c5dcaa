// The flight recorder's columns: every one named by joint, sensor, actuator or motor.

#include "bridge/flight_recorder.h"

#include <gtest/gtest.h>

#include "fixture.h"

namespace plumb::bridge {
namespace {

// The header line of a new log.
std::string Header(const std::string& xml, const std::vector<std::string>& motors) {
  Model model = Model::FromXmlString(xml, "robot.xml");
  testing::TempDir dir;
  {
    FlightRecorder recorder(dir.File("log.csv"), model, MotorMap::Bind(model, motors));
    recorder.Finish();
  }
  std::string text = testing::ReadFile(dir.File("log.csv"));
  return text.substr(0, text.find('\n'));
}

TEST(FlightRecorderTest, NamesEveryColumnByJointSensorOrMotor) {
  // motor order (b, a) differs from MuJoCo's joint order (a, b)
  std::string header = Header(R"(<mujoco><worldbody><body><freejoint/>
      <geom type="box" size="0.1 0.1 0.1"/>
      <body><joint name="a" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02"/>
        <body pos="0.3 0 0"><joint name="b" axis="0 1 0"/>
          <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02"/></body></body></body>
    </worldbody>
    <actuator><motor name="motor_a" joint="a"/><motor name="motor_b" joint="b"/></actuator>
    <sensor><jointpos name="angle_b" joint="b"/><framequat name="orientation" objtype="body"
      objname="world"/></sensor></mujoco>)",
                              {"motor_b", "a"});
  EXPECT_EQ(header,
            "time,kind,event,"
            "qpos[0],qpos[1],qpos[2],qpos[3],qpos[4],qpos[5],qpos[6],qpos[a],qpos[b],"
            "qvel[0],qvel[1],qvel[2],qvel[3],qvel[4],qvel[5],qvel[a],qvel[b],"
            "ctrl[motor_b],qfrc_applied[a],"
            "sensordata[angle_b],sensordata[orientation][0],sensordata[orientation][1],"
            "sensordata[orientation][2],sensordata[orientation][3],"
            "cmd.mode[motor_b],cmd.q[motor_b],cmd.dq[motor_b],cmd.kp[motor_b],cmd.kd[motor_b],"
            "cmd.tau[motor_b],cmd.mode[a],cmd.q[a],cmd.dq[a],cmd.kp[a],cmd.kd[a],cmd.tau[a],"
            "state.q[motor_b],state.dq[motor_b],state.tau_est[motor_b],"
            "state.q[a],state.dq[a],state.tau_est[a]");
}

}  // namespace
}  // namespace plumb::bridge
