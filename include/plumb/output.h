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

// The output file of a command's -o: a file that appears under its final name only
// when complete. It is written to a hidden temporary file in the same directory and
// renamed over the target by Commit(). If Commit() is never called (an error, an
// exception, an interrupt), the destructor removes the temporary file and nothing
// appears under the target. A SIGKILL can leave the hidden temporary behind, never a
// half-written target. What `path` names decides how it is written:
//   - "-": standard output (written directly, flushed by Commit(), never closed);
//   - a symbolic link (a chain of them, or one whose target does not exist yet): the
//     link is followed and the temporary file is renamed next to its final target, so
//     the link stays a link and now points to the new contents;
//   - an existing file that is not a regular file (a FIFO, a character or block device,
//     a terminal, a /proc or /dev/fd link such as /dev/stdout): opened and written
//     directly, with no temporary file and no rename, so a device node or FIFO is never
//     replaced by a regular file. A socket cannot be opened and is refused (IoError).
// An existing regular target keeps its permission bits; a new one gets 0666 & ~umask.
class AtomicFile {
 public:
  // Opens the output as described above (opening a FIFO waits for its reader).
  // @throws IoError naming `path` when the directory does not exist or is not writable,
  // when `path` is a directory or a socket, or when a chain of links does not end.
  explicit AtomicFile(std::string path);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();

  // The stream to write to (fully buffered).
  std::FILE* stream() { return file_; }
  // The path as given ("-" for standard output).
  const std::string& path() const { return path_; }
  // True when the output is written directly (standard output, FIFO, device) rather
  // than through a temporary file and a rename.
  bool direct() const { return temp_path_.empty(); }

  // Flushes, syncs and renames into place (direct outputs are flushed only).
  // @throws IoError on any write failure (e.g. disk full, ENOSPC on /dev/full); nothing
  // appears under the target then, except what a direct output has already received.
  void Commit();

 private:
  std::string path_;       // as given
  std::string target_;     // where the rename lands (the end of a chain of links)
  std::string temp_path_;  // empty for direct outputs
  struct Channel;          // the descriptor under file_ and its first write error
  std::unique_ptr<Channel> channel_;
  std::FILE* file_ = nullptr;
  bool owns_file_ = true;  // false for standard output
  bool committed_ = false;
};

// Output formats of sampled rows.
enum class SampleFormat {
  kTable,  // fixed-width columns, 5 decimals: the chapter's printout
  kCsv,    // header of path names, then the shortest text that reads back exactly
  kJsonl,  // one JSON object per sample, keys are path names
};

// CSV as every plumb command writes it. A number is the shortest text that reads back as
// exactly `v` (0.3, not 0.29999999999999999; std::to_chars, faster than printf, which matters
// when every step is a row), and NaN (not measured) is an empty field. A text field is
// quoted (RFC 4180) when it holds a comma, quote or newline.
void AppendCsvNumber(std::string* out, double v);
std::string CsvNumber(double v);
std::string CsvField(const std::string& text);

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
