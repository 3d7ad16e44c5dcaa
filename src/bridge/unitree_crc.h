// The CRC that Unitree's SDK2 puts in the last field of LowCmd_ and LowState_, and that the
// robot checks before it obeys a command.
//
// It runs over the message laid out as a C struct with natural alignment, little-endian and
// with zero padding (LowCmd_ 812 bytes for unitree_go, 1004 for unitree_hg; LowState_ 1180
// and 2092), taken as 32-bit words, every word but the last (the crc field itself): each
// word's value, most significant byte first, through CRC-32/MPEG-2 (polynomial 0x04C11DB7,
// initial value 0xFFFFFFFF, no reflection, no final XOR). The layout is built field by field
// here, so padding is always zero whatever the bytes in a received struct's padding hold.

#ifndef PLUMB_SRC_BRIDGE_UNITREE_CRC_H_
#define PLUMB_SRC_BRIDGE_UNITREE_CRC_H_

#include <cstddef>
#include <cstdint>
#include <vector>

#include "unitree_go.h"
#include "unitree_hg.h"

namespace plumb::bridge {

// CRC-32/MPEG-2 of `count` 32-bit words, each fed most significant byte first.
std::uint32_t Crc32Words(const std::uint32_t* words, std::size_t count);

// CRC-32/MPEG-2 of bytes (its check value: "123456789" gives 0x0376E6E7).
std::uint32_t Crc32Mpeg2(const std::uint8_t* bytes, std::size_t count);

// The message as the CRC sees it: the naturally aligned little-endian layout, zero padding.
std::vector<std::uint8_t> CrcLayout(const unitree_go_msg_dds__LowCmd_& m);
std::vector<std::uint8_t> CrcLayout(const unitree_go_msg_dds__LowState_& m);
std::vector<std::uint8_t> CrcLayout(const unitree_hg_msg_dds__LowCmd_& m);
std::vector<std::uint8_t> CrcLayout(const unitree_hg_msg_dds__LowState_& m);

// The crc field's value for a message (whatever its crc field holds now).
template <typename Message>
std::uint32_t UnitreeCrc(const Message& m) {
  std::vector<std::uint8_t> bytes = CrcLayout(m);
  std::vector<std::uint32_t> words(bytes.size() / 4);
  for (std::size_t i = 0; i < words.size(); ++i) {
    words[i] = std::uint32_t(bytes[4 * i]) | std::uint32_t(bytes[4 * i + 1]) << 8 |
               std::uint32_t(bytes[4 * i + 2]) << 16 | std::uint32_t(bytes[4 * i + 3]) << 24;
  }
  return Crc32Words(words.data(), words.size() - 1);
}

}  // namespace plumb::bridge

#endif  // PLUMB_SRC_BRIDGE_UNITREE_CRC_H_
