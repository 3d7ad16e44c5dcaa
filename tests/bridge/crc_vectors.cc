// Prints, for each of Unitree's four CRC-carrying messages filled with a fixed pattern, its
// layout (hex) and plumb's CRC, one JSON line each, for crc_crosscheck.py to check against
// Unitree's published packing and an independent CRC-32/MPEG-2 (fastcrc).

#include <cstdio>
#include <cstring>

#include "bridge/unitree_crc.h"

namespace {

template <typename Message>
void Print(const char* name, Message& m) {
  // every byte of every field from a pattern: the fields' values are whatever the bytes say
  auto* raw = reinterpret_cast<unsigned char*>(&m);
  for (std::size_t i = 0; i < sizeof m; ++i) raw[i] = static_cast<unsigned char>(i * 37 + 11);
  // floats with those bytes may be NaN; the CRC does not care, the packing round trip does
  std::vector<std::uint8_t> layout = plumb::bridge::CrcLayout(m);
  std::printf("{\"type\": \"%s\", \"crc\": %u, \"hex\": \"", name, plumb::bridge::UnitreeCrc(m));
  for (std::uint8_t b : layout) std::printf("%02x", b);
  std::printf("\"}\n");
}

}  // namespace

int main() {
  unitree_go_msg_dds__LowCmd_ go_cmd;
  unitree_go_msg_dds__LowState_ go_state;
  unitree_hg_msg_dds__LowCmd_ hg_cmd;
  unitree_hg_msg_dds__LowState_ hg_state;
  Print("unitree_go::msg::dds_::LowCmd_", go_cmd);
  Print("unitree_go::msg::dds_::LowState_", go_state);
  Print("unitree_hg::msg::dds_::LowCmd_", hg_cmd);
  Print("unitree_hg::msg::dds_::LowState_", hg_state);
  return 0;
}
