// DDS message handling: bytes are read as a serialised unitree_go and unitree_hg LowCmd_ by
// CycloneDDS's own deserialiser (normalised first, as CycloneDDS does on receipt), and what
// it gives goes through the bridge's command check (CRC, finite targets and gains).

#include <dds/dds.h>
#include <dds/ddsi/ddsi_cdrstream.h>

#include <cstring>
#include <vector>

#include "bridge/command_check.h"
#include "fuzz_common.h"
#include "unitree_go.h"
#include "unitree_hg.h"

namespace {

template <typename Cmd>
void Feed(const std::uint8_t* data, std::size_t size, const dds_topic_descriptor_t* desc) {
  if (size == 0) return;  // CycloneDDS hands the deserialiser no empty payload
  std::vector<unsigned char> buffer(data, data + size);  // normalised in place
  std::uint32_t offset = 0;
  if (dds_stream_normalize_data(reinterpret_cast<char*>(buffer.data()), &offset,
                                static_cast<std::uint32_t>(buffer.size()), false, CDR_ENC_VERSION_1,
                                desc->m_ops) == nullptr) {
    return;  // refused, as CycloneDDS refuses it on receipt
  }
  Cmd cmd;
  std::memset(&cmd, 0, sizeof cmd);
  dds_istream_t is = {buffer.data(), static_cast<std::uint32_t>(buffer.size()), 0,
                      CDR_ENC_VERSION_1};
  dds_stream_read(&is, reinterpret_cast<char*>(&cmd), desc->m_ops);
  std::vector<plumb::bridge::MotorCommand> out;
  for (bool crc : {true, false}) plumb::bridge::CheckCommand(cmd, crc, 64, &out);
  // with the raw bytes as the struct itself, too (a peer that sends a message of the right size)
  if (size >= sizeof(Cmd)) {
    std::memcpy(&cmd, data, sizeof(Cmd));
    plumb::bridge::CheckCommand(cmd, true, 64, &out);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Feed<unitree_go_msg_dds__LowCmd_>(data, size, &unitree_go_msg_dds__LowCmd__desc);
  Feed<unitree_hg_msg_dds__LowCmd_>(data, size, &unitree_hg_msg_dds__LowCmd__desc);
  return 0;
}
