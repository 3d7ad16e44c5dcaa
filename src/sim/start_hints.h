// Advice before a run starts, from the chapter's common-error table.
//
// Example:
//   for (const plumb::StartHint& hint : plumb::StartHints(model, data)) {
//     std::printf("%s %s, e.g. %s\n", hint.problem.c_str(), hint.advice.c_str(),
//                 hint.assignment.c_str());
//   }
//
// Thread-safety: StartHints only reads `model` and `data` (it tries offsets on a copy of the
// data) and keeps no state, so it may run while other threads read them too, but not while
// `data` is being written.

#ifndef PLUMB_SRC_SIM_START_HINTS_H_
#define PLUMB_SRC_SIM_START_HINTS_H_

#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/notice.h"

namespace plumb::internal {

// One problem with a start state, and what to do about it.
struct StartHint {
  std::string problem;     // "the model starts at rest in equilibrium ...: it will not move ..."
  std::string advice;      // "Start it away from equilibrium"
  std::string assignment;  // the assignment that does it (ParseAssignment's text), e.g.
                           // "qpos[hinge]=0.7"; "" when there is none to give
  std::string evidence;    // why it works ("plumb tried it: it gives |qacc| up to 3.2"), or ""
};

// The chapter's common-error table, for the state a run is about to start from: one hint
// per problem found (empty when nothing looks wrong). Today: a system at rest in
// equilibrium with nothing driving it will not move; the hint's assignment is one plumb
// tried and found to make it accelerate (so following it never repeats the hint), or a
// velocity when no offset does. Bodies that start asleep (plumb/sleep.h) stay still too;
// that hint's assignment turns sleep off. @throws MujocoError.
std::vector<StartHint> StartHints(const Model& model, const Data& data);

// Each of StartHints' hints, added to `notices` as a hint (topic kStart) whose text is what the
// plumb command prints after "plumb: hint: ": "PROBLEM ADVICE, e.g. ARGUMENT 'ASSIGNMENT'
// (EVIDENCE).", `argument` as the caller names it (Python's "set", the plumb command's flag).
// @throws MujocoError.
void AddStartHints(const Model& model, const Data& data, const std::string& argument,
                   Notices* notices);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_SIM_START_HINTS_H_
