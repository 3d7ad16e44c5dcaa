#include "plumb/error.h"

#include <string>

namespace plumb {
namespace {

// __FILE__ from the project's root: the build passes absolute paths, and a report names
// "src/core/worker_pool.cc:50", the same on every machine.
std::string FromProjectRoot(const char* file) {
  std::string path = file;
  for (const char* root : {"/src/", "/include/", "/apps/", "/tests/"}) {
    std::size_t at = path.rfind(root);
    if (at != std::string::npos) return path.substr(at + 1);
  }
  return path;
}

}  // namespace

ArgumentError::ArgumentError(std::string argument, std::string value, std::string problem)
    : ValueError(argument + (value.empty() ? "" : " " + value) + ": " + problem),
      argument_(std::move(argument)),
      value_(std::move(value)),
      problem_(std::move(problem)) {}

std::string Quoted(const std::string& text) { return "'" + text + "'"; }

InternalError::InternalError(const char* file, int line, const std::string& condition)
    : std::logic_error("plumb internal error at " + FromProjectRoot(file) + ":" +
                       std::to_string(line) + ": '" + condition +
                       "' does not hold (a bug in plumb: please report it)"),
      file_(FromProjectRoot(file)),
      line_(line) {}

}  // namespace plumb
