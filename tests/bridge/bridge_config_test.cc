// The bridge's configuration file: every key read, every mistake named with file:line.

#include <gtest/gtest.h>

#include "fixture.h"
#include "plumb/bridge.h"
#include "plumb/error.h"

namespace plumb {
namespace {

// The message LoadBridgeConfig gives for `text`, or "" when it loads.
std::string Complaint(const std::string& text) {
  testing::TempDir dir;
  testing::WriteFile(dir.File("b.toml"), text);
  try {
    LoadBridgeConfig(dir.File("b.toml"));
  } catch (const ValueError& e) {
    return e.what();
  }
  return "";
}

TEST(BridgeConfigTest, DefaultsAndKeys) {
  testing::TempDir dir;
  testing::WriteFile(dir.File("b.toml"), R"(family = "hg"
mode = "realtime"
domain = 7
control_period = 0.004
motors = ["a", "b"]
check_crc = false
log = "f.csv"
until = 2.5
command_queue = 8
[watchdog]
timeout_ms = 250
kd = 3
[imu]
quaternion = "orientation"
gyroscope = "imu_gyro"
accelerometer = "imu_acc"
body = "pelvis"
)");
  BridgeConfig c = LoadBridgeConfig(dir.File("b.toml"));
  EXPECT_EQ(c.family, BridgeFamily::kHg);
  EXPECT_EQ(c.mode, BridgeMode::kRealtime);
  EXPECT_EQ(c.domain, 7u);
  EXPECT_EQ(c.control_period, 0.004);
  EXPECT_EQ(c.motors, (std::vector<std::string>{"a", "b"}));
  EXPECT_FALSE(c.check_crc);
  EXPECT_EQ(c.log, "f.csv");
  EXPECT_EQ(c.until, 2.5);
  EXPECT_EQ(c.command_queue, 8u);
  EXPECT_EQ(c.watchdog_timeout, 0.25);
  EXPECT_EQ(c.watchdog_kd, 3);
  EXPECT_EQ(c.imu.quaternion, "orientation");
  EXPECT_EQ(c.imu.gyroscope, "imu_gyro");
  EXPECT_EQ(c.imu.accelerometer, "imu_acc");
  EXPECT_EQ(c.imu.body, "pelvis");
  testing::WriteFile(dir.File("empty.toml"), "");
  BridgeConfig d = LoadBridgeConfig(dir.File("empty.toml"));
  EXPECT_EQ(d.family, BridgeFamily::kGo);
  EXPECT_EQ(d.mode, BridgeMode::kLockstep);
  EXPECT_TRUE(d.imu.quaternion.empty() && d.imu.body.empty());
  EXPECT_TRUE(d.check_crc);
  EXPECT_EQ(d.command_queue, 64u);
}

TEST(BridgeConfigTest, MistakesNameTheFileLineAndKey) {
  EXPECT_NE(Complaint("[imu]\ngyro = \"g\"\n").find("b.toml:2:8: imu.gyro: unknown key"),
            std::string::npos)
      << Complaint("[imu]\ngyro = \"g\"\n");
  EXPECT_NE(Complaint("[imu]\nbody = 3\n").find("imu.body: must be a body's name in quotes"),
            std::string::npos);
  EXPECT_NE(Complaint("imu = 1\n").find("imu: must be a table"), std::string::npos);
  EXPECT_NE(Complaint("log = \"\"\n").find("log: must be a file name"), std::string::npos);
  EXPECT_NE(Complaint("domain = 1.5\n").find("domain: must be a whole number"), std::string::npos);
  EXPECT_NE(Complaint("command_queue = 0\n").find("command_queue: must be in [1, 1e+06]"),
            std::string::npos)
      << Complaint("command_queue = 0\n");
  EXPECT_NE(Complaint("mode = \"fast\"\n").find("b.toml:1:8: mode: must be one of"),
            std::string::npos)
      << Complaint("mode = \"fast\"\n");
}

TEST(BridgeConfigTest, FaultsAreRead) {
  testing::TempDir dir;
  testing::WriteFile(dir.File("b.toml"), R"(seed = 3
[[faults]]
kind = "drop"
direction = "state"
probability = 0.1
start = 1
stop = 2
[[faults]]
kind = "motor_failure"
motor = 2
behavior = "stuck"
)");
  BridgeConfig c = LoadBridgeConfig(dir.File("b.toml"));
  ASSERT_EQ(c.faults.size(), 2u);
  EXPECT_TRUE(c.faults[0].state);
  EXPECT_EQ(c.faults[0].text, "drop of states (p = 0.1) from 1 s to 2 s");
  EXPECT_TRUE(c.faults[1].stuck);
  EXPECT_EQ(c.seed, 3u);
  testing::WriteFile(dir.File("bad.toml"), "[[faults]]\nkind = \"motor_failure\"\n");
  try {
    LoadBridgeConfig(dir.File("bad.toml"));
    FAIL() << "no error";
  } catch (const ValueError& e) {
    EXPECT_NE(std::string(e.what()).find("faults[0].motor"), std::string::npos) << e.what();
  }
}

// The tables of what goes out beside rt/lowstate: the second IMU, the sport-mode state, the
// band and the gamepad (whose events file is found beside the configuration).
TEST(BridgeConfigTest, SportStateBandGamepadAndSecondImu) {
  testing::TempDir dir;
  testing::WriteFile(dir.File("b.toml"), R"([secondary_imu]
body = "torso_link"
[sport_state]
base = "pelvis"
feet = ["left_foot", "right_foot"]
[band]
body = "torso_link"
anchor = [0, 0, 2.5]
stiffness = 500
damping = 50
length = 0.5
release_at = 2
release_button = "A"
[gamepad]
events = "pad.txt"
rate = 50
topics = ["rt/wirelesscontroller"]
)");
  BridgeConfig c = LoadBridgeConfig(dir.File("b.toml"));
  EXPECT_TRUE(c.secondary_imu_configured);
  EXPECT_EQ(c.secondary_imu.body, "torso_link");
  EXPECT_TRUE(c.sport_state.publish);
  EXPECT_EQ(c.sport_state.base, "pelvis");
  EXPECT_EQ(c.sport_state.feet, (std::vector<std::string>{"left_foot", "right_foot"}));
  EXPECT_EQ(c.band.body, "torso_link");
  EXPECT_EQ(c.band.anchor[2], 2.5);
  EXPECT_EQ(c.band.stiffness, 500);
  EXPECT_EQ(c.band.damping, 50);
  EXPECT_EQ(c.band.length, 0.5);
  EXPECT_EQ(c.band.release_at, 2);
  EXPECT_EQ(c.band.release_button, "A");
  EXPECT_EQ(c.gamepad.events, dir.File("pad.txt"));
  EXPECT_EQ(c.gamepad.rate, 50);
  EXPECT_EQ(c.gamepad.topics, (std::vector<std::string>{"rt/wirelesscontroller"}));
  testing::WriteFile(dir.File("e.toml"), "");
  BridgeConfig plain = LoadBridgeConfig(dir.File("e.toml"));
  EXPECT_FALSE(plain.secondary_imu_configured);
  EXPECT_TRUE(plain.band.body.empty());
  EXPECT_TRUE(plain.gamepad.events.empty());
  EXPECT_EQ(plain.gamepad.topics.size(), 2u);
}

TEST(BridgeConfigTest, MistakesInTheNewTablesAreNamed) {
  EXPECT_NE(Complaint("[sport_state]\nfeet = [\"a\", \"b\", \"c\", \"d\", \"e\"]\n")
                .find("b.toml:2:8: sport_state.feet: 5 feet, but SportModeState_ carries 4"),
            std::string::npos);
  EXPECT_NE(Complaint("[band]\nbody = \"t\"\nrelease_button = \"jump\"\n")
                .find("band.release_button: 'jump' is not a gamepad button (buttons: R1, L1"),
            std::string::npos);
  EXPECT_NE(
      Complaint("[band]\nbody = \"t\"\nanchor = [0, 1]\n").find("band.anchor: must be [x, y, z]"),
      std::string::npos);
  EXPECT_NE(Complaint("[band]\nstiffness = 5\n").find("band.body: is missing"), std::string::npos);
  EXPECT_NE(Complaint("[gamepad]\nrate = 0\n").find("gamepad.rate: must be in [1, 10000]"),
            std::string::npos);
  EXPECT_NE(Complaint("[gamepad]\njoystick = 1\n").find("gamepad.joystick: unknown key"),
            std::string::npos);
  EXPECT_NE(Complaint("gamepad = 3\n").find("gamepad: must be a table: [gamepad]"),
            std::string::npos);
}

}  // namespace
}  // namespace plumb
