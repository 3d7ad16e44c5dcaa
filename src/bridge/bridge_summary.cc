// The bridge's words that do not need DDS (plumb/bridge.h): its domain's configuration and
// the summary of a run, the same for the command line, Python and a rehearsal's report.

#include <fmt/format.h>

#include <cmath>

#include "plumb/bridge.h"

namespace plumb {
namespace {

// "realtime factor 0.983, 12 late periods (the worst 33.1 ms late)", and lockstep's waits
// for a late controller.
std::string Pacing(const BridgeStats& stats) {
  std::string text = std::isnan(stats.realtime_factor)
                         ? "no period ran"
                         : fmt::format("realtime factor {:.3f}", stats.realtime_factor);
  text += fmt::format(", {} late periods", stats.late_periods);
  if (stats.late_periods > 0) {
    text += fmt::format(" (the worst {:.1f} ms late)", stats.worst_lateness * 1000);
  }
  if (stats.late_commands > 0) {  // lockstep: simulated time waited for them
    text += fmt::format(", {} late commands waited for (the longest {:.2f} s)",
                        stats.late_commands, stats.longest_wait);
  }
  return text;
}

// ", 1500 sport-mode states, 300 gamepad messages, the band released at 2 s": what went out
// beside rt/lowstate.
std::string Extras(const BridgeStats& stats) {
  std::string text;
  if (stats.sport_states > 0) text += fmt::format(", {} sport-mode states", stats.sport_states);
  if (stats.secondary_imu_states > 0) {
    text += fmt::format(", {} secondary IMU states", stats.secondary_imu_states);
  }
  if (stats.gamepad_messages > 0) {
    text += fmt::format(", {} gamepad messages", stats.gamepad_messages);
  }
  if (!std::isnan(stats.band_released)) {
    text += fmt::format(", the band released at {:g} s", stats.band_released);
  }
  return text;
}

}  // namespace

std::string BridgeLoopbackConfig() {
  return "<CycloneDDS><Domain Id=\"any\"><General>"
         "<Interfaces><NetworkInterface name=\"lo\"/></Interfaces>"
         "<AllowMulticast>false</AllowMulticast></General>"
         "<Discovery><ParticipantIndex>auto</ParticipantIndex>"
         "<MaxAutoParticipantIndex>50</MaxAutoParticipantIndex>"
         "<Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery>"
         "</Domain></CycloneDDS>";
}

std::string BridgeSummary(const BridgeStats& stats, const BridgeConfig& config) {
  return fmt::format(
      "{:.6g} s simulated in {} steps; {} commands applied, {} dropped for a bad CRC, {} for NaN "
      "values, {} from a second controller, {} from a full lockstep queue; {} states "
      "published{}; watchdog tripped {} times; {}{}{}",
      stats.time, stats.steps, stats.commands, stats.bad_crc, stats.non_finite,
      stats.foreign_commands, stats.queue_drops, stats.states, Extras(stats),
      stats.watchdog_trips, Pacing(stats), config.log.empty() ? "" : "; log ", config.log);
}

}  // namespace plumb
