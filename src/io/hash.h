// Fingerprints of files and compiled models (FNV-1a, 64 bits, as 16 hex digits): what the
// results store records so that a resumed or merged run can tell it is the same model. Not
// for security.
//
// Example:
//   std::string h = plumb::HashModel(model);  // "3f0c..." (16 hex digits)
//
// Thread-safety: HashFile reads its file and HashModel only reads the model; neither keeps state,
// so both may be called from several threads at once, also on one Model.

#ifndef PLUMB_SRC_IO_HASH_H_
#define PLUMB_SRC_IO_HASH_H_

#include <string>

#include "plumb/model.h"

namespace plumb::internal {

// Hash of a file's bytes. @throws IoError when it cannot be read.
std::string HashFile(const std::string& path);

// Hash of the compiled model as mj_saveModel writes it: changes when any included file
// changes, not when only comments or formatting do.
std::string HashModel(const Model& model);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_IO_HASH_H_
