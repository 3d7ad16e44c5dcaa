// The support check: what the engine refuses (its own words), and a documented table of what it
// accepts but computes differently from CPU MuJoCo, each finding named by element
// (docs/crosscheck.md lists the table and its sources).

#ifndef PLUMB_SRC_CROSSCHECK_SUPPORT_CHECK_H_
#define PLUMB_SRC_CROSSCHECK_SUPPORT_CHECK_H_

#include <set>
#include <string>
#include <utility>
#include <vector>

#include "plumb/check.h"
#include "plumb/crosscheck.h"
#include "plumb/model.h"

namespace plumb::internal {

// Geom pairs (smaller id first) that touch in CPU MuJoCo's run: what collision entries judge,
// so that boxes that never meet raise nothing.
using GeomPairs = std::set<std::pair<int, int>>;

// The versions row, then one row per table entry the model meets (PASS when it meets none).
std::vector<CheckRow> SupportRows(const Model& model, const EngineInfo& engine,
                                  const std::string& plumb_mujoco, const GeomPairs& touching);

// The engine's refusal (`message` verbatim), named by the element it concerns where the
// message says (the solver, the integrator, a geom type).
CheckRow RefusalRow(const Model& model, const std::string& engine, const std::string& message);

// A FAIL when the engine had no room for contacts or constraint rows (it drops them); a row with
// an empty id when it had room.
CheckRow CapacityRow(long contacts, long constraints);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_CROSSCHECK_SUPPORT_CHECK_H_
