// Judging a scenario's assertions over a run: each assertion on each of its paths, sample
// by sample, reduced over its window, then a verdict per assertion.

#ifndef PLUMB_SRC_SCENARIO_ASSERTION_TALLY_H_
#define PLUMB_SRC_SCENARIO_ASSERTION_TALLY_H_

#include <cstddef>
#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/scenario.h"

namespace plumb::internal {

class AssertionTally {
 public:
  explicit AssertionTally(const std::vector<Assertion>& assertions);

  // Feeds the state at `time` (after mj_forward, so derived quantities describe it) to every
  // assertion whose window holds `time`.
  void Sample(const Model& model, const Data& data, double time);

  struct Verdict {
    bool ok = false;
    // the first path that fails it ("qpos[a] = 0.3 at t = 1.2 s"), else the closest call
    std::string measured;
  };

  // The verdict on assertion `a`: every path must satisfy it.
  Verdict Judge(std::size_t a) const;

 private:
  struct Tally {
    bool ok = true;  // every sample so far (kEach)
    double first_bad = 0, first_bad_time = 0;
    double reduced = 0;  // over time (the other reductions)
    bool seen = false;
  };
  void Add(Reduction reduce, Comparison op, double bound, double value, double time, Tally* t);

  const std::vector<Assertion>& assertions_;
  std::vector<std::vector<Tally>> tallies_;  // [assertion][path]
};

}  // namespace plumb::internal

#endif  // PLUMB_SRC_SCENARIO_ASSERTION_TALLY_H_
