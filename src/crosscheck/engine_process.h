// EngineProcess: plumb's side of the engine adapter protocol (docs/engine-protocol.md).
//
// plumb crosscheck runs MuJoCo Warp and MJX, which are Python libraries, in a child process: the
// adapter (`<python> <engines>/adapter.py --engine warp --device cpu`). An EngineProcess starts
// it with its standard input and output on pipes and exchanges messages with it: one line of
// JSON, then the float64 arrays the line lists, in both directions. Standard error is the
// adapter's log: its last lines are kept for the messages of errors.
//
// Every failure of the adapter is an EngineError (the command-line tool exits with 6); an engine
// that refuses the model or an option is an EngineRefused, which crosscheck reports as a failed
// row. After an EngineError the adapter is gone (it is killed if it was still running) and every
// further Request says so; after an EngineRefused or another error reply it goes on serving.
//
// Thread-safety: one EngineProcess is used by one thread at a time. Nothing here changes the
// process's signal dispositions: writes go through a socket with MSG_NOSIGNAL, so an adapter that
// died makes a write fail with EPIPE rather than raise SIGPIPE.

#ifndef PLUMB_SRC_CROSSCHECK_ENGINE_PROCESS_H_
#define PLUMB_SRC_CROSSCHECK_ENGINE_PROCESS_H_

#include <sys/types.h>

#include <chrono>
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/child_process.h"
#include "plumb/stop.h"

namespace plumb::internal {

// One named array of a message: row-major values of the given shape (values.size() is the
// product of shape; an empty shape holds one value).
struct EngineArray {
  std::string name;
  std::vector<long> shape;
  std::vector<double> values;
};

// A reply of the adapter whose "ok" is true: its JSON line (with its "arrays" list) and the
// arrays of its payload, in the order sent.
struct EngineReply {
  nlohmann::json header;
  std::vector<EngineArray> arrays;

  const EngineArray* Find(std::string_view name) const;  // nullptr when absent
  const EngineArray& Get(std::string_view name) const;   // throws EngineError naming it
};

class EngineProcess {
 public:
  // Starts the adapter: argv[0] is the program (a path, or a name looked up on PATH), the rest its
  // arguments; extra_env is set in its environment on top of plumb's. Throws EngineError when it
  // cannot be started.
  explicit EngineProcess(std::vector<std::string> argv,
                         std::vector<std::pair<std::string, std::string>> extra_env = {});
  // Sends {"op":"quit"} and closes the adapter's input, waits up to 2 s for it to exit, then
  // kills it (its whole process group) and reaps it: never leaves a process behind, never throws.
  ~EngineProcess();
  EngineProcess(const EngineProcess&) = delete;
  EngineProcess& operator=(const EngineProcess&) = delete;

  // Sends one request and waits for its reply. The header's "arrays" list is made from `arrays`
  // (names and shapes; any "arrays" the header has is replaced). Throws
  //  - EngineRefused (the adapter's message verbatim) for a reply {"ok": false, "error":
  //    "refused"}, EngineError for any other error reply; the adapter goes on serving;
  //  - EngineError when the adapter exits or closes its output (the message gives its exit
  //    status or signal), breaks the framing, or does not reply within timeout_s seconds
  //    (<= 0: no limit), quoting its last lines on stderr; the adapter is then gone;
  //  - Interrupted when `stop` asks (looked at every 50 ms): the adapter is killed.
  // InternalError when an array's values do not fill its shape (a bug in the caller).
  EngineReply Request(const nlohmann::json& header, const std::vector<EngineArray>& arrays = {},
                      double timeout_s = 0, const StopToken& stop = {});

  // The adapter's last lines on stderr (up to 40, each cut at 1000 characters), one a line.
  std::string StderrTail() const;
  // The adapter's process id; -1 once it has ended and been reaped (for tests).
  pid_t pid() const { return pid_; }

 private:
  using Clock = std::chrono::steady_clock;
  struct Outgoing;
  class ReplyReader;

  // One round of poll() on the adapter's pipes, at most `wait_ms`: writes what `out` has left
  // (when given), reads stdout into `reader` (when given; else it is dropped) and stderr into
  // the tail. Returns what went wrong ("closed its output", "broke the protocol: ..."), or "".
  std::string PumpOnce(Outgoing* out, ReplyReader* reader, int wait_ms);
  void ReadStderr();
  // Kills the adapter's process group and reaps it (when it runs); closes the pipes.
  void Kill();
  // Waits up to `seconds` for the adapter to exit by itself, draining its output; reaps it and
  // returns true when it did.
  bool WaitForExit(double seconds);
  // The adapter failed: lets it end by itself for up to grace_s seconds (it may be exiting), kills
  // and reaps it, and throws EngineError saying `what` happened, how it ended and its last lines
  // on stderr. Later Requests throw the same.
  [[noreturn]] void Fail(const std::string& what, double grace_s);
  std::string HowItEnded() const;

  std::string program_;
  std::string command_;        // its command line, for messages
  pid_t pid_ = -1;             // -1 once reaped
  int status_ = 0;             // waitpid's status once reaped
  bool status_known_ = false;  // status_ is the adapter's (false: someone else reaped it)
  bool killed_ = false;        // plumb killed it
  int in_fd_ = -1;             // the adapter's stdin (a socket: MSG_NOSIGNAL)
  int out_fd_ = -1;            // its stdout
  int err_fd_ = -1;            // its stderr
  std::string failure_;        // why the adapter is gone, once it is
  std::vector<char> read_buffer_;
  LineTail stderr_tail_;  // its last lines on stderr
};

}  // namespace plumb::internal

#endif  // PLUMB_SRC_CROSSCHECK_ENGINE_PROCESS_H_
