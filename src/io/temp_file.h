// Hidden temporary files beside an output, which a killed writer cannot leave to pile up.
//
// A writer that makes its output appear whole (AtomicFile, VideoWriter) writes it first to a
// temporary file in the same folder, named ".<output name>.tmp-XXXXXX<suffix>", and renames it
// into place when done. A SIGKILL can leave that temporary behind. Each one is therefore
// locked (flock) by its writer for as long as the writer lives, and the next writer of the same
// output removes every such file whose lock is free: its writer has died (the kernel drops the
// locks of a killed process). A live writer's temporary is never touched, in this process or
// another.

#ifndef PLUMB_SRC_IO_TEMP_FILE_H_
#define PLUMB_SRC_IO_TEMP_FILE_H_

#include <string>

namespace plumb::internal {

// Removes the temporary files of `target` (as above) that no live writer holds, and returns how
// many it removed. Files it cannot open, lock or remove are left alone. Never throws.
int RemoveStaleTemporaries(const std::string& target);

// Creates a new temporary file for `target` (as above, mode 0600, close-on-exec) and locks it
// for as long as a descriptor of it stays open (including one a child process inherited).
// Returns the descriptor (the caller closes it); `*path` receives the file's name.
// @throws IoError naming `target` and the folder when the folder cannot be written.
int CreateLockedTemporary(const std::string& target, const std::string& suffix, std::string* path);

// A private folder (mode 0700) in the system's temporary folder ($TMPDIR, else /tmp), named
// "<prefix>-XXXXXX", removed with all it holds when the object goes.
class TempFolder {
 public:
  // @throws IoError naming the temporary folder and `purpose` ("the fitted model") when it
  // cannot be made.
  TempFolder(const std::string& prefix, const std::string& purpose);
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;
  ~TempFolder();

  const std::string& path() const { return path_; }
  // The path of `name` in the folder.
  std::string File(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

}  // namespace plumb::internal

#endif  // PLUMB_SRC_IO_TEMP_FILE_H_
