#include "core/file_kind.h"

#include <algorithm>
#include <cstring>

#include "plumb/error.h"
#include "plumb/model.h"

namespace plumb::internal {

FileKind SniffFileKind(const std::string& text) {
  // a NUL byte near the start marks a binary file, as git decides
  std::size_t head = std::min<std::size_t>(text.size(), 8000);
  if (std::memchr(text.data(), '\0', head) != nullptr) return FileKind::kBinary;
  std::size_t start = text.find_first_not_of(" \t\r\n\f\v");
  if (start == std::string::npos) return FileKind::kEmpty;
  // a UTF-8 byte order mark is text
  if (text.compare(start, 3, "\xEF\xBB\xBF") == 0) start += 3;
  char first = start < text.size() ? text[start] : '\0';
  if (first == '{' || first == '[') {
    std::size_t key = text.find("\"plumb_snapshot\"");
    return key != std::string::npos && key < 4096 ? FileKind::kSnapshot : FileKind::kJson;
  }
  if (first == '<') {
    // skip the declaration and comments: the root element decides
    std::size_t root = text.find("<mujoco");
    std::size_t other = start;
    while (other != std::string::npos &&
           (text.compare(other, 2, "<?") == 0 || text.compare(other, 4, "<!--") == 0)) {
      std::size_t end =
          text.compare(other, 2, "<?") == 0 ? text.find("?>", other) : text.find("-->", other);
      other = end == std::string::npos ? end : text.find('<', end);
    }
    return root != std::string::npos && root == other ? FileKind::kMjcf : FileKind::kXml;
  }
  return FileKind::kText;
}

std::string FileKindName(FileKind kind) {
  switch (kind) {
    case FileKind::kEmpty:
      return "empty";
    case FileKind::kBinary:
      return "a binary file";
    case FileKind::kSnapshot:
      return "a plumb snapshot (JSON)";
    case FileKind::kJson:
      return "a JSON file";
    case FileKind::kMjcf:
      return "an MJCF model (XML)";
    case FileKind::kXml:
      return "an XML file";
    case FileKind::kText:
      return "a text file";
  }
  return "a file";
}

void CheckModelText(const std::string& path, const std::string& text) {
  FileKind kind = SniffFileKind(text);
  std::string file = "model file '" + path + "'";
  switch (kind) {
    case FileKind::kEmpty:
      throw LoadError(file + " is empty (" + std::to_string(text.size()) +
                          " bytes): an MJCF model is XML starting with <mujoco>. Was it "
                          "truncated, or not written yet?",
                      "");
    case FileKind::kBinary:
      throw LoadError(file + " is a binary file, but neither an MJCF model (XML) nor a compiled " +
                          "model (.mjb) this MuJoCo (" + MujocoVersion() +
                          ") loads: give the .xml file, or a .mjb written by this version.",
                      "");
    case FileKind::kSnapshot:
      throw LoadError(file + " is a plumb snapshot (JSON), not a model. Give the MJCF model " +
                          "instead; to compare a model with this snapshot, run plumb diff " + path +
                          " MODEL.xml (the snapshot first).",
                      "");
    case FileKind::kJson:
      throw LoadError(file + " is a JSON file, not an MJCF model (XML starting with <mujoco>).",
                      "");
    default:
      return;
  }
}

}  // namespace plumb::internal
