// Hidden temporary files beside an output (temp_file.h).

#include "io/temp_file.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <vector>

#include "plumb/error.h"

namespace plumb::internal {

namespace fs = std::filesystem;

namespace {

// The characters mkstemp puts in place of XXXXXX.
constexpr std::size_t kRandomPart = 6;

fs::path FolderOf(const std::string& target) {
  fs::path dir = fs::path(target).parent_path();
  return dir.empty() ? fs::path(".") : dir;
}

std::string PrefixOf(const std::string& target) {
  return "." + fs::path(target).filename().string() + ".tmp-";
}

// True for a name CreateLockedTemporary makes for the prefix: six random characters, then
// nothing or an extension (".mp4", ".log").
bool IsTemporaryName(const std::string& name, const std::string& prefix) {
  if (name.size() < prefix.size() + kRandomPart || name.compare(0, prefix.size(), prefix) != 0) {
    return false;
  }
  for (std::size_t i = prefix.size(); i < prefix.size() + kRandomPart; ++i) {
    if (!std::isalnum(static_cast<unsigned char>(name[i]))) return false;
  }
  std::string rest = name.substr(prefix.size() + kRandomPart);
  if (rest.empty()) return true;
  if (rest[0] != '.' || rest.size() == 1) return false;
  for (std::size_t i = 1; i < rest.size(); ++i) {
    if (!std::isalnum(static_cast<unsigned char>(rest[i])) && rest[i] != '.') return false;
  }
  return true;
}

// True when `fd` is still the file named `path` (nobody removed or replaced it meanwhile).
bool SameFile(int fd, const std::string& path) {
  struct stat by_fd, by_name;
  return fstat(fd, &by_fd) == 0 && lstat(path.c_str(), &by_name) == 0 &&
         by_fd.st_dev == by_name.st_dev && by_fd.st_ino == by_name.st_ino;
}

}  // namespace

int RemoveStaleTemporaries(const std::string& target) {
  fs::path dir = FolderOf(target);
  std::string prefix = PrefixOf(target);
  std::vector<std::string> candidates;
  if (DIR* d = opendir(dir.c_str())) {
    while (dirent* e = readdir(d)) {
      if (IsTemporaryName(e->d_name, prefix)) candidates.push_back((dir / e->d_name).string());
    }
    closedir(d);
  }
  int removed = 0;
  for (const std::string& path : candidates) {
    int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
    if (fd < 0) continue;
    // a free lock means its writer has died; holding it, the file is ours to remove
    struct stat st;
    if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && flock(fd, LOCK_EX | LOCK_NB) == 0 &&
        SameFile(fd, path) && ::unlink(path.c_str()) == 0) {
      ++removed;
    }
    ::close(fd);
  }
  return removed;
}

int CreateLockedTemporary(const std::string& target, const std::string& suffix, std::string* path) {
  fs::path dir = FolderOf(target);
  std::string pattern = (dir / (PrefixOf(target) + "XXXXXX" + suffix)).string();
  for (;;) {
    std::vector<char> name(pattern.begin(), pattern.end());
    name.push_back('\0');
    int fd = mkostemps(name.data(), static_cast<int>(suffix.size()), O_CLOEXEC);
    if (fd < 0) {
      throw IoError("cannot write '" + target + "': " + std::strerror(errno) + " (folder '" +
                    dir.string() + "'); check that it exists and is writable, or write elsewhere.");
    }
    // another writer's clean-up may have taken the file between its creation and this lock
    // (it removes only files it could lock): then make another
    int locked;
    do {
      locked = flock(fd, LOCK_EX);
    } while (locked != 0 && errno == EINTR);
    if (locked != 0 || SameFile(fd, name.data())) {
      // a file system without locks (flock fails) keeps its temporaries: nothing can tell a
      // dead writer's from a live one's there, so none is ever removed
      *path = name.data();
      return fd;
    }
    ::close(fd);
  }
}

TempFolder::TempFolder(const std::string& prefix, const std::string& purpose) {
  std::error_code ec;
  fs::path base = fs::temp_directory_path(ec);
  if (ec) base = "/tmp";
  std::string pattern = (base / (prefix + "-XXXXXX")).string();
  if (mkdtemp(pattern.data()) == nullptr) {
    throw IoError("cannot make a temporary folder in '" + base.string() + "' for " + purpose +
                  " (" + std::strerror(errno) + "): set TMPDIR to a writable folder");
  }
  path_ = pattern;
}

TempFolder::~TempFolder() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

}  // namespace plumb::internal
