#include "core/child_process.h"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

extern char** environ;

namespace plumb::internal {
namespace {

std::vector<char*> CStrings(const std::vector<std::string>& strings) {
  std::vector<char*> pointers;
  for (const std::string& s : strings) pointers.push_back(const_cast<char*>(s.c_str()));
  pointers.push_back(nullptr);
  return pointers;
}

}  // namespace

std::vector<std::string> ChildEnvironment(
    const std::vector<std::pair<std::string, std::string>>& extra) {
  std::vector<std::string> env;
  for (char** e = environ; e != nullptr && *e != nullptr; ++e) {
    std::string entry = *e;
    std::string name = entry.substr(0, entry.find('='));
    bool replaced =
        std::any_of(extra.begin(), extra.end(), [&](const auto& kv) { return kv.first == name; });
    if (!replaced) env.push_back(std::move(entry));
  }
  for (const auto& [name, value] : extra) env.push_back(name + "=" + value);
  return env;
}

int AboveStdio(int fd) {
  if (fd > 2) return fd;
  int moved = fcntl(fd, F_DUPFD_CLOEXEC, 3);
  int saved = errno;
  close(fd);
  errno = saved;
  return moved;
}

void CloseFd(int& fd) {
  if (fd >= 0) close(fd);
  fd = -1;
}

int SpawnChild(const std::string& program, const std::vector<std::string>& argv,
               const std::vector<std::string>& env, const int child_fds[3],
               const std::string& directory, pid_t* pid) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  for (int stream = 0; stream < 3; ++stream) {
    posix_spawn_file_actions_adddup2(&actions, child_fds[stream], stream);
  }
  if (!directory.empty()) posix_spawn_file_actions_addchdir_np(&actions, directory.c_str());
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t none, defaults;
  sigemptyset(&none);
  sigemptyset(&defaults);
  for (int sig : {SIGPIPE, SIGINT, SIGTERM}) sigaddset(&defaults, sig);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setsigdefault(&attr, &defaults);
  posix_spawnattr_setpgroup(&attr, 0);
  posix_spawnattr_setflags(&attr,
                           POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  std::vector<char*> args = CStrings(argv);
  std::vector<char*> envp = CStrings(env);
  *pid = -1;
  int error = posix_spawnp(pid, program.c_str(), &actions, &attr, args.data(), envp.data());
  posix_spawnattr_destroy(&attr);
  posix_spawn_file_actions_destroy(&actions);
  return error;
}

bool ReadAvailable(int& fd, const std::function<void(const char*, std::size_t)>& take,
                   std::size_t most) {
  char buffer[1 << 16];
  bool any = false;
  std::size_t read_so_far = 0;
  while (fd >= 0 && read_so_far < most) {
    ssize_t got = read(fd, buffer, std::min(sizeof buffer, most - read_so_far));
    if (got < 0 && errno == EINTR) continue;
    if (got < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
    if (got <= 0) {
      CloseFd(fd);  // its end, or an error that reading again will not mend
      break;
    }
    any = true;
    read_so_far += std::size_t(got);
    take(buffer, std::size_t(got));
  }
  return any;
}

bool ProcessGroupRunning(pid_t group) {
  if (group <= 0) return false;
  if (kill(-group, 0) != 0 && errno == ESRCH) return false;
  DIR* proc = opendir("/proc");
  if (proc == nullptr) return true;  // the group has a member: it may run
  bool running = false;
  while (const dirent* entry = readdir(proc)) {
    if (entry->d_name[0] < '1' || entry->d_name[0] > '9') continue;
    char text[512];
    std::string path = std::string("/proc/") + entry->d_name + "/stat";
    int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) continue;
    ssize_t got = read(fd, text, sizeof text - 1);
    close(fd);
    if (got <= 0) continue;
    text[got] = '\0';
    const char* close_paren = std::strrchr(text, ')');  // the name may hold anything
    char state = 0;
    long process_group = 0;
    if (close_paren != nullptr &&
        std::sscanf(close_paren + 1, " %c %*d %ld", &state, &process_group) == 2 &&
        process_group == group && state != 'Z' && state != 'X') {
      running = true;
      break;
    }
  }
  closedir(proc);
  return running;
}

std::string WaitStatusText(int status, bool plumb_killed) {
  if (WIFEXITED(status)) return "it exited with status " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) {
    int sig = WTERMSIG(status);
    if (plumb_killed && sig == SIGKILL) return "plumb killed it";
    const char* name = strsignal(sig);
    return "it was killed by signal " + std::to_string(sig) +
           (name ? std::string(" (") + name + ")" : "");
  }
  return "it ended";
}

std::string SignalName(int signal) {
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 32))
  if (const char* abbreviation = sigabbrev_np(signal)) return std::string("SIG") + abbreviation;
#else
  static const struct {
    int number;
    const char* name;
  } kNames[] = {{SIGHUP, "SIGHUP"},   {SIGINT, "SIGINT"},   {SIGQUIT, "SIGQUIT"},
                {SIGILL, "SIGILL"},   {SIGTRAP, "SIGTRAP"}, {SIGABRT, "SIGABRT"},
                {SIGBUS, "SIGBUS"},   {SIGFPE, "SIGFPE"},   {SIGKILL, "SIGKILL"},
                {SIGUSR1, "SIGUSR1"}, {SIGSEGV, "SIGSEGV"}, {SIGUSR2, "SIGUSR2"},
                {SIGPIPE, "SIGPIPE"}, {SIGALRM, "SIGALRM"}, {SIGTERM, "SIGTERM"}};
  for (const auto& entry : kNames) {
    if (entry.number == signal) return entry.name;
  }
#endif
  return "signal " + std::to_string(signal);
}

void LineTail::Add(const char* data, std::size_t size) {
  for (std::size_t i = 0; i < size; ++i) {
    if (data[i] != '\n') {
      if (partial_.size() < line_chars_) partial_ += data[i];
      continue;
    }
    lines_.push_back(std::move(partial_));
    partial_.clear();
    if (lines_.size() > most_lines_) lines_.pop_front();
  }
}

std::vector<std::string> LineTail::Last() const {
  std::vector<std::string> last(lines_.begin(), lines_.end());
  if (!partial_.empty()) last.push_back(partial_);
  if (last.size() > most_lines_) last.erase(last.begin(), last.end() - long(most_lines_));
  return last;
}

}  // namespace plumb::internal
