// What the bridge publishes beside rt/lowstate, end to end on loopback DDS with controllers in
// the test program: a G1 from the robot corpus hangs on the elastic band, then stands once it
// lets go, under a plain PD controller, with rt/sportmodestate and rt/secondary_imu reporting
// it; a gamepad events file switches a controller's mode; faults reach the sport-mode state.
// Lockstep and realtime both.

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <future>
#include <string>
#include <vector>

#include "bridge/bridge_fixture.h"
#include "bridge/dds_link.h"
#include "bridge/gamepad_script.h"
#include "bridge/messages.h"
#include "bridge/test_domain.h"
#include "bridge/unitree_crc.h"
#include "fixture.h"
#include "plumb/bridge.h"

namespace plumb {
namespace {

using bridge::PadMessage;
using bridge::SportMessage;
using HgCmd = unitree_hg_msg_dds__LowCmd_;
using HgState = unitree_hg_msg_dds__LowState_;
using HgImu = unitree_hg_msg_dds__IMUState_;

class ModeTest : public ::testing::TestWithParam<BridgeMode> {};

std::string ModeName(const ::testing::TestParamInfo<BridgeMode>& info) {
  return info.param == BridgeMode::kLockstep ? "Lockstep" : "Realtime";
}

// Takes every sample waiting on `reader`, keeping the last in `last`; returns how many.
template <typename T>
int TakeAll(bridge::DdsReader<T>& reader, T* last) {
  int n = 0;
  while (reader.Take(last)) ++n;
  return n;
}

// The G1's 29 joints in Unitree's motor order (legs, waist, arms), as plain joint motors.
const std::vector<std::string> kG1Joints = {
    "left_hip_pitch_joint",      "left_hip_roll_joint",        "left_hip_yaw_joint",
    "left_knee_joint",           "left_ankle_pitch_joint",     "left_ankle_roll_joint",
    "right_hip_pitch_joint",     "right_hip_roll_joint",       "right_hip_yaw_joint",
    "right_knee_joint",          "right_ankle_pitch_joint",    "right_ankle_roll_joint",
    "waist_yaw_joint",           "waist_roll_joint",           "waist_pitch_joint",
    "left_shoulder_pitch_joint", "left_shoulder_roll_joint",   "left_shoulder_yaw_joint",
    "left_elbow_joint",          "left_wrist_roll_joint",      "left_wrist_pitch_joint",
    "left_wrist_yaw_joint",      "right_shoulder_pitch_joint", "right_shoulder_roll_joint",
    "right_shoulder_yaw_joint",  "right_elbow_joint",          "right_wrist_roll_joint",
    "right_wrist_pitch_joint",   "right_wrist_yaw_joint"};

// Calls `answer` on every state that arrives in `*s`, until the bridge's run ends (or a
// minute passes).
template <typename S, typename Answer>
void Serve(bridge::DdsReader<S>& states, S* s, std::future<BridgeStats>& run, Answer answer) {
  auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline) {
    if (states.Take(s)) {
      answer();
    } else if (run.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
      return;
    } else {
      states.Wait(DDS_MSECS(20));
    }
  }
}

// The standing pose Unitree's G1 policies start from: knees a little bent (rad).
double StandingAngle(std::size_t motor) {
  switch (motor % 6) {
    case 0:
      return motor < 12 ? -0.1 : 0;  // hip pitch
    case 3:
      return motor < 12 ? 0.3 : 0;  // knee
    case 4:
      return motor < 12 ? -0.2 : 0;  // ankle pitch
    default:
      return 0;
  }
}

// The tilt of a (w, x, y, z) orientation from upright: the angle between its z axis and the
// world's, rad.
double Tilt(const float q[4]) {
  double w = q[0], x = q[1], y = q[2], z = q[3];
  double n2 = w * w + x * x + y * y + z * z;
  return std::acos(std::clamp(1 - 2 * (x * x + y * y) / n2, -1.0, 1.0));
}

// A G1 from the corpus, with a floor under it, hangs on the band where it starts, then stands
// once the band lets go at 1 s, held by nothing but PD on its joints (kp 150 legs and waist,
// 40 arms). rt/sportmodestate reports the pelvis and both feet; rt/secondary_imu the torso.
TEST_P(ModeTest, AG1HangsOnTheBandThenStandsOnceReleased) {
  std::string g1 = testing::RequireCorpusModel("mjlab-1.6.0/unitree_g1/xmls/g1.xml");
  if (g1.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  testing::TempDir dir;
  // a floor, and the joints' armature (the motors' reflected inertia), which mjlab sets in
  // Python where its MJCF has none: without it the wrists' stiff PD is unstable at 2 ms
  Model model = Model::Load(testing::EditedModelCopy(
      g1,
      {{"<worldbody>", R"(<worldbody><geom name="floor" type="plane" size="0 0 0.05"/>)"},
       {R"(<default class="g1">)", R"(<default class="g1"><joint armature="0.02"/>)"}},
      dir.path()));
  BridgeConfig config;
  config.family = BridgeFamily::kHg;
  config.mode = GetParam();
  config.domain = testing::FreeDomain();
  config.motors = kG1Joints;
  config.until = 3.0;
  config.watchdog_timeout = 3.0;
  config.log = dir.File("log.csv");
  config.band.body = "torso_link";  // above the robot's centre of mass: it hangs upright
  config.band.release_at = 1.0;
  config.sport_state.feet = {"left_foot", "right_foot"};
  config.secondary_imu.body = "torso_link";
  config.secondary_imu_configured = true;

  bridge::DdsDomain domain(config.domain);
  bridge::DdsWriter<HgCmd> commands(domain, "rt/lowcmd", &unitree_hg_msg_dds__LowCmd__desc);
  bridge::DdsReader<HgState> states(domain, "rt/lowstate", &unitree_hg_msg_dds__LowState__desc);
  bridge::DdsReader<SportMessage> sport(domain, "rt/sportmodestate", bridge::SportType());
  bridge::DdsReader<HgImu> torso(domain, "rt/secondary_imu", &unitree_hg_msg_dds__IMUState__desc);
  StopSource stop;
  auto run =
      std::async(std::launch::async, [&] { return RunBridge(model, {}, config, stop.token()); });
  double mass = model->body_subtreemass[1];
  struct Seen {
    double z = NAN, height = NAN, feet = NAN, tilt = NAN, torso_tilt = NAN;
  } hanging, standing;
  int sport_count = 0, torso_count = 0, untyped = 0;
  HgState s;
  SportMessage last_sport{};
  HgImu last_torso{};
  Serve(states, &s, run, [&] {
    sport_count += TakeAll(sport, &last_sport);
    torso_count += TakeAll(torso, &last_torso);
    Seen now{last_sport.position[2], last_sport.body_height,
             double(last_sport.foot_force[0]) + last_sport.foot_force[1],
             Tilt(s.imu_state.quaternion), Tilt(last_torso.quaternion)};
    if (SimMs(s) == 900) hanging = now;
    if (SimMs(s) >= 2900) standing = now;
    // a G1 rev 1.0 of 29 motors reports type 5, as Unitree's g1_description says
    if (s.mode_machine != 5) ++untyped;
    HgCmd cmd;
    std::memset(&cmd, 0, sizeof cmd);
    for (std::size_t i = 0; i < kG1Joints.size(); ++i) {
      auto& m = cmd.motor_cmd[i];
      m.mode = 1;
      m.q = static_cast<float>(StandingAngle(i));
      m.kp = i < 12 ? 400 : i < 15 ? 200 : 40;
      m.kd = i < 12 ? 8 : i < 15 ? 5 : 2;
    }
    cmd.crc = bridge::UnitreeCrc(cmd);
    commands.Write(cmd);
  });
  stop.RequestStop();
  BridgeStats stats = run.get();
  EXPECT_EQ(untyped, 0) << "states whose mode_machine is not 5";
  ASSERT_FALSE(stats.diverged) << stats.problem;
  EXPECT_NEAR(stats.band_released, 1.0, 0.0021);
  EXPECT_GT(sport_count, 1000);
  EXPECT_GT(torso_count, 1000);
  double weight = mass * 9.81;
  // hanging: where it started, the band carrying the weight (the feet at most a tenth)
  EXPECT_NEAR(hanging.z, 0.793, 0.03);
  EXPECT_LT(hanging.feet, 0.1 * weight);
  // upright, as a hoist holds it: the band's body within 0.6 degrees, the pelvis below it
  // within what the waist's PD lets it sag (without the hold: 0.062 and 0.057 rad)
  EXPECT_LT(hanging.torso_tilt, 0.01);
  EXPECT_LT(hanging.tilt, 0.03);
  // standing: upright on its feet, which carry its weight
  EXPECT_GT(standing.z, 0.7);
  EXPECT_LT(standing.tilt, 0.15);
  EXPECT_LT(standing.torso_tilt, 0.15);
  EXPECT_NEAR(standing.feet, weight, 0.1 * weight);
  EXPECT_GT(standing.height, 0.6);  // the pelvis above the soles' sites
  std::string log = testing::ReadFile(config.log);
  EXPECT_NE(log.find("band: torso_link hangs from"), std::string::npos);
  EXPECT_NE(log.find("band: released at t = 1 s (release_at)"), std::string::npos);
}

// A controller damps (kp 0) until the gamepad's start comes on rt/wirelesscontroller, then
// holds the pendulum at 0.5 rad: the events file switches its mode at 0.5 s, and
// rt/lowstate's wireless_remote carries the same keys.
TEST_P(ModeTest, AGamepadFileSwitchesAControllersMode) {
  testing::TempDir dir;
  testing::WriteFile(dir.File("pad.txt"), "# the operator\nt = 0.5: start\n");
  Model model = Model::Load(testing::kPendulum);
  BridgeConfig config = PendulumConfig(testing::FreeDomain(), 1.5);
  config.mode = GetParam();
  config.gamepad.events = dir.File("pad.txt");
  config.log = dir.File("log.csv");
  bridge::DdsDomain domain(config.domain);
  bridge::DdsWriter<Cmd> commands(domain, "rt/lowcmd", &unitree_go_msg_dds__LowCmd__desc);
  bridge::DdsReader<State> states(domain, "rt/lowstate", &unitree_go_msg_dds__LowState__desc);
  bridge::DdsReader<PadMessage> pad(domain, "rt/wirelesscontroller", bridge::PadType());
  StopSource stop;
  auto run = std::async(std::launch::async, [&] {
    return RunBridge(model, {ParseAssignment(model, "qpos[hinge]=0.7")}, config, stop.token());
  });
  bool holding = false;
  double switched = NAN, remote_start = NAN, q = NAN;
  State s;
  PadMessage p{};
  Serve(states, &s, run, [&] {
    double t = SimMs(s) / 1000.0;
    q = s.motor_state[0].q;
    std::uint16_t remote = s.wireless_remote[2] | s.wireless_remote[3] << 8;
    if (std::isnan(remote_start) && (remote >> 2 & 1)) remote_start = t;
    while (pad.Take(&p)) {
      if (!holding && (p.keys >> 2 & 1)) {
        holding = true;
        switched = t;
      }
    }
    Cmd cmd = Hold(0.5);
    if (!holding) {
      cmd.motor_cmd[0].kp = 0;
      cmd.motor_cmd[0].tau = 0;
    }
    cmd.crc = bridge::UnitreeCrc(cmd);
    commands.Write(cmd);
  });
  stop.RequestStop();
  BridgeStats stats = run.get();
  EXPECT_NEAR(switched, 0.5, 0.05);
  EXPECT_NEAR(remote_start, 0.5, 0.005);
  EXPECT_NEAR(q, 0.5, 0.02);
  EXPECT_GE(stats.gamepad_messages, 140);  // 100 Hz of simulated time
  std::string log = testing::ReadFile(config.log);
  EXPECT_NE(log.find("gamepad: start pressed for 0.1 s"), std::string::npos);
  EXPECT_NE(log.find(",gamepad,lx 0 ly 0 rx 0 ry 0 keys 0x0004 (start),"), std::string::npos);
}

// A 2 kg box hangs on the band with the default rest length: where it starts, the band
// carrying its weight; the gamepad's A (pressed at 0.3 s) lets it fall.
TEST_P(ModeTest, TheGamepadsButtonReleasesTheBand) {
  testing::TempDir dir;
  testing::WriteFile(dir.File("pad.txt"), "t = 0.3: A\n");
  Model model = Model::FromXmlString(R"(<mujoco><worldbody><body name="box" pos="0 0 1">
      <freejoint/><geom type="box" size="0.1 0.1 0.1" mass="2"/>
      <body><joint name="spin" axis="0 0 1"/><geom size="0.01" mass="0.001"/></body>
      </body></worldbody></mujoco>)");
  BridgeConfig config = PendulumConfig(testing::FreeDomain(), 0.5);
  config.mode = GetParam();
  config.motors = {"spin"};
  config.band.body = "box";
  config.band.release_button = "a";
  config.gamepad.events = dir.File("pad.txt");
  config.log = dir.File("log.csv");
  bridge::DdsDomain domain(config.domain);
  bridge::DdsWriter<Cmd> commands(domain, "rt/lowcmd", &unitree_go_msg_dds__LowCmd__desc);
  bridge::DdsReader<State> states(domain, "rt/lowstate", &unitree_go_msg_dds__LowState__desc);
  bridge::DdsReader<SportMessage> sport(domain, "rt/sportmodestate", bridge::SportType());
  StopSource stop;
  auto run =
      std::async(std::launch::async, [&] { return RunBridge(model, {}, config, stop.token()); });
  double z_held = NAN, z_end = NAN;
  State s;
  SportMessage m{};
  Serve(states, &s, run, [&] {
    TakeAll(sport, &m);
    if (SimMs(s) <= 300) z_held = m.position[2];
    z_end = m.position[2];
    Cmd c = Hold(0);
    c.crc = bridge::UnitreeCrc(c);
    commands.Write(c);
  });
  stop.RequestStop();
  BridgeStats stats = run.get();
  EXPECT_NEAR(stats.band_released, 0.3, 0.0021);
  EXPECT_NEAR(z_held, 1.0, 1e-3);  // held where it started
  EXPECT_LT(z_end, 0.85);          // 0.2 s of free fall: 0.2 m
  EXPECT_NE(testing::ReadFile(config.log).find("band: released at t = 0.3"), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(Modes, ModeTest,
                         ::testing::Values(BridgeMode::kLockstep, BridgeMode::kRealtime), ModeName);

// Faults on the state reach rt/sportmodestate: a dropped state's sport-mode state is dropped
// with it, and noise on position shows on the published position only.
TEST(BridgeTopicsTest, FaultsReachTheSportModeState) {
  Model model = Model::Load(testing::kPendulum);
  BridgeConfig config = PendulumConfig(testing::FreeDomain(), 1.0);
  config.sport_state.base = "link";
  FaultSpec drop;
  drop.kind = FaultSpec::Kind::kDrop;
  drop.state = true;
  drop.probability = 0.3;
  FaultSpec noise;
  noise.kind = FaultSpec::Kind::kNoise;
  noise.signal = "position";
  noise.motor = 2;  // z
  noise.sigma = 0.01;
  config.faults = {drop, noise};
  config.seed = 7;
  bridge::DdsDomain domain(config.domain);
  bridge::DdsWriter<Cmd> commands(domain, "rt/lowcmd", &unitree_go_msg_dds__LowCmd__desc);
  bridge::DdsReader<State> states(domain, "rt/lowstate", &unitree_go_msg_dds__LowState__desc);
  bridge::DdsReader<SportMessage> sport(domain, "rt/sportmodestate", bridge::SportType());
  StopSource stop;
  auto run =
      std::async(std::launch::async, [&] { return RunBridge(model, {}, config, stop.token()); });
  int received = 0, sport_received = 0;
  double sum = 0, sum2 = 0, x_max = 0;
  State s;
  SportMessage m;
  Serve(states, &s, run, [&] {
    ++received;
    while (sport.Take(&m)) {
      ++sport_received;
      double dz = m.position[2] - 1.5;
      sum += dz;
      sum2 += dz * dz;
      x_max = std::max(x_max, std::fabs(double(m.position[0])));
    }
    commands.Write([&] {
      Cmd c = Hold(0.3);
      c.crc = bridge::UnitreeCrc(c);
      return c;
    }());
  });
  stop.RequestStop();
  BridgeStats stats = run.get();
  EXPECT_GT(stats.dropped_states, 0.2 * stats.states);
  EXPECT_EQ(stats.sport_states, stats.states);
  // one fate: as many sport-mode states arrived as low states (the last may still be on its way)
  EXPECT_NEAR(sport_received, received, 2);
  EXPECT_LT(received, stats.states - stats.dropped_states + 2);
  double mean = sum / sport_received, sd = std::sqrt(sum2 / sport_received - mean * mean);
  EXPECT_NEAR(sd, 0.01, 0.002);
  EXPECT_NEAR(mean, 0, 0.002);
  EXPECT_EQ(x_max, 0);  // the noise is on z alone
}

}  // namespace
}  // namespace plumb
