// What regression.cc (writing a snapshot) gives regression_diff.cc (comparing one with the
// current model). Private to the regression folder.

#ifndef PLUMB_SRC_REGRESSION_REGRESSION_INTERNAL_H_
#define PLUMB_SRC_REGRESSION_REGRESSION_INTERNAL_H_

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/path.h"

namespace plumb::internal {

using nlohmann::ordered_json;

// The snapshot format written ("plumb_snapshot"): 2 added the keyframes (structure.keyframe);
// version 1 files are still read, and their keyframes are not compared.
inline constexpr int kSnapshotFormat = 2;

// The snapshot of `model` with `sets` applied, as JSON; `diverged` receives the reason when
// the golden trajectory diverges ("" otherwise).
ordered_json SnapshotJson(const Model& model, const std::vector<Assignment>& sets,
                          std::string* diverged);

// How a snapshot names element `id` of type `obj`: its name, "world" for body 0, "#3" when
// unnamed, "(none)" for -1.
std::string SnapshotElementName(const Model& model, int obj, int id);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_REGRESSION_REGRESSION_INTERNAL_H_
