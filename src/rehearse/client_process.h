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
#include <string>
#include <utility>
#include <vector>

#include "core/child_process.h"

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

  // Ends it: `signal` to its process group, then SIGKILL to the group after `grace` s if it
  // still runs; it is reaped and its output read. What it started that outlives it (still in
  // its group) gets the same: the signal, the rest of `grace`, then SIGKILL. Returns whether
  // SIGKILL was needed for the client itself. When it has ended already only what lingers of
  // its group is stopped, and it returns false.
  bool Stop(int signal, double grace);

  // Once it has ended: its exit status (-1 when a signal ended it, or while it runs) and the
  // signal (0 when it exited, or while it runs).
  int exit_code() const;
  int signal() const;
  // "exited with status 1", "ended on SIGINT", "killed by SIGKILL after the grace period"
  // (Stop had to kill it); "is still running" before it ended.
  std::string HowItEnded() const;

  // Its output's last lines (a last line without its newline included), each cut at 1000
  // characters.
  std::vector<std::string> Tail() const;
  double wall() const;  // s since it started (until it ended, once it has)
  // Why writing its output to the file stopped ("" when every line was written).
  const std::string& output_error() const { return output_error_; }

 private:
  void Read();
  void AddOutput(const char* data, std::size_t size);
  // Reaps it when it has ended (waiting for it when `block`), then reads what is left of its
  // output. Returns whether it has ended.
  bool Reap(bool block);
  // Whether anything of its process group still runs (zombies do not count).
  bool GroupRunning();

  std::string command_;  // for messages
  std::string output_path_;
  pid_t pid_ = -1;    // -1 once reaped
  pid_t group_ = -1;  // kept after it is reaped: what it started may outlive it; -1 once empty
  int fd_ = -1;       // the read end of its output's pipe
  int status_ = 0;
  bool status_known_ = false;  // false: another part of plumb reaped it
  bool ended_ = false;
  bool killed_ = false;  // Stop had to SIGKILL it
  LineTail tail_;
  int output_fd_ = -1;
  std::string output_error_;
  double started_ = 0, ended_at_ = 0;  // steady clock, s
};

}  // namespace plumb::internal

#endif  // PLUMB_SRC_REHEARSE_CLIENT_PROCESS_H_
