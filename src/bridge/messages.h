// The Unitree message types the bridge speaks, per family, its DDS side (Link), and how it
// fills what it publishes beside rt/lowstate: rt/sportmodestate, rt/secondary_imu and the
// wireless controller.

#ifndef PLUMB_SRC_BRIDGE_MESSAGES_H_
#define PLUMB_SRC_BRIDGE_MESSAGES_H_

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "bridge/dds_link.h"
#include "bridge/gamepad_script.h"
#include "bridge/imu.h"
#include "bridge/sport_state.h"
#include "plumb/bridge.h"
#include "unitree_go.h"
#include "unitree_hg.h"

namespace plumb::bridge {

// The message types of a family.
template <BridgeFamily F>
struct Family;
template <>
struct Family<BridgeFamily::kGo> {
  using Cmd = unitree_go_msg_dds__LowCmd_;
  using State = unitree_go_msg_dds__LowState_;
  using ImuState = unitree_go_msg_dds__IMUState_;
  static constexpr int kMotors = 20;
  static const dds_topic_descriptor_t* CmdType() { return &unitree_go_msg_dds__LowCmd__desc; }
  static const dds_topic_descriptor_t* StateType() { return &unitree_go_msg_dds__LowState__desc; }
  static const dds_topic_descriptor_t* ImuType() { return &unitree_go_msg_dds__IMUState__desc; }
  // unitree_go's LowState_ has no robot type: `mode_machine` is for the hg family only
  static void Header(State* s, int /*mode_machine*/) {
    s->head[0] = 0xFE;
    s->head[1] = 0xEF;
    s->level_flag = 0xFF;
  }
};
template <>
struct Family<BridgeFamily::kHg> {
  using Cmd = unitree_hg_msg_dds__LowCmd_;
  using State = unitree_hg_msg_dds__LowState_;
  using ImuState = unitree_hg_msg_dds__IMUState_;
  static constexpr int kMotors = 35;
  static const dds_topic_descriptor_t* CmdType() { return &unitree_hg_msg_dds__LowCmd__desc; }
  static const dds_topic_descriptor_t* StateType() { return &unitree_hg_msg_dds__LowState__desc; }
  static const dds_topic_descriptor_t* ImuType() { return &unitree_hg_msg_dds__IMUState__desc; }
  static void Header(State* s, int mode_machine) {
    s->mode_machine = static_cast<std::uint8_t>(mode_machine);
  }
};

// Both families' messages share these; the G1 publishes unitree_go's too.
using SportMessage = unitree_go_msg_dds__SportModeState_;
using PadMessage = unitree_go_msg_dds__WirelessController_;
inline const dds_topic_descriptor_t* SportType() {
  return &unitree_go_msg_dds__SportModeState__desc;
}
inline const dds_topic_descriptor_t* PadType() {
  return &unitree_go_msg_dds__WirelessController__desc;
}

// What goes out at a state's tick: rt/lowstate and, where the bridge publishes them,
// rt/sportmodestate and rt/secondary_imu (one fate for the three under faults).
template <BridgeFamily F>
struct Outgoing {
  typename Family<F>::State low;
  SportMessage sport;
  typename Family<F>::ImuState imu;
};

// The bridge's side of DDS: commands in; states, the sport-mode state, the second IMU (when
// `sport`, `secondary`) and the gamepad (when configured) out.
template <BridgeFamily F>
struct Link {
  Link(const BridgeConfig& c, bool sport, bool secondary)
      : domain(c.domain),
        commands(domain, "rt/lowcmd", Family<F>::CmdType()),
        states(domain, "rt/lowstate", Family<F>::StateType()) {
    if (sport) this->sport.emplace(domain, "rt/sportmodestate", SportType());
    if (secondary) imu.emplace(domain, "rt/secondary_imu", Family<F>::ImuType());
    if (c.gamepad.events.empty()) return;
    for (const std::string& topic : c.gamepad.topics) pads.emplace_back(domain, topic, PadType());
  }
  void Write(const Outgoing<F>& out) {
    states.Write(out.low);
    if (sport) sport->Write(out.sport);
    if (imu) imu->Write(out.imu);
  }
  DdsDomain domain;
  DdsReader<typename Family<F>::Cmd> commands;
  DdsWriter<typename Family<F>::State> states;
  std::optional<DdsWriter<SportMessage>> sport;
  std::optional<DdsWriter<typename Family<F>::ImuState>> imu;
  std::vector<DdsWriter<PadMessage>> pads;
};

// An IMU reading into either family's IMUState_ (single precision, as on the wire).
template <typename ImuState>
void FillImu(const ImuReading& r, ImuState* out) {
  for (int k = 0; k < 4; ++k) out->quaternion[k] = static_cast<float>(r.quaternion[k]);
  for (int k = 0; k < 3; ++k) {
    out->gyroscope[k] = static_cast<float>(r.gyroscope[k]);
    out->accelerometer[k] = static_cast<float>(r.accelerometer[k]);
    out->rpy[k] = static_cast<float>(r.rpy[k]);
  }
}

// rt/sportmodestate at simulated time t (s): the reading of `feet` feet, and the IMU as
// rt/lowstate publishes it. A foot force beyond the wire's 16 bits is clipped to them.
inline SportMessage MakeSportMessage(double t, const SportReading& r, const ImuReading& imu,
                                     std::size_t feet) {
  SportMessage s;
  std::memset(&s, 0, sizeof s);
  double whole = std::floor(t);
  s.stamp.sec = static_cast<std::int32_t>(whole);
  s.stamp.nanosec = static_cast<std::uint32_t>(std::llround((t - whole) * 1e9) % 1000000000);
  FillImu(imu, &s.imu_state);
  for (int k = 0; k < 3; ++k) {
    s.position[k] = static_cast<float>(r.position[k]);
    s.velocity[k] = static_cast<float>(r.velocity[k]);
  }
  s.body_height = static_cast<float>(r.body_height);
  s.yaw_speed = static_cast<float>(r.yaw_speed);
  for (std::size_t i = 0; i < feet; ++i) {
    s.foot_force[i] =
        static_cast<std::int16_t>(std::lround(std::clamp(r.foot_force[i], -32768.0, 32767.0)));
    for (int k = 0; k < 3; ++k) {
      s.foot_position_body[3 * i + k] = static_cast<float>(r.foot_position[i][k]);
      s.foot_speed_body[3 * i + k] = static_cast<float>(r.foot_speed[i][k]);
    }
  }
  return s;
}

inline PadMessage MakePadMessage(const GamepadState& pad) {
  PadMessage m;
  std::memset(&m, 0, sizeof m);
  m.lx = static_cast<float>(pad.lx);
  m.ly = static_cast<float>(pad.ly);
  m.rx = static_cast<float>(pad.rx);
  m.ry = static_cast<float>(pad.ry);
  m.keys = pad.keys;
  return m;
}

// A gamepad message as the flight log records it: "lx 0.5 ly 0 rx 0 ry 0 keys 0x0004 (start)".
inline std::string PadText(const GamepadState& pad) {
  std::string held;
  for (int b = 0; b < 16; ++b) {
    if (pad.keys >> b & 1u) held += (held.empty() ? "" : " ") + std::string(kButtonNames[b]);
  }
  return fmt::format("lx {:g} ly {:g} rx {:g} ry {:g} keys {:#06x}{}", pad.lx, pad.ly, pad.rx,
                     pad.ry, pad.keys, held.empty() ? "" : " (" + held + ")");
}

}  // namespace plumb::bridge

#endif  // PLUMB_SRC_BRIDGE_MESSAGES_H_
