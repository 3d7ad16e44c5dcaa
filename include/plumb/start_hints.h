// Advice before a run starts, from the chapter's common-error table.
//
// Example:
//   for (const std::string& hint : plumb::StartHints(model, data)) std::puts(hint.c_str());
//
// Thread-safety: StartHints only reads `model` and `data` (it tries offsets on a copy of the
// data) and keeps no state, so it may run while other threads read them too, but not while
// `data` is being written.

#ifndef PLUMB_INCLUDE_PLUMB_START_HINTS_H_
#define PLUMB_INCLUDE_PLUMB_START_HINTS_H_

#include <string>
#include <vector>

#include "plumb/model.h"

namespace plumb {

// The chapter's common-error table, for the state a run is about to start from: one
// line of advice per problem found (empty when nothing looks wrong). Today: a system
// at rest in equilibrium with nothing driving it will not move; the advice names a
// --set that plumb tried and found to make it accelerate (so following it never
// repeats the hint), or a velocity when no offset does. @throws MujocoError.
std::vector<std::string> StartHints(const Model& model, const Data& data);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_START_HINTS_H_
