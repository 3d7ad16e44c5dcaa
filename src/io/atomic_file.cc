#include "io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>

#include "io/temp_file.h"
#include "plumb/error.h"

namespace plumb::internal {

namespace fs = std::filesystem;

namespace {

// The maximum number of symbolic links followed, as the kernel's ELOOP limit.
constexpr int kMaxLinks = 40;

// Links under /proc and /dev/fd name an open file (a pipe, a terminal, a deleted
// file), not a path where a new file could be renamed into place.
bool NamesAnOpenFile(const fs::path& link) {
  std::string s = link.lexically_normal().string();
  return s.rfind("/proc/", 0) == 0 || s.rfind("/dev/fd/", 0) == 0;
}

// Follows the symbolic links from `path` to the file they finally name, which need not
// exist yet. Returns "" when the chain passes through a /proc or /dev/fd link (the
// output is then written directly). @throws IoError when the chain does not end.
std::string FinalTarget(const std::string& path) {
  fs::path p = path;
  for (int hops = 0; hops < kMaxLinks; ++hops) {
    struct stat st;
    if (lstat(p.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return p.string();
    if (NamesAnOpenFile(p)) return "";
    std::error_code ec;
    fs::path next = fs::read_symlink(p, ec);
    if (ec)
      throw IoError("cannot write '" + path + "': cannot read the link '" + p.string() +
                    "': " + ec.message());
    p = next.is_absolute() ? next : p.parent_path() / next;
  }
  throw IoError("cannot write '" + path + "': more than " + std::to_string(kMaxLinks) +
                " symbolic links (a loop?); give the file's real path with -o.");
}

}  // namespace

// A stream over a descriptor that remembers why the first write failed: stdio's own error
// flag forgets errno, and "No space left on device" is what the user needs to read.
struct AtomicFile::Channel {
  int fd = -1;
  int error = 0;

  static ssize_t Write(void* cookie, const char* data, size_t size) {
    auto* c = static_cast<Channel*>(cookie);
    size_t done = 0;
    while (done < size) {
      ssize_t n = ::write(c->fd, data + done, size - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        if (c->error == 0) c->error = n < 0 ? errno : EIO;
        break;
      }
      done += static_cast<size_t>(n);
    }
    return static_cast<ssize_t>(done);
  }
  static int Close(void* cookie) { return ::close(static_cast<Channel*>(cookie)->fd); }

  // Wraps `fd` (owned from now on) in a fully buffered stream. @throws IoError.
  static std::FILE* Open(Channel* c, int fd, const std::string& path) {
    c->fd = fd;
    std::FILE* file = fopencookie(c, "w", {nullptr, &Write, nullptr, &Close});
    if (!file) {
      ::close(fd);
      throw IoError("cannot write '" + path + "': " + std::strerror(errno));
    }
    std::setvbuf(file, nullptr, _IOFBF, 1 << 16);
    return file;
  }
};

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  // "-" is standard output
  if (path_ == "-") {
    file_ = stdout;
    owns_file_ = false;
    return;
  }
  // an existing file that is not a regular file is written directly: a device node or a
  // FIFO must never be replaced by a regular file
  struct stat st;
  bool exists = ::stat(path_.c_str(), &st) == 0;
  if (exists && S_ISDIR(st.st_mode)) {
    throw IoError("cannot write '" + path_ + "': it is a directory; give a file name.");
  }
  if (exists && S_ISSOCK(st.st_mode)) {
    throw IoError("cannot write '" + path_ +
                  "': it is a socket; give a file, a FIFO or '-' (standard output) with -o.");
  }
  std::string target = exists && !S_ISREG(st.st_mode) ? "" : FinalTarget(path_);
  if (target.empty()) {
    int fd = ::open(path_.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
    if (fd < 0) throw IoError("cannot write '" + path_ + "': " + std::strerror(errno));
    channel_ = std::make_unique<Channel>();
    file_ = Channel::Open(channel_.get(), fd, path_);
    return;
  }
  // a regular file (or none yet), perhaps behind links: written next to the link's target,
  // after removing what writers of it that were killed left there
  target_ = target;
  RemoveStaleTemporaries(target_);
  int fd = CreateLockedTemporary(target_, "", &temp_path_);
  // the lock lives with this second descriptor until the rename (the stream's is closed first)
  lock_fd_ = fcntl(fd, F_DUPFD_CLOEXEC, 0);
  // an existing file keeps its permissions; a new one gets those of an ordinary new file
  // (mkstemp uses 0600)
  mode_t mask = umask(0);
  umask(mask);
  fchmod(fd, exists ? (st.st_mode & 07777) : (0666 & ~mask));
  channel_ = std::make_unique<Channel>();
  try {
    file_ = Channel::Open(channel_.get(), fd, path_);
  } catch (const IoError&) {
    std::remove(temp_path_.c_str());
    throw;
  }
}

AtomicFile::~AtomicFile() {
  if (file_ && owns_file_) std::fclose(file_);
  if (!committed_ && !temp_path_.empty()) std::remove(temp_path_.c_str());
  if (lock_fd_ >= 0) ::close(lock_fd_);
}

void AtomicFile::Commit() { Finish(nullptr); }

int AtomicFile::CommitForAppending() {
  int kept = -1;
  Finish(&kept);
  return kept;
}

void AtomicFile::Finish(int* kept) {
  errno = 0;
  bool ok =
      std::fflush(file_) == 0 && !std::ferror(file_) && (direct() || fsync(channel_->fd) == 0);
  int error = channel_ && channel_->error != 0 ? channel_->error : errno != 0 ? errno : EIO;
  if (kept != nullptr && ok) {
    // a descriptor of the same open file, which outlives the stream
    *kept = fcntl(channel_ ? channel_->fd : fileno(file_), F_DUPFD_CLOEXEC, 0);
    if (*kept < 0) {
      ok = false;
      error = errno;
    } else {
      fcntl(*kept, F_SETFL, fcntl(*kept, F_GETFL) | O_APPEND);
    }
  }
  if (owns_file_) ok = (std::fclose(file_) == 0) && ok;
  file_ = nullptr;
  auto fail = [&](const std::string& message) {
    if (kept != nullptr && *kept >= 0) ::close(*kept);
    throw IoError(message);
  };
  if (direct()) {
    if (!ok) {
      std::string name = path_ == "-" ? "standard output" : "'" + path_ + "'";
      fail("cannot write " + name + ": " + std::strerror(error) + "; the output is incomplete.");
    }
    committed_ = true;
    return;
  }
  if (!ok) {
    fail("cannot write '" + path_ + "': " + std::strerror(error) +
         "; nothing was written under that name.");
  }
  if (std::rename(temp_path_.c_str(), target_.c_str()) != 0) {
    fail("cannot write '" + path_ + "': " + std::strerror(errno));
  }
  committed_ = true;
  ::close(lock_fd_);
  lock_fd_ = -1;
}

}  // namespace plumb::internal
