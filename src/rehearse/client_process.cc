// The client as a child process: spawned with the core's pieces (core/child_process.h), read
// with poll() in slices short enough to notice that it ended while something it started still
// holds its output's pipe open.

#include "rehearse/client_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <thread>

#include "plumb/error.h"

namespace plumb::internal {
namespace {

constexpr std::size_t kLineChars = 1000;       // characters kept of each line of the tail
constexpr double kSlice = 0.01;                // s: how often Poll looks whether it has ended
constexpr std::size_t kFinalRead = 16u << 20;  // bytes read at most once it has ended

double Now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Refuses a working directory the client could not start in, naming it.
void CheckDirectory(const std::string& directory) {
  if (directory.empty()) return;
  struct stat info;
  std::string why;
  if (stat(directory.c_str(), &info) != 0) {
    why = std::strerror(errno);
  } else if (!S_ISDIR(info.st_mode)) {
    why = "it is a file";
  } else if (access(directory.c_str(), X_OK) != 0) {
    why = std::string("plumb may not enter it (") + std::strerror(errno) + ")";
  }
  if (!why.empty()) {
    throw ValueError("the client's working directory '" + directory + "' is not a directory: " +
                     why + ". Give a folder that exists (a relative one is taken from the folder " +
                     "plumb runs in), or none to run the client in plumb's.");
  }
}

}  // namespace

ClientProcess::ClientProcess(const std::string& command, const std::string& directory,
                             const std::vector<std::pair<std::string, std::string>>& environment,
                             std::size_t tail_lines, const std::string& output)
    : command_(command), output_path_(output), tail_(tail_lines, kLineChars) {
  CheckDirectory(directory);
  if (!output.empty()) {
    output_fd_ = open(output.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (output_fd_ < 0) {
      throw IoError("cannot write the client's output to '" + output +
                    "': " + std::strerror(errno) + ". Give a file in a folder plumb may write to.");
    }
  }
  int out[2] = {-1, -1};
  int input = -1;
  auto fail = [&](const std::string& what, int error) {
    for (int* fd : {&out[0], &out[1], &input, &output_fd_}) CloseFd(*fd);
    throw IoError("cannot start the client (/bin/sh -c '" + command + "'): " + what + ": " +
                  std::strerror(error));
  };
  if (pipe2(out, O_CLOEXEC) != 0 || (out[1] = AboveStdio(out[1])) < 0) {
    fail("no pipe for its output", errno);
  }
  if ((input = open("/dev/null", O_RDONLY | O_CLOEXEC)) < 0 || (input = AboveStdio(input)) < 0) {
    fail("cannot open /dev/null for its input", errno);
  }
  const int child_fds[3] = {input, out[1], out[1]};
  started_ = Now();
  if (int error = SpawnChild("/bin/sh", {"/bin/sh", "-c", command}, ChildEnvironment(environment),
                             child_fds, directory, &pid_)) {
    pid_ = -1;
    fail("/bin/sh could not be run", error);
  }
  group_ = pid_;
  CloseFd(input);
  CloseFd(out[1]);
  fd_ = out[0];
  fcntl(fd_, F_SETFL, fcntl(fd_, F_GETFL) | O_NONBLOCK);
}

ClientProcess::~ClientProcess() {
  if (pid_ > 0) {
    kill(-group_, SIGKILL);
    kill(pid_, SIGKILL);
    while (waitpid(pid_, &status_, 0) < 0 && errno == EINTR) {
    }
    pid_ = -1;
  }
  if (group_ > 0) kill(-group_, SIGKILL);  // what it started and left behind; ESRCH: nothing
  CloseFd(fd_);
  CloseFd(output_fd_);
}

void ClientProcess::AddOutput(const char* data, std::size_t size) {
  tail_.Add(data, size);
  while (output_fd_ >= 0 && size > 0) {
    ssize_t wrote = write(output_fd_, data, size);
    if (wrote < 0 && errno == EINTR) continue;
    if (wrote <= 0) {
      output_error_ = "cannot write to '" + output_path_ + "': " + std::strerror(errno);
      CloseFd(output_fd_);
      break;
    }
    data += wrote;
    size -= std::size_t(wrote);
  }
}

void ClientProcess::Read() {
  ReadAvailable(fd_, [this](const char* data, std::size_t size) { AddOutput(data, size); });
}

bool ClientProcess::Reap(bool block) {
  if (pid_ <= 0) return ended_;
  pid_t done;
  while ((done = waitpid(pid_, &status_, block ? 0 : WNOHANG)) < 0 && errno == EINTR) {
  }
  if (done == 0) return false;
  status_known_ = done == pid_;  // else ECHILD: another part of plumb reaped it
  pid_ = -1;
  ended_ = true;
  ended_at_ = Now();
  // What it wrote is in the pipe now; what it started may hold the pipe open and write on:
  // take what is there, and no more.
  ReadAvailable(
      fd_, [this](const char* data, std::size_t size) { AddOutput(data, size); }, kFinalRead);
  CloseFd(fd_);
  return true;
}

bool ClientProcess::Poll(double seconds) {
  const double deadline = Now() + (std::isfinite(seconds) ? std::max(seconds, 0.0) : 0.0);
  while (!Reap(false)) {
    double left = std::min(deadline - Now(), kSlice);
    if (left <= 0) {
      Read();
      return false;
    }
    if (fd_ >= 0) {
      pollfd slot = {fd_, POLLIN, 0};
      if (poll(&slot, 1, std::max(1, int(std::lround(left * 1000)))) > 0) Read();
    } else {
      std::this_thread::sleep_for(std::chrono::duration<double>(left));
    }
  }
  return true;
}

bool ClientProcess::GroupRunning() {
  if (group_ > 0 && !ProcessGroupRunning(group_)) group_ = -1;  // never signalled again
  return group_ > 0;
}

bool ClientProcess::Stop(int first_signal, double grace) {
  if (!running() && !GroupRunning()) return false;
  const double deadline = Now() + (std::isfinite(grace) ? std::max(grace, 0.0) : 0.0);
  kill(-group_, first_signal);
  if (running()) Poll(deadline - Now());
  bool needed = false;
  if (running()) {
    kill(-group_, SIGKILL);
    kill(pid_, SIGKILL);
    Reap(true);
    needed = signal() == SIGKILL;  // else it ended on its own just then
    killed_ = needed;
  }
  while (GroupRunning() && Now() < deadline) {
    std::this_thread::sleep_for(
        std::chrono::duration<double>(std::min(kSlice * 5, deadline - Now())));
  }
  if (group_ > 0) kill(-group_, SIGKILL);
  return needed;
}

int ClientProcess::exit_code() const {
  return ended_ && status_known_ && WIFEXITED(status_) ? WEXITSTATUS(status_) : -1;
}

int ClientProcess::signal() const {
  return ended_ && status_known_ && WIFSIGNALED(status_) ? WTERMSIG(status_) : 0;
}

std::string ClientProcess::HowItEnded() const {
  if (!ended_) return "is still running";
  if (!status_known_) return "ended (its exit status is unknown: another part of plumb reaped it)";
  if (killed_ && signal() == SIGKILL) return "killed by SIGKILL after the grace period";
  if (signal() != 0) return "ended on " + SignalName(signal());
  return "exited with status " + std::to_string(exit_code());
}

std::vector<std::string> ClientProcess::Tail() const { return tail_.Last(); }

double ClientProcess::wall() const { return (ended_ ? ended_at_ : Now()) - started_; }

}  // namespace plumb::internal
