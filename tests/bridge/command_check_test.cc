// The bridge's check of an arriving command: CRC, finite targets and gains, both families.

#include "bridge/command_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

namespace plumb::bridge {
namespace {

template <typename Cmd>
Cmd Good() {
  Cmd cmd;
  std::memset(&cmd, 0, sizeof cmd);
  for (auto& m : cmd.motor_cmd) {
    m.mode = 1;
    m.q = 0.5f;
    m.kp = 20;
    m.kd = 2;
  }
  cmd.crc = UnitreeCrc(cmd);
  return cmd;
}

template <typename Cmd>
void CheckFamily(std::size_t slots) {
  std::vector<MotorCommand> out;
  Cmd cmd = Good<Cmd>();
  EXPECT_EQ(CheckCommand(cmd, true, 3, &out), CommandVerdict::kGood);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[2].kp, 20);
  EXPECT_FLOAT_EQ(out[2].q, 0.5f);
  // more motors than the message has: capped, never read past the array
  EXPECT_EQ(CheckCommand(cmd, true, 1000, &out), CommandVerdict::kGood);
  EXPECT_EQ(out.size(), slots);
  cmd.crc ^= 1;
  EXPECT_EQ(CheckCommand(cmd, true, 3, &out), CommandVerdict::kBadCrc);
  EXPECT_EQ(CheckCommand(cmd, false, 3, &out), CommandVerdict::kGood);  // check_crc = false
  for (float bad :
       {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    Cmd nan = Good<Cmd>();
    nan.motor_cmd[1].kd = bad;
    nan.crc = UnitreeCrc(nan);
    EXPECT_EQ(CheckCommand(nan, true, 3, &out), CommandVerdict::kNonFinite);
    // a bad value beyond the mapped motors is not read
    EXPECT_EQ(CheckCommand(nan, true, 1, &out), CommandVerdict::kGood);
  }
}

TEST(CommandCheckTest, GoFamily) { CheckFamily<unitree_go_msg_dds__LowCmd_>(20); }
TEST(CommandCheckTest, HgFamily) { CheckFamily<unitree_hg_msg_dds__LowCmd_>(35); }

}  // namespace
}  // namespace plumb::bridge
