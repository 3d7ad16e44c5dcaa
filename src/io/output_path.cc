#include "io/output_path.h"

#include <filesystem>
#include <system_error>

#include "plumb/error.h"

namespace plumb::internal {

namespace fs = std::filesystem;

namespace {

// A file that an output replaces or writes into: a regular file or a folder (after links).
bool Replaceable(const std::string& path) {
  std::error_code ec;
  fs::file_status status = fs::status(path, ec);
  return !ec && (fs::is_regular_file(status) || fs::is_directory(status));
}

// The path made absolute, with "." and ".." resolved by its text alone (links left as they are).
fs::path Spelled(const std::string& path) {
  std::error_code ec;
  fs::path absolute = fs::absolute(path, ec);
  return (ec ? fs::path(path) : absolute).lexically_normal();
}

}  // namespace

bool SameFile(const std::string& a, const std::string& b) {
  if (a.empty() || b.empty()) return false;
  std::error_code ec;
  bool same = fs::equivalent(a, b, ec);
  return !ec && same;
}

void RefuseOutputsOntoInputs(const std::vector<NamedPath>& outputs,
                             const std::vector<NamedPath>& inputs) {
  for (const NamedPath& out : outputs) {
    if (out.path.empty() || !Replaceable(out.path)) continue;
    for (const NamedPath& in : inputs) {
      if (!SameFile(out.path, in.path)) continue;
      std::string how =
          Spelled(out.path) == Spelled(in.path) ? "" : " (under another name)";
      throw ArgumentError(out.name, Quoted(out.path),
                          in.name + " " + Quoted(in.path) + " is the same file" + how +
                              ", and the output would destroy its input; write it elsewhere.");
    }
  }
}

}  // namespace plumb::internal
