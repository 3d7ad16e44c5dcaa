// The tables a person reads of inspect, converge, diff, replay and identify: what the CLI prints
// without --format json (verify's and audit's are in check_table.h).
//
// Example:
//   std::string text = plumb::ConvergeTable(plumb::Converge(model, {}, metric, dt, 4, 1e-3, 2));
//
// Thread-safety: pure functions of their arguments; they throw nothing of plumb's own.

#ifndef PLUMB_INCLUDE_PLUMB_RESULT_TABLE_H_
#define PLUMB_INCLUDE_PLUMB_RESULT_TABLE_H_

#include <string>
#include <vector>

#include "plumb/converge.h"
#include "plumb/describe.h"
#include "plumb/identify.h"
#include "plumb/regression.h"
#include "plumb/replay.h"
#include "plumb/report.h"
#include "plumb/robot_log.h"

namespace plumb {

// plumb inspect's table: the model (`mujoco` is the MuJoCo version to name), its sizes and
// options, bodies, joints, actuators, sensors, delays, what is what, with units.
std::string DescriptionTable(const ModelDescription& description, const std::string& mujoco);

// The levels (dt, value, difference, order, estimated error), then the verdict: the observed
// order, the value, the recommended timestep and the contact caveat.
std::string ConvergeTable(const ConvergenceResult& result);

// The assignments the model ran with and the notes, the compiler's changes (three of them),
// every change, the count, and under another MuJoCo than the snapshot's a line answering the
// upgrade's question. `snapshot` is the snapshot's path as given; `set_prefix` comes before
// each quoted assignment (the command-line tool's "--set ").
std::string DiffTable(const SnapshotDiff& diff, const std::string& snapshot,
                      const std::string& set_prefix = "");

// Per signal: samples, rms and max error, when the worst was, the fit in percent.
std::string FitTable(const std::vector<SignalFit>& fits);

// What was replayed (span, inputs, windows, delays), the fit table, the overall fit, notes.
std::string ReplayTable(const std::string& model, const RobotLog& log, const ReplayOptions& options,
                        const ReplayResult& result);

// The estimates with standard errors and 95 % intervals (and the delay), the correlations,
// the solver, noise per signal, fit per log before and after, the held-out log's fit
// (`validation`, nullptr: none), what changed, and the identifiability warnings.
std::string IdentifyTable(const std::string& model, const IdentifyResult& result,
                          const std::vector<RobotLog>& logs, DelayKind delay,
                          const HeldOutLog* validation);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_RESULT_TABLE_H_
