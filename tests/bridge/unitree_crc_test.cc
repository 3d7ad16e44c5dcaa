// Unitree's message CRC: the algorithm's check value, the layouts' sizes against the C
// structs idlc generates from idl/, and padding that cannot change the result.

#include "bridge/unitree_crc.h"

#include <gtest/gtest.h>

#include <cstring>

namespace plumb::bridge {
namespace {

TEST(UnitreeCrcTest, Crc32Mpeg2CheckValue) {
  const char* check = "123456789";
  EXPECT_EQ(Crc32Mpeg2(reinterpret_cast<const std::uint8_t*>(check), 9), 0x0376E6E7u);
  std::uint32_t word = 0x31323334;  // "1234" as one word, most significant byte first
  EXPECT_EQ(Crc32Words(&word, 1), Crc32Mpeg2(reinterpret_cast<const std::uint8_t*>("1234"), 4));
}

// A message filled with a byte pattern through its fields, over zeroed memory: the bytes of
// the C struct then equal the layout the CRC runs over, padding included.
template <typename Message>
void ExpectLayoutIsTheCStruct(std::size_t size, void (*fill)(Message*)) {
  Message m;
  std::memset(&m, 0, sizeof m);
  fill(&m);
  std::vector<std::uint8_t> layout = CrcLayout(m);
  ASSERT_EQ(sizeof(Message), size);
  ASSERT_EQ(layout.size(), size);
  EXPECT_EQ(std::memcmp(layout.data(), &m, size), 0);
  // garbage in the padding of a received struct does not reach the CRC: the bytes whose
  // change leaves the layout alone are padding; fill them with garbage
  Message dirty = m;
  auto* raw = reinterpret_cast<std::uint8_t*>(&dirty);
  int padding = 0;
  for (std::size_t i = 0; i < size; ++i) {
    std::uint8_t kept = raw[i];
    raw[i] = std::uint8_t(kept ^ 0xFF);
    bool is_padding = CrcLayout(dirty) == layout;
    raw[i] = is_padding ? 0xA5 : kept;
    padding += is_padding;
  }
  EXPECT_GT(padding, 0);
  EXPECT_EQ(CrcLayout(dirty), layout);
  EXPECT_EQ(UnitreeCrc(dirty), UnitreeCrc(m));
  // the crc field itself is not covered; every other word is
  std::uint32_t before = UnitreeCrc(m);
  m.crc = 0xDEADBEEF;
  EXPECT_EQ(UnitreeCrc(m), before);
}

void FillGoCmd(unitree_go_msg_dds__LowCmd_* m) {
  m->head[0] = 0xFE;
  m->head[1] = 0xEF;
  m->level_flag = 0xFF;
  m->bandwidth = 0x1234;
  for (int i = 0; i < 20; ++i) {
    m->motor_cmd[i].mode = 1;
    m->motor_cmd[i].q = 0.1f * i;
    m->motor_cmd[i].kp = 50;
    m->motor_cmd[i].kd = 3.5f;
    m->motor_cmd[i].reserve[2] = i;
  }
  m->bms_cmd.off = 7;
  m->led[11] = 9;
  m->gpio = 3;
  m->reserve = 0xCAFE;
}

void FillGoState(unitree_go_msg_dds__LowState_* m) {
  m->level_flag = 1;
  m->imu_state.quaternion[0] = 1;
  m->imu_state.temperature = 40;
  for (int i = 0; i < 20; ++i) {
    m->motor_state[i].mode = 1;
    m->motor_state[i].q = -0.2f * i;
    m->motor_state[i].temperature = 30;
    m->motor_state[i].lost = i;
  }
  m->bms_state.soc = 90;
  m->bms_state.current = -1234;
  m->bms_state.cell_vol[14] = 3700;
  m->foot_force[3] = -5;
  m->tick = 123456;
  m->bit_flag = 2;
  m->adc_reel = 1.5f;
  m->temperature_ntc2 = 33;
  m->power_a = 2.5f;
  m->fan_frequency[3] = 1000;
}

void FillHgCmd(unitree_hg_msg_dds__LowCmd_* m) {
  m->mode_pr = 0;
  m->mode_machine = 5;
  for (int i = 0; i < 35; ++i) {
    m->motor_cmd[i].mode = 1;
    m->motor_cmd[i].q = 0.01f * i;
    m->motor_cmd[i].kp = 60;
    m->motor_cmd[i].reserve = i;
  }
  m->reserve[3] = 77;
}

void FillHgState(unitree_hg_msg_dds__LowState_* m) {
  m->version[1] = 3;
  m->mode_machine = 5;
  m->tick = 99;
  m->imu_state.rpy[2] = 0.5f;
  m->imu_state.temperature = -3;
  for (int i = 0; i < 35; ++i) {
    m->motor_state[i].mode = 1;
    m->motor_state[i].tau_est = 0.5f * i;
    m->motor_state[i].temperature[1] = 41;
    m->motor_state[i].vol = 24;
    m->motor_state[i].motorstate = i;
  }
  m->wireless_remote[39] = 1;
  m->reserve[0] = 5;
}

TEST(UnitreeCrcTest, GoLowCmdIs812Bytes) {
  ExpectLayoutIsTheCStruct<unitree_go_msg_dds__LowCmd_>(812, FillGoCmd);
}
TEST(UnitreeCrcTest, GoLowStateIs1180Bytes) {
  ExpectLayoutIsTheCStruct<unitree_go_msg_dds__LowState_>(1180, FillGoState);
}
TEST(UnitreeCrcTest, HgLowCmdIs1004Bytes) {
  ExpectLayoutIsTheCStruct<unitree_hg_msg_dds__LowCmd_>(1004, FillHgCmd);
}
TEST(UnitreeCrcTest, HgLowStateIs2092Bytes) {
  ExpectLayoutIsTheCStruct<unitree_hg_msg_dds__LowState_>(2092, FillHgState);
}

TEST(UnitreeCrcTest, OneChangedGainChangesTheCrc) {
  unitree_go_msg_dds__LowCmd_ m;
  std::memset(&m, 0, sizeof m);
  FillGoCmd(&m);
  std::uint32_t crc = UnitreeCrc(m);
  m.motor_cmd[19].kd = 3.6f;
  EXPECT_NE(UnitreeCrc(m), crc);
}

}  // namespace
}  // namespace plumb::bridge
