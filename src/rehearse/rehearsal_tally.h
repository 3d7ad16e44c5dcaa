// A rehearsal's assertions judged as the bridge runs (plumb/rehearse.h RehearsalAssertion):
// each published state is a sample of every assertion whose window holds it, as
// scenario/assertion_tally.h judges a scenario's; and the time axis the report draws (the
// asserted signals, each motor's commanded and measured position).

#ifndef PLUMB_SRC_REHEARSE_REHEARSAL_TALLY_H_
#define PLUMB_SRC_REHEARSE_REHEARSAL_TALLY_H_

#include <vector>

#include "plumb/bridge.h"
#include "plumb/check.h"
#include "plumb/model.h"
#include "plumb/rehearse.h"

namespace plumb::internal {

class RehearsalTally {
 public:
  RehearsalTally(const std::vector<RehearsalAssertion>& assertions,
                 const std::vector<BridgeMotorInfo>& motors);

  // A published state (derived quantities computed) and its motors.
  void Sample(const Model& model, const Data& data, const std::vector<BridgeMotorSample>& motors);
  void Event(double t, const std::string& what);

  // One row per assertion (section "assert", id "assert", subject its text): PASS when it
  // holds, FAIL with the first sample that breaks it or the reduced value, SKIP... never: an
  // assertion with no sample in its window FAILs saying so.
  std::vector<CheckRow> Rows() const;

  // The time axis, moved out.
  RehearsalTrace TakeTrace();
};

}  // namespace plumb::internal

#endif  // PLUMB_SRC_REHEARSE_REHEARSAL_TALLY_H_
