// What the bridge does with a command that arrives, before it is applied: the CRC is checked
// (as the robot does) and every target and gain must be finite. One rule for both message
// families, and the entry point the fuzzer feeds raw messages to.

#ifndef PLUMB_SRC_BRIDGE_COMMAND_CHECK_H_
#define PLUMB_SRC_BRIDGE_COMMAND_CHECK_H_

#include <cstddef>
#include <vector>

#include "bridge/pd_law.h"
#include "bridge/unitree_crc.h"
#include "plumb/bridge.h"

namespace plumb::bridge {

enum class CommandVerdict { kGood, kBadCrc, kNonFinite };

// Checks `cmd` and, when it is good, writes the first `motors` motor commands to `out`
// (`motors` is at most the family's motor count: the motor map checks that). A slot that
// `empty` marks (MotorMap::EmptySlots) drives nothing: it is left mode 0 and not checked, as
// slots beyond `motors` are not.
template <typename Cmd>
CommandVerdict CheckCommand(const Cmd& cmd, bool check_crc, std::size_t motors,
                            std::vector<MotorCommand>* out, const std::vector<bool>& empty = {}) {
  if (check_crc && UnitreeCrc(cmd) != cmd.crc) return CommandVerdict::kBadCrc;
  constexpr std::size_t kSlots = sizeof(cmd.motor_cmd) / sizeof(cmd.motor_cmd[0]);
  if (motors > kSlots) motors = kSlots;
  out->assign(motors, {});
  for (std::size_t i = 0; i < motors; ++i) {
    if (i < empty.size() && empty[i]) continue;
    const auto& m = cmd.motor_cmd[i];
    (*out)[i] = {m.mode, m.q, m.dq, m.tau, m.kp, m.kd};
    if (!(*out)[i].finite()) return CommandVerdict::kNonFinite;
  }
  return CommandVerdict::kGood;
}

// Every motor slot of `cmd` as sent, for a BridgeObserver.
template <typename Cmd>
std::vector<BridgeCommandSlot> CommandSlots(const Cmd& cmd) {
  constexpr std::size_t kSlots = sizeof(cmd.motor_cmd) / sizeof(cmd.motor_cmd[0]);
  std::vector<BridgeCommandSlot> slots(kSlots);
  for (std::size_t i = 0; i < kSlots; ++i) {
    const auto& m = cmd.motor_cmd[i];
    slots[i] = {m.mode, m.q, m.dq, m.tau, m.kp, m.kd};
  }
  return slots;
}

}  // namespace plumb::bridge

#endif  // PLUMB_SRC_BRIDGE_COMMAND_CHECK_H_
