// The JSON documents of plumb's results: what `--format json` prints, for a library user too.
//
// Each is pretty-printed (2-space indent) and ends in a newline. A number that is not finite
// (a NaN where nothing could be measured) is null. Check rows have one shape everywhere:
//   {"id", "section", "title", "status", "element", "element_type", "element_name",
//    "element_id", "measured", "measured_unit", "measured_text", "reference",
//    "reference_unit", "reference_text", "threshold", "rel_error", "explanation", "fix",
//    "accepted"}
// where "element" is the element's label or the row's subject ("" for the whole model),
// "measured" and "reference" are the numbers, or the texts when the row has no number, and
// "accepted" is the reason an accept list gives for the row (plumb/accept.h), else null. A
// summary counts the rows by status, the accepted ones apart: {"pass", "warn", "fail", "skip",
// "accepted"}.
//
// Example:
//   std::string json = plumb::VerifyToJson(plumb::Verify(model, options));
//
// Thread-safety: pure functions of their arguments. Text that is not valid UTF-8 (a name in
// the model) makes nlohmann::json throw its type_error; nothing else is thrown.

#ifndef PLUMB_INCLUDE_PLUMB_RESULT_JSON_H_
#define PLUMB_INCLUDE_PLUMB_RESULT_JSON_H_

#include <string>
#include <vector>

#include "plumb/audit.h"
#include "plumb/converge.h"
#include "plumb/crosscheck.h"
#include "plumb/identify.h"
#include "plumb/regression.h"
#include "plumb/rehearse.h"
#include "plumb/replay.h"
#include "plumb/report.h"
#include "plumb/robot_log.h"
#include "plumb/verify.h"

namespace plumb {

// {"model", "mujoco_version", "tol", "checks": [row...], "summary": {pass, warn, fail, skip,
//  accepted}}
std::string VerifyToJson(const VerifyReport& report);

// {"model", "mujoco_version", "layers": {layer: [row...]}, "repro_folders", "summary"}
std::string AuditToJson(const AuditReport& report);

// {"model", "mujoco_version", "engine": {engine, engine_version, backend, mujoco_version,
//  mujoco_library, device, precision}, "model_transfer", "checks": [row...], "divergence":
//  [{signal, element, threshold, engine: [s...], chaos: [s...]}], "throughput": {worlds, steps,
//  engine_steps_per_second, engine_compile_seconds, cpu_steps_per_second, cpu_threads},
//  "summary"}
std::string CrosscheckToJson(const CrosscheckReport& report);

// {"metric", "model", "integrator_expected_order", "levels": [{dt, value, diff, order, error,
//  error_is_richardson, roundoff}], "observed_order", "order_resolved", "extrapolated", "scale",
//  "tol", "recommended_dt", "contacts", "caveat", "note"}
std::string ConvergeToJson(const ConvergenceResult& result);

// {"snapshot" (the path given), "model", "identical", "tol", the versions, "snapshot_sets",
//  "sets", "diverged", "notes", "changes": [{path, old, new, kind, step?, what}],
//  "compiler_changes"}
std::string DiffToJson(const SnapshotDiff& diff, const std::string& snapshot);

// {"model", "log", "window", "input_delay", "sensor_delay", "signals": [{column, path, samples,
//  rms, max_abs, worst_time, fit}], "fit", "diverged", "problem", "notes"}
std::string ReplayToJson(const std::string& model, const RobotLog& log,
                         const ReplayOptions& options, const ReplayResult& result);

// {"model", "estimates", "correlation", "singular_values", "delay"?, "first_solve",
//  "iterations", ..., "logs": [{log, fit_nominal, fit_fitted, noise}], "validation"?,
//  "warnings"}. `delay` is the kind of delay that was estimated; `validation` the held-out log's
// replays (nullptr: none).
std::string IdentifyToJson(const std::string& model, const IdentifyResult& result,
                           const std::vector<RobotLog>& logs, DelayKind delay,
                           const HeldOutLog* validation);

// plumb bridge --client: {"command": "rehearse", "model", "mujoco_version", "passed",
//  "rows": [row...], "summary", "client": {kind (ClientEndingName), exit_code (null when it did
//  not exit), signal (0: none), time, wall, last_lines, text}, "view": {commands,
//  first_command, first_command_time, period_median, period_p95, period_worst,
//  commands_per_period, motors: [{name, commands, outside_range, worst_outside, saturated,
//  saturated_fraction, worst_torque, tracking_rms, tracking_worst}], unknown_motors, own_pd},
//  "bridge": {every BridgeStats field}, "events": [{time, what}]}; a front end adds the
// call's "notices" (JsonWithNotices). The client's output is not trusted to be UTF-8: bytes
// that are not are replaced (U+FFFD), not refused.
std::string RehearsalToJson(const std::string& model, const RehearsalResult& result);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_RESULT_JSON_H_
