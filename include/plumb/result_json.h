// The JSON documents of plumb's results: what `--format json` prints, for a library user too.
//
// Each is pretty-printed (2-space indent) and ends in a newline. A number that is not finite
// (a NaN where nothing could be measured) is null. Check rows have one shape everywhere:
//   {"id", "section", "title", "status", "element", "element_type", "element_name",
//    "element_id", "measured", "measured_unit", "measured_text", "reference",
//    "reference_unit", "reference_text", "threshold", "rel_error", "explanation", "fix"}
// where "element" is the element's label or the row's subject ("" for the whole model), and
// "measured" and "reference" are the numbers, or the texts when the row has no number.
//
// Example:
//   std::string json = plumb::VerifyToJson(plumb::Verify(model, options));
//
// Thread-safety: pure functions of their arguments. Text that is not valid UTF-8 (a name in
// the model) makes nlohmann::json throw its type_error; nothing else is thrown.

#ifndef PLUMB_INCLUDE_PLUMB_RESULT_JSON_H_
#define PLUMB_INCLUDE_PLUMB_RESULT_JSON_H_

#include <string>

#include "plumb/audit.h"
#include "plumb/verify.h"

namespace plumb {

// {"model", "mujoco_version", "tol", "checks": [row...], "summary": {pass, warn, fail, skip}}
std::string VerifyToJson(const VerifyReport& report);

// {"model", "mujoco_version", "layers": {layer: [row...]}, "repro_folders", "summary"}
std::string AuditToJson(const AuditReport& report);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_RESULT_JSON_H_
