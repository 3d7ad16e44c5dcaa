#include "batch/store_path.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "core/input_file.h"
#include "plumb/error.h"

namespace plumb::internal {
namespace {

namespace fs = std::filesystem;

// Why `what` cannot be written (errno `error` of access(W_OK)), with what to do.
std::string Unwritable(const std::string& what, int error) {
  if (error == EROFS) {
    return what + " is on a read-only file system; give a store path on a writable one";
  }
  return fmt::format("{} is not writable ({}); give a store path in a folder you can write", what,
                     std::strerror(error));
}

}  // namespace

void CheckStorePath(const std::string& path, bool write) {
  std::string store = "results store '" + path + "'";
  struct stat st {};
  bool exists = ::stat(path.c_str(), &st) == 0;
  if (exists && !S_ISREG(st.st_mode)) {
    throw IoError(
        fmt::format("{} is not a regular file ({}): give the path of a store file, "
                    "new or one plumb wrote, e.g. results.db.",
                    store, FileTypeName(st.st_mode)));
  }
  if (!exists && errno != ENOENT && errno != ENOTDIR) {  // a missing folder is told below
    throw IoError(fmt::format("{} cannot be reached ({}); give another store path.", store,
                              std::strerror(errno)));
  }
  if (!write) {
    if (!exists) throw IoError(store + " does not exist; give the path of a store plumb wrote.");
    return;
  }
  fs::path folder = fs::path(path).parent_path();
  std::string shown = folder.empty() ? std::string(".") : folder.string();
  struct stat dir {};
  if (::stat(shown.c_str(), &dir) != 0) {
    throw IoError(
        fmt::format("{}: the folder '{}' does not exist ({}); make it first (mkdir -p "
                    "'{}') or give a store path in an existing folder.",
                    store, shown, std::strerror(errno), shown));
  }
  if (!S_ISDIR(dir.st_mode)) {
    throw IoError(fmt::format("{}: '{}' is not a folder ({}); give a store path in a folder.",
                              store, shown, FileTypeName(dir.st_mode)));
  }
  if (exists && ::access(path.c_str(), W_OK) != 0) throw IoError(Unwritable(store, errno) + ".");
  if (!exists) {
    // made here, empty (an empty file is a new store to SQLite), so that what creating it meets
    // is told: a folder like /proc takes no new file although root may write it. Never removed
    // again: another plumb may have opened it meanwhile.
    int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0 && errno != EEXIST) {
      throw IoError(Unwritable(fmt::format("{}: its folder '{}'", store, shown), errno) + ".");
    }
    if (fd >= 0) ::close(fd);
  }
  if (::access(shown.c_str(), W_OK) != 0) {
    throw IoError(Unwritable(fmt::format("{}: its folder '{}'", store, shown), errno) +
                  " (SQLite writes the store's journal, -wal and -shm files, beside it).");
  }
}

}  // namespace plumb::internal
