#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "plumb/error.h"
#include "plumb/output.h"

namespace plumb {

namespace fs = std::filesystem;

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  fs::path target(path_);
  std::error_code ec;
  if (fs::is_directory(target, ec)) {
    throw IoError("cannot write '" + path_ + "': it is a directory; give a file name.");
  }
  fs::path dir = target.parent_path();
  if (dir.empty()) dir = ".";
  std::string pattern = (dir / ("." + target.filename().string() + ".tmp-XXXXXX")).string();
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  int fd = mkstemp(name.data());
  if (fd < 0) {
    throw IoError("cannot write '" + path_ + "': " + std::strerror(errno) + " (directory '" +
                  dir.string() + "'). Choose a writable location with -o.");
  }
  // keep the permissions an ordinary new file would get (mkstemp uses 0600)
  mode_t mask = umask(0);
  umask(mask);
  fchmod(fd, 0666 & ~mask);
  temp_path_ = name.data();
  file_ = fdopen(fd, "w");
  if (!file_) {
    ::close(fd);
    std::remove(temp_path_.c_str());
    throw IoError("cannot write '" + path_ + "': " + std::strerror(errno));
  }
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 16);
}

AtomicFile::~AtomicFile() {
  if (file_) std::fclose(file_);
  if (!committed_ && !temp_path_.empty()) std::remove(temp_path_.c_str());
}

void AtomicFile::Commit() {
  bool ok = std::fflush(file_) == 0 && !std::ferror(file_) && fsync(fileno(file_)) == 0;
  int error = errno;
  ok = (std::fclose(file_) == 0) && ok;
  file_ = nullptr;
  if (!ok) {
    throw IoError("cannot write '" + path_ + "': " + std::strerror(error) +
                  "; nothing was written under that name.");
  }
  if (std::rename(temp_path_.c_str(), path_.c_str()) != 0) {
    throw IoError("cannot write '" + path_ + "': " + std::strerror(errno));
  }
  committed_ = true;
}

}  // namespace plumb
