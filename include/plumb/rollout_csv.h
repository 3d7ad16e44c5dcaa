// Rollouts as CSV, the one layout `plumb rollout` prints and `plumb results` reads back out of a
// store: rollout, the drawn parameters, the metrics (empty when unmeasured), diverged (0/1),
// diverged_at (s; empty unless diverged), problem (why metrics are missing; empty when none).
// Numbers and text follow plumb's CSV rules (CsvNumber, CsvField in plumb/sample_writer.h).
//
// Thread-safety: pure functions. Nothing throws but std::bad_alloc.

#ifndef PLUMB_INCLUDE_PLUMB_ROLLOUT_CSV_H_
#define PLUMB_INCLUDE_PLUMB_ROLLOUT_CSV_H_

#include <string>
#include <vector>

#include "plumb/rollout.h"

namespace plumb {

// The column names, in order, for rollouts with these parameter and metric names (as
// ParameterNames and the metrics' texts give them).
std::vector<std::string> RolloutCsvColumns(const std::vector<std::string>& params,
                                           const std::vector<std::string>& metrics);

// One rollout's line, with its newline, in the order of RolloutCsvColumns.
std::string RolloutCsvRow(const RolloutResult& result);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_ROLLOUT_CSV_H_
