// The rehearsal's own rows: how the client ended (client.process) and what the bridge saw of
// the link (bridge.*), beside the assertions' rows (rehearsal_tally.h) and what plumb saw of
// the client's commands (client_watch.h).

#ifndef PLUMB_SRC_REHEARSE_REHEARSAL_ROWS_H_
#define PLUMB_SRC_REHEARSE_REHEARSAL_ROWS_H_

#include <vector>

#include "plumb/bridge.h"
#include "plumb/check.h"
#include "plumb/rehearse.h"

namespace plumb::internal {

// client.process: PASS when the client ran to the end and ended on plumb's signal (or exited
// 0 on it); FAIL when it could not start, exited early with a non-zero status or a signal, or
// had to be killed; WARN when it exited 0 by itself before the end (what followed was not
// rehearsed).
CheckRow ClientProcessRow(const ClientEnding& ending, const BridgeConfig& config);

// bridge.crc (FAIL: the robot drops commands whose CRC is wrong), bridge.values (FAIL: NaN
// targets or gains), bridge.watchdog (FAIL: the controller fell silent for the watchdog's
// timeout and the robot damped), bridge.controllers (WARN: a second controller wrote
// rt/lowcmd), bridge.pacing (realtime: WARN when periods started late: this machine fell
// behind, the rehearsal is less faithful than the robot), bridge.diverged (FAIL).
std::vector<CheckRow> BridgeRows(const BridgeStats& stats, const BridgeConfig& config);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_REHEARSE_REHEARSAL_ROWS_H_
