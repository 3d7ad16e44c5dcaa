// Where a results store may live: the checks a store's path passes before SQLite opens it, so
// that a path SQLite cannot use is refused with its real cause ("is on a read-only file system",
// "is not a regular file (a character device)", "the folder ... does not exist") instead of
// SQLite's "unable to open database file" or "disk I/O error".

#ifndef PLUMB_SRC_BATCH_STORE_PATH_H_
#define PLUMB_SRC_BATCH_STORE_PATH_H_

#include <string>

namespace plumb::internal {

// Checks that a results store can be opened at `path`: an existing path must be a regular file;
// to write (`write`), the file, or the folder that is to hold it, must be writable, and so must
// its folder (SQLite keeps its journal, STORE-wal and STORE-shm, beside the store). A new store
// is made here as an empty file (which SQLite takes for a new store).
// @throws IoError naming the store, the cause and what to do.
void CheckStorePath(const std::string& path, bool write);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_BATCH_STORE_PATH_H_
