// Output files that appear complete or not at all (a command's -o).
//
// Thread-safety: use an AtomicFile from one thread at a time; different ones may be written at
// once from different threads, even for one target (each has its own locked temporary; the last
// Commit wins). Opening a file that is not written directly reads the umask by setting it to 0
// and back, so a file another thread creates at that instant may miss the umask.

#ifndef PLUMB_SRC_IO_ATOMIC_FILE_H_
#define PLUMB_SRC_IO_ATOMIC_FILE_H_

#include <cstdio>
#include <memory>
#include <string>

namespace plumb::internal {

// The output file of a command's -o: a file that appears under its final name only
// when complete. It is written to a hidden temporary file in the same directory and
// renamed over the target by Commit(). If Commit() is never called (an error, an
// exception, an interrupt), the destructor removes the temporary file and nothing
// appears under the target. A SIGKILL can leave the hidden temporary
// (".<name>.tmp-XXXXXX") behind, never a half-written target; the next AtomicFile of the
// same target removes the temporaries whose writers have died (each writer holds a lock on
// its own while it lives). What `path` names decides how it is written:
//   - "-": standard output (written directly, flushed by Commit(), never closed);
//   - a symbolic link (a chain of them, or one whose target does not exist yet): the
//     link is followed and the temporary file is renamed next to its final target, so
//     the link stays a link and now points to the new contents;
//   - an existing file that is not a regular file (a FIFO, a character or block device,
//     a terminal, a /proc or /dev/fd link such as /dev/stdout): opened and written
//     directly, with no temporary file and no rename, so a device node or FIFO is never
//     replaced by a regular file. A socket cannot be opened and is refused (IoError).
// An existing regular target keeps its permission bits; a new one gets 0666 & ~umask.
class AtomicFile {
 public:
  // Opens the output as described above (opening a FIFO waits for its reader).
  // @throws IoError naming `path` when the directory does not exist or is not writable,
  // when `path` is a directory or a socket, or when a chain of links does not end.
  explicit AtomicFile(std::string path);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();

  // The stream to write to (fully buffered).
  std::FILE* stream() { return file_; }
  // The path as given ("-" for standard output).
  const std::string& path() const { return path_; }
  // True when the output is written directly (standard output, FIFO, device) rather
  // than through a temporary file and a rename.
  bool direct() const { return temp_path_.empty(); }

  // Flushes, syncs and renames into place (direct outputs are flushed only).
  // @throws IoError on any write failure (e.g. disk full, ENOSPC on /dev/full); nothing
  // appears under the target then, except what a direct output has already received.
  void Commit();
  // As Commit(), and returns a new descriptor (close-on-exec, O_APPEND) of the committed file,
  // which the caller owns and closes: a log that appears with its header whole and then grows.
  // @throws IoError as Commit() does.
  int CommitForAppending();

 private:
  void Finish(int* kept);  // Commit(); with `kept`, also a descriptor of the committed file
  std::string path_;       // as given
  std::string target_;     // where the rename lands (the end of a chain of links)
  std::string temp_path_;  // empty for direct outputs
  struct Channel;          // the descriptor under file_ and its first write error
  std::unique_ptr<Channel> channel_;
  std::FILE* file_ = nullptr;
  bool owns_file_ = true;  // false for standard output
  bool committed_ = false;
  int lock_fd_ = -1;  // holds the temporary's lock until the rename (temp_file.h)
};

}  // namespace plumb::internal

#endif  // PLUMB_SRC_IO_ATOMIC_FILE_H_
