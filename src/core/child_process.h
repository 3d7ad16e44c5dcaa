// The pieces plumb's child processes share (crosscheck's engine adapter, the rehearsal's
// client): the environment they get, the spawn (a process group of their own, signals as a fresh
// process has them, their standard streams on descriptors plumb made, a working directory),
// reading what they write without blocking, the last lines of it, and how one ended.
//
// Nothing here throws plumb's errors: a failure is an errno value, and the caller words it.
//
// Thread-safety: the functions are; one thread at a time uses a LineTail.

#ifndef PLUMB_SRC_CORE_CHILD_PROCESS_H_
#define PLUMB_SRC_CORE_CHILD_PROCESS_H_

#include <sys/types.h>

#include <cstddef>
#include <deque>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace plumb::internal {

// plumb's environment with `extra` set on top of it ("NAME=value" entries).
std::vector<std::string> ChildEnvironment(
    const std::vector<std::pair<std::string, std::string>>& extra);

// `fd` moved above the standard streams (so the child's dup2 onto 0, 1, 2 cannot clobber it),
// close-on-exec; -1 on failure (errno set).
int AboveStdio(int fd);
// Closes `fd` when it is open and sets it to -1.
void CloseFd(int& fd);

// Starts `program` (a path, or a name looked up on plumb's PATH) with `argv` and `env` in a
// process group of its own, with no blocked signal and SIGPIPE, SIGINT and SIGTERM as a fresh
// process has them (an ignored signal stays ignored across exec, and plumb's command ignores
// SIGPIPE), its standard input, output and error on child_fds[0..2] (descriptors above 2: see
// AboveStdio) and `directory` as its working directory ("": plumb's). Returns 0 and sets *pid,
// or the error number posix_spawn gave.
int SpawnChild(const std::string& program, const std::vector<std::string>& argv,
               const std::vector<std::string>& env, const int child_fds[3],
               const std::string& directory, pid_t* pid);

// Reads what is there on the non-blocking `fd` (up to `most` bytes) and hands it to `take`;
// closes `fd` (sets it to -1) at its end or on an error that reading again will not mend.
// Returns whether anything was read.
bool ReadAvailable(int& fd, const std::function<void(const char*, std::size_t)>& take,
                   std::size_t most = std::size_t(1) << 20);

// Whether a process of the group `group` still runs: zombies, which a signal no longer ends (an
// init that reaps no orphans leaves them), do not count.
bool ProcessGroupRunning(pid_t group);

// How a child ended, from its wait status, as part of a sentence: "it exited with status 1",
// "it was killed by signal 11 (Segmentation fault)", "plumb killed it" (SIGKILL when
// `plumb_killed`).
std::string WaitStatusText(int status, bool plumb_killed);
// A signal's short name: "SIGINT", "SIGKILL"; "signal 42" for one without a name.
std::string SignalName(int signal);

// The last lines of a stream of text, each cut at `line_chars` characters.
class LineTail {
 public:
  LineTail(std::size_t most_lines, std::size_t line_chars)
      : most_lines_(most_lines), line_chars_(line_chars) {}
  void Add(const char* data, std::size_t size);
  // The complete lines kept (up to most_lines), oldest first.
  const std::deque<std::string>& lines() const { return lines_; }
  // The last line so far, not yet ended by a newline.
  const std::string& partial() const { return partial_; }
  // The last most_lines lines, the partial one included when there is one.
  std::vector<std::string> Last() const;

 private:
  std::size_t most_lines_, line_chars_;
  std::deque<std::string> lines_;
  std::string partial_;
};

}  // namespace plumb::internal

#endif  // PLUMB_SRC_CORE_CHILD_PROCESS_H_
