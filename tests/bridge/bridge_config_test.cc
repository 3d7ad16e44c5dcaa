// The bridge's configuration file: every key read, every mistake named with file:line.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <functional>
#include <future>

#include "bridge/band.h"
#include "bridge/imu.h"
#include "bridge/motor_map.h"
#include "bridge/sport_state.h"
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
start_tick = 77
mode_machine = 3
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
  EXPECT_EQ(c.start_tick, 77u);
  EXPECT_EQ(c.mode_machine, 3);
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
  EXPECT_EQ(d.start_tick, 1000u);  // a real robot's tick counts from its boot: never 0
  EXPECT_EQ(d.mode_machine, -1);   // hg: from the motor count
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
  EXPECT_NE(Complaint("start_tick = 0\n").find("start_tick: must be in [1, 4e+09]"),
            std::string::npos)
      << Complaint("start_tick = 0\n");
  EXPECT_NE(Complaint("mode_machine = 5\n").find("mode_machine: is a unitree_hg field"),
            std::string::npos)
      << Complaint("mode_machine = 5\n");
  EXPECT_NE(Complaint("family = \"hg\"\nmode_machine = 256\n").find("mode_machine: must be in"),
            std::string::npos);
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
hold_stiffness = 0
hold_damping = 7
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
  EXPECT_EQ(c.band.hold_stiffness, 0);
  EXPECT_EQ(c.band.hold_damping, 7);
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

// The message LoadBridgeConfig gives for `path` as an IoError, or "" when it loads.
std::string Unreadable(const std::string& path) {
  try {
    LoadBridgeConfig(path);
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

// Issue 46: a missing file, a directory, /dev/zero and a FIFO are refused (a directory and
// /dev/zero ran on defaults, a FIFO hung), and so is a file over 1 MiB.
TEST(BridgeConfigTest, OnlyARegularFileIsAConfiguration) {
  testing::TempDir dir;
  EXPECT_NE(
      Unreadable(dir.File("nonexist.toml"))
          .find("no bridge config '" + dir.File("nonexist.toml") + "' (No such file or directory)"),
      std::string::npos);
  EXPECT_NE(Unreadable(dir.path()).find("is a directory, not a file"), std::string::npos);
  EXPECT_NE(Unreadable("/dev/zero").find("'/dev/zero' is a character device"), std::string::npos);
  ASSERT_EQ(mkfifo(dir.File("p").c_str(), 0600), 0);
  auto fifo = std::async(std::launch::async, [&] { return Unreadable(dir.File("p")); });
  if (fifo.wait_for(std::chrono::seconds(10)) != std::future_status::ready) {
    int fd = ::open(dir.File("p").c_str(), O_WRONLY | O_NONBLOCK);  // let it go
    if (fd >= 0) ::close(fd);
    ADD_FAILURE() << "LoadBridgeConfig waited on a FIFO";
  }
  EXPECT_NE(fifo.get().find("is a FIFO (named pipe), not a file"), std::string::npos);
  testing::WriteFile(dir.File("big.toml"), "# " + std::string(1 << 20, 'x') + "\n");
  EXPECT_NE(Unreadable(dir.File("big.toml")).find("a bridge config may be at most 1048576"),
            std::string::npos);
}

TEST(BridgeConfigTest, AByteOrderMarkIsSkipped) {
  EXPECT_EQ(Complaint("\xEF\xBB\xBF"
                      "family = \"hg\"\n"),
            "");
}

// Issue 46: a 100 KB unknown key is cut, and a key's bytes that would not print are escaped.
TEST(BridgeConfigTest, EchoedKeysAreShortAndPrintable) {
  std::string why = Complaint(std::string(100000, 'k') + " = 1\n");
  EXPECT_LT(why.size(), 600u) << why.substr(0, 600);
  EXPECT_NE(why.find(std::string(60, 'k') + "\xE2\x80\xA6 (100000 bytes): unknown key"),
            std::string::npos)
      << why.substr(0, 600);
  why = Complaint("\"a\\u0001b\" = 1\n");
  EXPECT_NE(why.find("a\\x01b: unknown key"), std::string::npos) << why;
}

// Issue 8 of 46: a motor named twice was accepted, and plumb replay then refused its log.
TEST(BridgeConfigTest, AMotorNamedTwiceIsRefused) {
  std::string why = Complaint("motors = [\"abdomen_y\", \"knee\", \"abdomen_y\"]\n");
  EXPECT_NE(why.find("b.toml:1:32: motors: 'abdomen_y' is named twice, as motor 0 (at "),
            std::string::npos)
      << why;
  EXPECT_NE(why.find("b.toml:1:11) and motor 2"), std::string::npos) << why;
}

// Unitree's H1 deploy script commands slots 0-5, 7, 8, 10, 11 for its model's legs: "" in
// motors = [...] is a slot of the robot's the model has no motor for (trailing ones too); a
// list of empty slots only is refused at its line.
TEST(BridgeConfigTest, AnEmptyMotorSlotIsRead) {
  testing::TempDir dir;
  testing::WriteFile(dir.File("b.toml"), "motors = [\"\", \"hinge\", \"\", \"\"]\n");
  BridgeConfig c = LoadBridgeConfig(dir.File("b.toml"));
  EXPECT_EQ(c.motors, (std::vector<std::string>{"", "hinge", "", ""}));
  EXPECT_EQ(c.positions.at("motors[1]"), dir.File("b.toml") + ":1:15");
  EXPECT_EQ(Complaint("motors = [\"hinge\", \"\", \"\"]\n"), "");  // not named twice
  std::string why = Complaint("family = \"go\"\nmotors = [\"\", \"\"]\n");
  EXPECT_NE(why.find("b.toml:2:10: motors: every slot is empty"), std::string::npos) << why;
  EXPECT_NE(Complaint("motors = [\"hinge\", 3]\n").find("every entry must be a name in quotes"),
            std::string::npos);
}

// Issue 46: a name the model lacks ([imu], [band], motors, [sport_state]) is reported at the
// line that wrote it.
TEST(BridgeConfigTest, NamesTheModelLacksAreReportedAtTheirLine) {
  testing::TempDir dir;
  testing::WriteFile(dir.File("b.toml"),
                     "motors = [\"hinge\", \"elbow\"]\n"
                     "[imu]\n"
                     "gyroscope = \"no_gyro\"\n"
                     "body = \"no_body\"\n"
                     "[band]\n"
                     "body = \"no_band\"\n"
                     "[sport_state]\n"
                     "base = \"no_base\"\n");
  BridgeConfig c = LoadBridgeConfig(dir.File("b.toml"));
  EXPECT_EQ(c.positions.at("motors[1]"), dir.File("b.toml") + ":1:20");
  EXPECT_EQ(c.positions.at("imu.gyroscope"), dir.File("b.toml") + ":3:13");
  Model model = Model::Load(testing::kPendulum);
  Data data(model);
  auto message = [](const std::function<void()>& bind) { return testing::ValueErrorOf(bind); };
  EXPECT_EQ(message([&] {
              bridge::MotorMap::Bind(model, c.motors, c.positions);
            }).rfind(dir.File("b.toml") + ":1:20: motor 1: 'elbow' is neither", 0),
            0u);
  EXPECT_EQ(message([&] {
              bridge::Imu::Bind(model, c.imu, bridge::kPrimaryImu, c.positions);
            }).rfind(dir.File("b.toml") + ":3:13: [imu] gyroscope = 'no_gyro'", 0),
            0u);
  c.imu.gyroscope.clear();
  EXPECT_EQ(message([&] {
              bridge::Imu::Bind(model, c.imu, bridge::kPrimaryImu, c.positions);
            }).rfind(dir.File("b.toml") + ":4:8: [imu] body = 'no_body'", 0),
            0u);
  EXPECT_EQ(message([&] {
              bridge::Band(model.get(), data.get(), c.band, c.positions);
            }).rfind(dir.File("b.toml") + ":6:8: [band] body = 'no_band'", 0),
            0u);
  EXPECT_EQ(message([&] {
              bridge::SportState::Bind(model, c.sport_state, c.positions);
            }).rfind(dir.File("b.toml") + ":8:8: [sport_state] base = 'no_base'", 0),
            0u);
}

}  // namespace
}  // namespace plumb
