#include "core/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "plumb/error.h"

namespace plumb::internal {
namespace {

constexpr std::size_t kMiB = std::size_t{1} << 20;

struct KindInfo {
  const char* name;
  std::size_t cap;
  const char* give;  // what to give instead of something that is not a file
};

KindInfo Info(InputKind kind) {
  switch (kind) {
    case InputKind::kModel:
      return {"model file", 256 * kMiB, "the MJCF model (.xml) or a compiled model (.mjb)"};
    case InputKind::kBridgeConfig:
      return {"bridge config", 1 * kMiB, "the bridge configuration's .toml file"};
    case InputKind::kGamepadScript:
      return {"gamepad script", 4 * kMiB, "a text file of timed events (t = 2.0: start)"};
    case InputKind::kScenario:
      return {"scenario", 64 * kMiB, "the scenario's .toml or .json file"};
    case InputKind::kAcceptList:
      return {"accept list", 4 * kMiB, "the accept list's .toml file"};
    case InputKind::kPoseFile:
      return {"pose file", 1 * kMiB, "a text file of qpos numbers or NAME=VALUE lines"};
    case InputKind::kRobotLog:
      return {"robot log", 1024 * kMiB, "the log's .csv file"};
    case InputKind::kColumnMap:
      return {"column map", 1 * kMiB, "the column map's .toml file"};
    case InputKind::kSnapshot:
      return {"snapshot", 64 * kMiB, "the JSON file plumb snapshot wrote"};
  }
  return {"input file", 1 * kMiB, "a file"};
}

// "a bridge config", "an accept list".
std::string Article(const char* name) {
  return (std::strchr("aeiou", name[0]) != nullptr ? "an " : "a ") + std::string(name);
}

std::string Bytes(std::size_t n) {
  if (n >= kMiB && n % kMiB == 0)
    return std::to_string(n) + " (" + std::to_string(n / kMiB) + " MiB)";
  return std::to_string(n);
}

class Descriptor {
 public:
  explicit Descriptor(int fd) : fd_(fd) {}
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

}  // namespace

const char* FileTypeName(mode_t mode) {
  if (S_ISREG(mode)) return "a regular file";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

const char* InputKindName(InputKind kind) { return Info(kind).name; }

std::size_t InputCap(InputKind kind) { return Info(kind).cap; }

std::string ReadInputFile(const std::string& path, InputKind kind) {
  const KindInfo info = Info(kind);
  auto not_a_file = [&](mode_t mode) {
    return IoError("'" + path + "' is " + FileTypeName(mode) + ", not a file: plumb reads " +
                   Article(info.name) + " only from a regular file. Give " + info.give +
                   (S_ISFIFO(mode) ? "; write what the pipe carries to a file first." : "."));
  };
  auto unreadable = [&](int error) {
    return IoError(std::string("cannot read the ") + info.name + " '" + path + "' (" +
                   std::strerror(error) + ").");
  };
  // non-blocking: opening a FIFO waits for a writer otherwise, and no signal would end it
  Descriptor fd(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC));
  if (fd.get() < 0) {
    int error = errno;
    struct stat st;
    // a socket cannot be opened at all (ENXIO): say what it is
    if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) throw not_a_file(st.st_mode);
    if (error == ENOENT) {
      throw IoError(std::string("no ") + info.name + " '" + path + "' (" + std::strerror(error) +
                    "): check the path (a relative one starts at the current directory).");
    }
    throw unreadable(error);
  }
  struct stat st;
  if (::fstat(fd.get(), &st) != 0) throw unreadable(errno);
  if (!S_ISREG(st.st_mode)) throw not_a_file(st.st_mode);
  auto too_big = [&](std::size_t size, bool or_more) {
    return IoError(
        "'" + path + "' is " + std::to_string(size) + " bytes" + (or_more ? " (or more)" : "") +
        "; " + Article(info.name) + " may be at most " + Bytes(info.cap) +
        ". Check that it is the right file" +
        (kind == InputKind::kRobotLog ? ", or cut the log to the stretch you need." : "."));
  };
  if (st.st_size > 0 && static_cast<std::size_t>(st.st_size) > info.cap) {
    throw too_big(static_cast<std::size_t>(st.st_size), false);
  }
  // at most cap + 1 bytes: a file that grows while it is read (or says size 0, as /proc does)
  // is refused once it passes the cap
  std::string text;
  text.resize(st.st_size > 0 ? static_cast<std::size_t>(st.st_size) + 1 : 64 * 1024);
  std::size_t used = 0;
  for (;;) {
    if (used == text.size()) text.resize(std::min(text.size() * 2, info.cap + 1));
    ssize_t n = ::read(fd.get(), &text[used], text.size() - used);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw unreadable(errno);
    if (n == 0) break;
    used += static_cast<std::size_t>(n);
    if (used > info.cap) throw too_big(used, true);
  }
  text.resize(used);
  return text;
}

}  // namespace plumb::internal
