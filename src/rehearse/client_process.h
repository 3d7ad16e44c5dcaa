// The rehearsal's client as a child process: `/bin/sh -c COMMAND` in a working directory, with
// variables set on top of plumb's environment, its standard input /dev/null and its standard
// output and error together on one pipe that plumb reads (the last lines kept, every line
// optionally written to a file). It runs in a process group of its own: Ctrl-C reaches plumb
// alone, which stops it, and a signal to the group reaches whatever it started (a shell
// script's python, a launcher's workers).
//
// Thread-safety: one thread at a time uses a ClientProcess.

#ifndef PLUMB_SRC_REHEARSE_CLIENT_PROCESS_H_
#define PLUMB_SRC_REHEARSE_CLIENT_PROCESS_H_

#include <sys/types.h>

#include <cstddef>
#include <cstdio>
#include <deque>
#include <string>
#include <utility>
#include <vector>

namespace plumb::internal {

class ClientProcess {
 public:
  // Starts it. `output`: a file for its whole output ("" none), truncated first.
  // @throws ValueError naming `directory` when it is not a directory plumb may enter; IoError
  // when the pipe, the output file or the process cannot be made.
  ClientProcess(const std::string& command, const std::string& directory,
                const std::vector<std::pair<std::string, std::string>>& environment,
                std::size_t tail_lines, const std::string& output);
  // Kills its process group if it still runs, and reaps it: never leaves a process behind.
  ~ClientProcess();
  ClientProcess(const ClientProcess&) = delete;
  ClientProcess& operator=(const ClientProcess&) = delete;

  // Reads what it wrote, for up to `seconds` or until it ends. Returns whether it has ended
  // (then its output is read to the end).
  bool Poll(double seconds);
  bool running() const { return pid_ > 0; }

  // Ends it: `signal` to its process group, then SIGKILL after `grace` s if it still runs.
  // Returns whether SIGKILL was needed. Nothing when it has ended already.
  bool Stop(int signal, double grace);

  // Once it has ended: its exit status (-1 when a signal ended it) and the signal (0 when it
  // exited).
  int exit_code() const;
  int signal() const;
  // "exited with status 1", "ended on SIGINT", "killed by SIGKILL"
  std::string HowItEnded() const;

  // Its output's last lines (a last line without its newline included).
  std::vector<std::string> Tail() const;
  double wall() const;  // s since it started (until it ended, once it has)

 private:
  void Read();
  void AddOutput(const char* data, std::size_t size);

  pid_t pid_ = -1;
  pid_t group_ = -1;  // kept after it is reaped: what it started may outlive it
  int fd_ = -1;
  int status_ = 0;
  bool ended_ = false;
  std::size_t tail_lines_;
  std::deque<std::string> lines_;
  std::string partial_;
  std::FILE* output_ = nullptr;
  double started_ = 0, ended_at_ = 0;  // steady clock, s
};

}  // namespace plumb::internal

#endif  // PLUMB_SRC_REHEARSE_CLIENT_PROCESS_H_
