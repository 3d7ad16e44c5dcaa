// The rehearsal's own rows (rehearsal_rows.h).

#include "rehearse/rehearsal_rows.h"

#include <fmt/format.h>

#include <cmath>

namespace plumb::internal {
namespace {

// The rows' titles: what each tests, one line.
const char* Title(const std::string& id) {
  if (id == "client.process") return "the client runs to the end and stops when asked";
  if (id == "bridge.crc") return "commands carry Unitree's CRC";
  if (id == "bridge.values") return "commands are finite";
  if (id == "bridge.watchdog") return "the client never falls silent";
  if (id == "bridge.controllers") return "one controller on the domain";
  if (id == "bridge.pacing") return "the simulation keeps the wall clock's pace";
  return "the simulation stays sound";
}

CheckRow Row(const char* id, CheckStatus status, std::string measured, std::string explanation,
             std::string fix = "") {
  CheckRow row;
  row.section = id[0] == 'c' ? "client" : "bridge";
  row.id = id;
  row.title = Title(id);
  row.status = status;
  row.measured_text = std::move(measured);
  row.explanation = std::move(explanation);
  row.fix = std::move(fix);
  return row;
}

// "1 of 6250 commands" as a counted quantity.
CheckRow Counted(const char* id, CheckStatus status, long count, long of, std::string what,
                 std::string explanation, std::string fix) {
  CheckRow row = Row(id, status, fmt::format("{} of {} {}", count, of, what),
                     std::move(explanation), std::move(fix));
  row.measured = {static_cast<double>(count), ""};
  row.reference = {0, ""};
  row.threshold = true;
  row.reference_text = "0";
  return row;
}

}  // namespace

CheckRow ClientProcessRow(const ClientEnding& e, const BridgeConfig& config) {
  using Kind = ClientEnding::Kind;
  std::string when = std::isnan(e.time) ? "" : fmt::format(" at t = {:.3f} s", e.time);
  switch (e.kind) {
    case Kind::kNotStarted:
      return Row("client.process", CheckStatus::kFail, e.text,
                 "The client never ran: the bridge stopped before it was up.");
    case Kind::kKilled:
      return Row("client.process", CheckStatus::kFail, e.text + when,
                 "The client did not end on SIGINT within its grace period and was killed, as a "
                 "robot's operator would have to.",
                 "Let the deploy script end on Ctrl-C (SIGINT), or give it a longer grace.");
    case Kind::kStopped:
      return Row("client.process", CheckStatus::kPass, e.text + when,
                 fmt::format("The client ran to the rehearsal's end ({:g} s) and ended when "
                             "asked.",
                             config.until));
    case Kind::kExitedEarly:
      break;
  }
  if (e.exit_code == 0) {
    return Row("client.process", CheckStatus::kWarn, e.text + when,
               fmt::format("The client ended by itself before the rehearsal's end ({:g} s): "
                           "what the robot would do after that was not rehearsed.",
                           config.until),
               "Rehearse no longer than the client runs, or let it run until it is stopped.");
  }
  return Row("client.process", CheckStatus::kFail, e.text + when,
             "The client failed before the rehearsal's end; its last lines say why.",
             "Run the client's command by hand against plumb bridge to see it fail.");
}

std::vector<CheckRow> BridgeRows(const BridgeStats& s, const BridgeConfig& config) {
  std::vector<CheckRow> rows;
  long received = s.commands + s.bad_crc + s.non_finite;
  rows.push_back(Counted(
      "bridge.crc", s.bad_crc > 0 ? CheckStatus::kFail : CheckStatus::kPass, s.bad_crc, received,
      "commands with a wrong CRC",
      "The robot drops a command whose CRC is not Unitree's, as the bridge did.",
      s.bad_crc > 0 ? "Compute the CRC over the message as Unitree's SDK does (its crc module) "
                      "before each write."
                    : ""));
  rows.push_back(Counted(
      "bridge.values", s.non_finite > 0 ? CheckStatus::kFail : CheckStatus::kPass, s.non_finite,
      received, "commands with a NaN or infinite target or gain",
      "A command with a value that is not finite is dropped.",
      s.non_finite > 0 ? "Find where the policy's output or the script's arithmetic makes NaN "
                         "(an observation out of its range, a division by zero)."
                       : ""));
  CheckRow watchdog = Counted(
      "bridge.watchdog", s.watchdog_trips > 0 ? CheckStatus::kFail : CheckStatus::kPass,
      s.watchdog_trips, s.commands, "",
      fmt::format("The watchdog damps the motors when no command comes for {:g} ms{}.",
                  config.watchdog_timeout * 1000,
                  config.mode == BridgeMode::kLockstep ? " of simulated time" : ""),
      s.watchdog_trips > 0 ? "The client fell silent: see its command period (client.period) "
                             "and its last lines."
                           : "");
  watchdog.measured_text =
      fmt::format("tripped {} times over {} commands", s.watchdog_trips, s.commands);
  rows.push_back(watchdog);
  if (s.foreign_commands > 0) {
    rows.push_back(Counted("bridge.controllers", CheckStatus::kWarn, s.foreign_commands,
                           s.foreign_commands + s.commands, "commands from a second controller",
                           "Another DataWriter wrote rt/lowcmd while the client was in charge; "
                           "the bridge dropped its commands.",
                           "Run one controller per DDS domain."));
  }
  if (config.mode == BridgeMode::kRealtime) {
    CheckRow row = Counted(
        "bridge.pacing", s.late_periods > 0 ? CheckStatus::kWarn : CheckStatus::kPass,
        s.late_periods, s.steps, "periods started late",
        fmt::format("Realtime keeps the wall clock's pace (realtime factor {:.3f}); a late "
                    "period is time the simulation lost, which the robot does not.",
                    s.realtime_factor),
        s.late_periods > 0 ? "Rehearse on a quieter machine, or in lockstep." : "");
    rows.push_back(row);
  }
  if (s.diverged) {
    rows.push_back(Row("bridge.diverged", CheckStatus::kFail, s.problem,
                       "The simulation's state went bad: the rehearsal ended there.",
                       "Audit the model (plumb audit), and read the commands just before it "
                       "in the flight log."));
  }
  return rows;
}

}  // namespace plumb::internal
