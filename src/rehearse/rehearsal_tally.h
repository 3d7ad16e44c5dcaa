// A rehearsal's assertions judged as the bridge runs (plumb/rehearse.h RehearsalAssertion):
// each published state is a sample of every assertion whose window holds it, as
// scenario/assertion_tally.h judges a scenario's; and the time axis the report draws (the
// asserted signals, each motor's commanded and measured position).

#ifndef PLUMB_SRC_REHEARSE_REHEARSAL_TALLY_H_
#define PLUMB_SRC_REHEARSE_REHEARSAL_TALLY_H_

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "plumb/bridge.h"
#include "plumb/check.h"
#include "plumb/model.h"
#include "plumb/rehearse.h"
#include "scenario/assertion_tally.h"

namespace plumb::internal {

class RehearsalTally {
 public:
  // The trace keeps at most `trace_cap` samples (at least 2): past it, every other one is
  // dropped and from then on every 2nd state is kept, then every 4th, ...
  RehearsalTally(const std::vector<RehearsalAssertion>& assertions,
                 const std::vector<BridgeMotorInfo>& motors, std::size_t trace_cap = 20000);
  RehearsalTally(const RehearsalTally&) = delete;  // tally_ reads plain_
  RehearsalTally& operator=(const RehearsalTally&) = delete;

  // A published state (derived quantities computed) and its motors.
  void Sample(const Model& model, const Data& data, const std::vector<BridgeMotorSample>& motors);
  void Event(double t, const std::string& what);

  // One row per assertion (section "assert", id "assert", subject its text): PASS when it
  // holds, FAIL with the first sample that breaks it or the reduced value, SKIP... never: an
  // assertion with no sample in its window FAILs saying so.
  std::vector<CheckRow> Rows() const;

  // The time axis, moved out.
  RehearsalTrace TakeTrace();

 private:
  // Signal k of assertion a at this state; nullopt when it has no sample (a tracking error
  // with no position command in force).
  std::optional<double> Value(std::size_t a, std::size_t k, const Model& model, const Data& data,
                              const std::vector<BridgeMotorSample>& motors) const;
  bool KeepInTrace();  // whether this state goes into the trace (decimation)

  std::vector<RehearsalAssertion> assertions_;
  std::vector<Assertion> plain_;  // each one's Assertion, as tally_ reads them
  AssertionTally tally_;
  std::vector<BridgeMotorInfo> motors_;
  std::vector<std::size_t> motor_slots_;  // the slots with a motor (empty ones left out)
  std::vector<std::string> motor_names_;  // the motors' names, a number when unnamed
  std::vector<std::vector<std::size_t>> trace_index_;  // [assertion][signal]: its trace row
  RehearsalTrace trace_;
  std::size_t trace_cap_;
  long states_ = 0;  // samples seen
  long stride_ = 1;  // the trace keeps every stride_-th
};

}  // namespace plumb::internal

#endif  // PLUMB_SRC_REHEARSE_REHEARSAL_TALLY_H_
