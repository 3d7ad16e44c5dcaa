// The repro folder of a diverged run: everything needed to run the failing step again.
//
// Thread-safety: WriteRepro only reads `model` and `result` (Model::SaveXml is serialised with
// Model::Load). It assembles the folder under ".<name>.tmp-<process id>" beside `dir`, so two
// threads of one process must not write repros to the same `dir` at once.

#ifndef PLUMB_INCLUDE_PLUMB_REPRO_H_
#define PLUMB_INCLUDE_PLUMB_REPRO_H_

#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/run.h"

namespace plumb {

// Writes a repro folder for a diverged run and returns its path: model.xml (as saved by
// mj_saveLastXML, when the model came from XML), model.mjb (the exact compiled model,
// edits included), last_good.json and bad.json (time, qpos, qvel, act, ctrl),
// warnings.json, command.txt and README.txt. command.txt holds comment lines (the
// directory it ran in, and `note` when not empty, e.g. which of a command's runs
// diverged), then the exact command line, shell-quoted, as the last line: `sh command.txt`
// in that directory runs it again.
// The folder is `dir`, or `dir-2`, `dir-3`, ... when that exists; it is assembled under
// a temporary name and renamed, so it is complete or absent. @throws IoError.
std::string WriteRepro(const Model& model, const RunResult& result,
                       const std::vector<std::string>& argv, const std::string& dir,
                       const std::string& note = "");

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_REPRO_H_
