// plumb's JSON documents: a model's description, a state, a run's warnings.
//
// Thread-safety: the functions are pure: call them from any thread. They throw nothing of
// plumb's own; text that is not valid UTF-8 (a name in the model) makes nlohmann::json throw
// its type_error.

#ifndef PLUMB_INCLUDE_PLUMB_JSON_OUTPUT_H_
#define PLUMB_INCLUDE_PLUMB_JSON_OUTPUT_H_

#include <string>
#include <vector>

#include "plumb/describe.h"
#include "plumb/run.h"

namespace plumb {

// JSON documents (pretty-printed, 2-space indent, ending in a newline).
std::string DescriptionToJson(const ModelDescription& description, const std::string& mujoco);
std::string StateToJson(const StateSnapshot& state);
std::string WarningsToJson(const std::vector<WarningSummary>& warnings);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_JSON_OUTPUT_H_
