// Writing results: atomic files, run samples as table/CSV/JSON lines, JSON documents,
// and the repro folder of a diverged run.

#ifndef PLUMB_INCLUDE_PLUMB_OUTPUT_H_
#define PLUMB_INCLUDE_PLUMB_OUTPUT_H_

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "plumb/describe.h"
#include "plumb/run.h"

namespace plumb {

// A file that appears under its final name only when complete: it is written to a
// hidden temporary file in the same directory and renamed over `path` by Commit().
// If Commit() is never called (an error, an exception, an interrupt), the destructor
// removes the temporary file and nothing appears under `path`. A SIGKILL can leave the
// hidden temporary behind, never a half-written `path`.
class AtomicFile {
 public:
  // Creates the temporary file. @throws IoError naming `path` when the directory does
  // not exist or is not writable.
  explicit AtomicFile(std::string path);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();

  // The stream to write to (fully buffered).
  std::FILE* stream() { return file_; }
  const std::string& path() const { return path_; }

  // Flushes, syncs and renames into place. @throws IoError on any write failure
  // (e.g. disk full), in which case nothing appears under `path`.
  void Commit();

 private:
  std::string path_;
  std::string temp_path_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
};

// Output formats of sampled rows.
enum class SampleFormat {
  kTable,  // fixed-width columns, 5 decimals: the chapter's printout
  kCsv,    // header of path names, then %.17g values (full double precision)
  kJsonl,  // one JSON object per sample, keys are path names
};

// A sink writing rows to `out` (not owned) in `format`. Rows are written as they
// arrive; nothing is kept in memory. Write errors surface as IoError from End().
std::unique_ptr<SampleSink> MakeSampleWriter(SampleFormat format, std::FILE* out);

// JSON documents (pretty-printed, 2-space indent, ending in a newline).
std::string DescriptionToJson(const ModelDescription& description, const std::string& mujoco);
std::string StateToJson(const StateSnapshot& state);
std::string WarningsToJson(const std::vector<WarningSummary>& warnings);

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

// Quotes `arg` for a POSIX shell when it needs it.
std::string ShellQuote(const std::string& arg);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_OUTPUT_H_
