// Unitree's message CRC (unitree_crc.h): the layout, field by field, and CRC-32/MPEG-2.

#include "bridge/unitree_crc.h"

#include <cstring>

namespace plumb::bridge {
namespace {

// Appends values at their natural alignment, little-endian, padding with zeros.
class Layout {
 public:
  template <typename T>
  void Put(T value) {
    Align(sizeof(T));
    std::uint8_t raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));  // x86-64 and AArch64 are little-endian
    bytes_.insert(bytes_.end(), raw, raw + sizeof(T));
  }
  template <typename T, std::size_t N>
  void Put(const T (&values)[N]) {
    for (const T& v : values) Put(v);
  }
  // A struct starts at the largest alignment of its members.
  void Align(std::size_t to) {
    while (bytes_.size() % to != 0) bytes_.push_back(0);
  }
  std::vector<std::uint8_t> Take(std::size_t struct_alignment) {
    Align(struct_alignment);
    return std::move(bytes_);
  }

 private:
  std::vector<std::uint8_t> bytes_;
};

// A MotorCmd_ of either family (their reserve differs: three words or one).
template <typename MotorCmd>
void PutMotor(Layout& l, const MotorCmd& c) {
  l.Align(4);
  l.Put(c.mode);
  for (float v : {c.q, c.dq, c.tau, c.kp, c.kd}) l.Put(v);
  l.Put(c.reserve);
}

// The header unitree_go's LowCmd_ and LowState_ share.
template <typename Message>
void PutGoHeader(Layout& l, const Message& m) {
  l.Put(m.head);
  l.Put(m.level_flag);
  l.Put(m.frame_reserve);
  l.Put(m.sn);
  l.Put(m.version);
  l.Put(m.bandwidth);
}

template <typename Imu>
void PutImu(Layout& l, const Imu& imu) {
  l.Align(4);
  l.Put(imu.quaternion);
  l.Put(imu.gyroscope);
  l.Put(imu.accelerometer);
  l.Put(imu.rpy);
  l.Put(imu.temperature);
  l.Align(4);
}

}  // namespace

std::uint32_t Crc32Mpeg2(const std::uint8_t* bytes, std::size_t count) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < count; ++i) {
    crc ^= std::uint32_t(bytes[i]) << 24;
    for (int bit = 0; bit < 8; ++bit) {
      crc = (crc & 0x80000000u) ? (crc << 1) ^ 0x04C11DB7u : crc << 1;
    }
  }
  return crc;
}

std::uint32_t Crc32Words(const std::uint32_t* words, std::size_t count) {
  std::vector<std::uint8_t> bytes;
  bytes.reserve(count * 4);
  for (std::size_t i = 0; i < count; ++i) {
    for (int shift = 24; shift >= 0; shift -= 8) bytes.push_back(std::uint8_t(words[i] >> shift));
  }
  return Crc32Mpeg2(bytes.data(), bytes.size());
}

std::vector<std::uint8_t> CrcLayout(const unitree_go_msg_dds__LowCmd_& m) {
  Layout l;
  PutGoHeader(l, m);
  for (const auto& c : m.motor_cmd) PutMotor(l, c);
  l.Put(m.bms_cmd.off);
  l.Put(m.bms_cmd.reserve);
  l.Put(m.wireless_remote);
  l.Put(m.led);
  l.Put(m.fan);
  l.Put(m.gpio);
  l.Put(m.reserve);
  l.Put(m.crc);
  return l.Take(4);
}

std::vector<std::uint8_t> CrcLayout(const unitree_go_msg_dds__LowState_& m) {
  Layout l;
  PutGoHeader(l, m);
  PutImu(l, m.imu_state);
  for (const auto& s : m.motor_state) {
    l.Align(4);
    l.Put(s.mode);
    for (float v : {s.q, s.dq, s.ddq, s.tau_est, s.q_raw, s.dq_raw, s.ddq_raw}) l.Put(v);
    l.Put(s.temperature);
    l.Put(s.lost);
    l.Put(s.reserve);
  }
  const auto& b = m.bms_state;
  l.Align(4);
  for (std::uint8_t v : {b.version_high, b.version_low, b.status, b.soc}) l.Put(v);
  l.Put(b.current);
  l.Put(b.cycle);
  l.Put(b.bq_ntc);
  l.Put(b.mcu_ntc);
  l.Put(b.cell_vol);
  l.Align(4);
  l.Put(m.foot_force);
  l.Put(m.foot_force_est);
  l.Put(m.tick);
  l.Put(m.wireless_remote);
  l.Put(m.bit_flag);
  l.Put(m.adc_reel);
  l.Put(m.temperature_ntc1);
  l.Put(m.temperature_ntc2);
  l.Put(m.power_v);
  l.Put(m.power_a);
  l.Put(m.fan_frequency);
  l.Put(m.reserve);
  l.Put(m.crc);
  return l.Take(4);
}

std::vector<std::uint8_t> CrcLayout(const unitree_hg_msg_dds__LowCmd_& m) {
  Layout l;
  l.Put(m.mode_pr);
  l.Put(m.mode_machine);
  for (const auto& c : m.motor_cmd) PutMotor(l, c);
  l.Put(m.reserve);
  l.Put(m.crc);
  return l.Take(4);
}

std::vector<std::uint8_t> CrcLayout(const unitree_hg_msg_dds__LowState_& m) {
  Layout l;
  l.Put(m.version);
  l.Put(m.mode_pr);
  l.Put(m.mode_machine);
  l.Put(m.tick);
  PutImu(l, m.imu_state);
  for (const auto& s : m.motor_state) {
    l.Align(4);
    l.Put(s.mode);
    for (float v : {s.q, s.dq, s.ddq, s.tau_est}) l.Put(v);
    l.Put(s.temperature);
    l.Put(s.vol);
    l.Put(s.sensor);
    l.Put(s.motorstate);
    l.Put(s.reserve);
  }
  l.Put(m.wireless_remote);
  l.Put(m.reserve);
  l.Put(m.crc);
  return l.Take(4);
}

}  // namespace plumb::bridge
