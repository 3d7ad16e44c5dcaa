// Judging a scenario's assertions over a run: each assertion on each of its signals (its
// paths, or values a caller reads itself), sample by sample, reduced over its window, then a
// verdict per assertion.

#ifndef PLUMB_SRC_SCENARIO_ASSERTION_TALLY_H_
#define PLUMB_SRC_SCENARIO_ASSERTION_TALLY_H_

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/scenario.h"

namespace plumb::internal {

class AssertionTally {
 public:
  // Each assertion's signals are its paths. `assertions` must outlive the tally.
  explicit AssertionTally(const std::vector<Assertion>& assertions);
  // Assertion a's signals are `names[a]` (its paths when that is empty or missing), fed by
  // SampleValue.
  AssertionTally(const std::vector<Assertion>& assertions,
                 std::vector<std::vector<std::string>> names);

  // Feeds the state at `time` (after mj_forward, so derived quantities describe it) to every
  // path of every assertion whose window holds `time`.
  void Sample(const Model& model, const Data& data, double time);

  // Whether assertion a's window holds `time`.
  bool InWindow(std::size_t a, double time) const;
  // Feeds signal k of assertion a its value at `time`; nothing outside a's window.
  void SampleValue(std::size_t a, std::size_t k, double value, double time);

  struct Verdict {
    bool ok = false;
    // the first signal that fails it ("qpos[a] = 0.3 at t = 1.2 s"), else the closest call
    std::string measured;
    // the number that decides it (the failing sample, the reduced value); NaN when none does
    // (every sample holds, no sample)
    double value = NAN;
  };

  // The verdict on assertion `a`: every signal must satisfy it.
  Verdict Judge(std::size_t a) const;

 private:
  struct Tally {
    bool ok = true;  // every sample so far (kEach)
    double first_bad = 0, first_bad_time = 0;
    double reduced = 0;  // over time (the other reductions)
    double sum = 0;      // kMean: of the samples
    long count = 0;      // samples
  };
  static void Add(const Assertion& as, double value, double time, Tally* t);

  const std::vector<Assertion>& assertions_;
  std::vector<std::vector<std::string>> names_;  // [assertion][signal]
  std::vector<std::vector<Tally>> tallies_;      // [assertion][signal]
  std::vector<bool> paths_;                      // [assertion]: its signals are its paths
};

}  // namespace plumb::internal

#endif  // PLUMB_SRC_SCENARIO_ASSERTION_TALLY_H_
