// pd_client: a low-level controller speaking Unitree's rt/lowcmd / rt/lowstate (unitree_go
// messages, CRC included) over DDS on loopback. Two jobs:
//   pd_client pendulum --domain D [--target 0.5] [--seconds 3]
//       motor 0 held at the target: gravity feed-forward m g d sin(q), kp 20, kd 2
//   pd_client go2 --domain D [--seconds 3]
//       from lying down to standing, as Unitree's stand example does: joint targets
//       interpolated from where the legs are to the standing pose over 1 s, kp 50, kd 3.5,
//       then held
//   pd_client torque --domain D [--seconds 3]
//       motor 0 driven by torque alone (kp = kd = 0): a chirp of 2 N m from 0.2 to 3 Hz over
//       --seconds, computed at each state's time; for identification from the flight log
// It answers every state with one command (so a lockstep simulator advances in step) and
// stops after --seconds of the robot's time (its tick less the first state's). Exit 0, or 1 when no
// state came within 5 s.

#include <dds/dds.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "unitree_go.h"

namespace {

using Cmd = unitree_go_msg_dds__LowCmd_;
using State = unitree_go_msg_dds__LowState_;

// Unitree's CRC: CRC-32/MPEG-2 over the message's 32-bit words but the last, each word most
// significant byte first. The struct is zeroed before it is filled, so its padding is zero
// and its memory is the layout the robot checks.
std::uint32_t Crc(const Cmd& cmd) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(&cmd);
  std::size_t words = sizeof(Cmd) / 4 - 1;
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::size_t w = 0; w < words; ++w) {
    std::uint32_t word;
    std::memcpy(&word, bytes + 4 * w, 4);
    for (int shift = 24; shift >= 0; shift -= 8) {
      crc ^= ((word >> shift) & 0xFFu) << 24;
      for (int bit = 0; bit < 8; ++bit)
        crc = (crc & 0x80000000u) ? (crc << 1) ^ 0x04C11DB7u : crc << 1;
    }
  }
  return crc;
}

std::string LoopbackConfig() {
  return "<CycloneDDS><Domain Id=\"any\"><General><Interfaces><NetworkInterface name=\"lo\"/>"
         "</Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery>"
         "<ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>50"
         "</MaxAutoParticipantIndex><Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery>"
         "</Domain></CycloneDDS>";
}

const char* Option(int argc, char** argv, const char* name, const char* fallback) {
  for (int i = 2; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], name) == 0) return argv[i + 1];
  }
  return fallback;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || (std::strcmp(argv[1], "pendulum") != 0 && std::strcmp(argv[1], "go2") != 0 &&
                   std::strcmp(argv[1], "torque") != 0)) {
    std::fprintf(stderr,
                 "usage: pd_client pendulum|go2|torque --domain D [--target Q] [--seconds S]\n");
    return 2;
  }
  bool go2 = std::strcmp(argv[1], "go2") == 0;
  bool torque = std::strcmp(argv[1], "torque") == 0;
  auto domain = static_cast<dds_domainid_t>(std::atoi(Option(argc, argv, "--domain", "1")));
  double target = std::atof(Option(argc, argv, "--target", "0.5"));
  double seconds = std::atof(Option(argc, argv, "--seconds", "3"));

  dds_entity_t d = dds_create_domain(domain, LoopbackConfig().c_str());
  dds_entity_t participant = dds_create_participant(domain, nullptr, nullptr);
  if (d < 0 || participant < 0) {
    std::fprintf(stderr, "pd_client: DDS domain %u: %s\n", domain,
                 dds_strretcode(participant < 0 ? participant : d));
    return 1;
  }
  dds_entity_t cmd_topic = dds_create_topic(participant, &unitree_go_msg_dds__LowCmd__desc,
                                            "rt/lowcmd", nullptr, nullptr);
  dds_entity_t state_topic = dds_create_topic(participant, &unitree_go_msg_dds__LowState__desc,
                                              "rt/lowstate", nullptr, nullptr);
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 1);
  dds_entity_t writer = dds_create_writer(participant, cmd_topic, qos, nullptr);
  dds_qset_reliability(qos, DDS_RELIABILITY_BEST_EFFORT, 0);
  dds_qset_history(qos, DDS_HISTORY_KEEP_ALL, 0);
  dds_entity_t reader = dds_create_reader(participant, state_topic, qos, nullptr);
  dds_delete_qos(qos);
  dds_entity_t waitset = dds_create_waitset(participant);
  dds_entity_t readable = dds_create_readcondition(reader, DDS_ANY_STATE);
  dds_waitset_attach(waitset, readable, 0);

  // the standing pose of a Go2 (hip, thigh, calf of each leg)
  const float stand[3] = {0.0f, 0.9f, -1.8f};
  float start[12] = {0};
  bool have_start = false;
  long answered = 0;
  std::uint32_t first_tick = 0;  // the first state's tick: a robot's counts from its boot
  for (;;) {
    if (dds_waitset_wait(waitset, nullptr, 0, DDS_SECS(5)) <= 0) {
      std::fprintf(stderr, "pd_client: no state for 5 s (after %ld)\n", answered);
      return answered > 0 ? 0 : 1;
    }
    State state;
    void* samples[1] = {&state};
    dds_sample_info_t info;
    bool got = false;
    while (dds_take(reader, samples, &info, 1, 1) > 0) got = got || info.valid_data;
    if (!got) continue;
    // a robot's tick counts from its boot (ms): the time is the tick less the first one's
    if (first_tick == 0) first_tick = state.tick;
    double t = (state.tick - first_tick) / 1000.0;
    if (t >= seconds) break;
    Cmd cmd;
    std::memset(&cmd, 0, sizeof cmd);
    cmd.head[0] = 0xFE;
    cmd.head[1] = 0xEF;
    cmd.level_flag = 0xFF;
    if (go2) {
      if (!have_start) {
        for (int i = 0; i < 12; ++i) start[i] = state.motor_state[i].q;
        have_start = true;
      }
      float share = static_cast<float>(std::min(1.0, t / 1.0));
      for (int i = 0; i < 12; ++i) {
        auto& m = cmd.motor_cmd[i];
        m.mode = 1;
        m.q = (1 - share) * start[i] + share * stand[i % 3];
        m.kp = 50;
        m.kd = 3.5f;
      }
    } else if (torque) {
      const double kPi = 3.14159265358979323846;
      auto& m = cmd.motor_cmd[0];
      m.mode = 1;
      m.tau = static_cast<float>(
          2.0 * std::sin(2 * kPi * (0.2 * t + (3.0 - 0.2) * t * t / (2 * seconds))));
    } else {
      auto& m = cmd.motor_cmd[0];
      m.mode = 1;
      m.q = static_cast<float>(target);
      m.kp = 20;
      m.kd = 2;
      m.tau = static_cast<float>(1.0 * 9.81 * 0.5 * std::sin(target));
    }
    cmd.crc = Crc(cmd);
    dds_write(writer, &cmd);
    ++answered;
  }
  std::printf("pd_client: answered %ld states\n", answered);
  dds_delete(participant);
  dds_delete(d);
  return 0;
}
