// Bodies that start asleep. With the sleep flag on (<option><flag sleep="enable"/>),
// MuJoCo 3.x freezes a kinematic tree whose speed stays below opt.sleep_tolerance, and
// <body sleep="init"> makes a tree start asleep: it does not move, answer its actuators or
// press on its contacts until something touches it. That saves time in a scene; it would
// make every test of the tree's physics read zero. plumb's one rule: the checks (audit,
// verify) run their copies of the model with sleep off, and say which bodies would have
// started asleep.
//
//   plumb::SleepingStart asleep = plumb::FindSleepingStart(model, data);  // after the start
//   plumb::Model awake = model.Clone();
//   plumb::WakeForTesting(awake);
//
// MuJoCo 2.x has no sleep: nothing is ever asleep. Thread-safety: FindSleepingStart only
// reads; WakeForTesting writes its model.

#ifndef PLUMB_INCLUDE_PLUMB_SLEEP_H_
#define PLUMB_INCLUDE_PLUMB_SLEEP_H_

#include <string>
#include <vector>

#include "plumb/keyframe.h"
#include "plumb/model.h"

namespace plumb {

struct SleepingStart {
  std::vector<std::string> bodies;  // the root body of each tree asleep at the start
  bool empty() const { return bodies.empty(); }
  // "Bodies 'arm', 'box' start asleep (...)", or "".
  std::string Describe() const;
};

// The trees asleep in `data` (a state made from `model`, after mj_forward), by root body.
SleepingStart FindSleepingStart(const Model& model, const Data& data);

// The trees asleep where a plain run of `model` from `pose` with `sets` on top starts: the
// model's own start, without the joints ReferencePose::into_range would move into their ranges
// (writing a tree's state wakes it). Writes `sets`' parameters into `model`.
// @throws as StartAtPose does.
SleepingStart FindSleepingStart(Model& model, const ReferencePose& pose,
                                const std::vector<Assignment>& sets);

// Turns sleep off in `model`: Data made or reset from it afterwards has every tree awake.
void WakeForTesting(Model& model);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_SLEEP_H_
