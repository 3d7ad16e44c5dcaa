// What the fuzz targets share: the models they parse against, a scratch file for parsers
// that read files, and the rule that a plumb::Error (a clear message for bad input) is the
// expected answer while anything else (a crash, another exception, a sanitizer report) is
// a finding.

#ifndef PLUMB_TESTS_FUZZ_FUZZ_COMMON_H_
#define PLUMB_TESTS_FUZZ_FUZZ_COMMON_H_

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

#include "plumb/error.h"
#include "plumb/model.h"

namespace plumb::fuzz {

inline const Model& Pendulum() {
  static const Model model = Model::Load(std::string(PLUMB_SOURCE_DIR) + "/models/pendulum.xml");
  return model;
}

// A model with free and ball joints, actuators, sensors and many names.
inline const Model& Humanoid() {
  static const Model model = Model::Load("/usr/share/mujoco/model/humanoid/humanoid.xml");
  return model;
}

inline std::string Text(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// Writes the input to this process's scratch file with `suffix` and returns its path.
inline std::string ScratchFile(const std::uint8_t* data, std::size_t size, const char* suffix) {
  std::string path = "/tmp/plumb-fuzz-" + std::to_string(getpid()) + suffix;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) __builtin_trap();
  if (size > 0 && std::fwrite(data, 1, size, f) != size) __builtin_trap();
  std::fclose(f);
  return path;
}

// Runs `f`; a plumb::Error is the expected answer to bad input.
template <typename F>
void Expect(F&& f) {
  try {
    f();
  } catch (const Error&) {
  }
}

}  // namespace plumb::fuzz

#endif  // PLUMB_TESTS_FUZZ_FUZZ_COMMON_H_
