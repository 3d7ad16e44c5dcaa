// What a file given as a model or a snapshot is, from its first bytes, so that a wrong
// file is named for what it is (empty, binary, a snapshot, an MJCF model) instead of
// passing MuJoCo's XML parser error through.
//
// Thread-safety: the functions are pure (no state; CheckModelText is given the text and reads no
// file): call them from any thread, at once.

#ifndef PLUMB_SRC_CORE_FILE_KIND_H_
#define PLUMB_SRC_CORE_FILE_KIND_H_

#include <string>

namespace plumb::internal {

enum class FileKind {
  kEmpty,     // nothing but blanks
  kBinary,    // a NUL byte in the first 8000 bytes (as git decides)
  kSnapshot,  // JSON written by plumb snapshot
  kJson,      // any other JSON
  kMjcf,      // XML whose root element is <mujoco>
  kXml,       // other XML (URDF, which MuJoCo also loads, ...)
  kText,      // anything else
};

// The kind of `text`, the contents of a file.
FileKind SniffFileKind(const std::string& text);

// The kind in words for messages: "empty", "a binary file", "a plumb snapshot (JSON)",
// "a JSON file", "an MJCF model (XML)", "an XML file", "a text file".
std::string FileKindName(FileKind kind);

// Refuses a file that cannot be an XML model before MuJoCo's parser sees it: empty,
// binary or JSON (a plumb snapshot in particular). `text` is the contents of `path`.
// @throws LoadError saying what the file is and what to give or run instead.
void CheckModelText(const std::string& path, const std::string& text);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_CORE_FILE_KIND_H_
