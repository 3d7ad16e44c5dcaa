// Scenario files against the humanoid: the first byte picks TOML (even) or JSON (odd), the
// rest is the file.

#include "fuzz_common.h"
#include "plumb/scenario.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace plumb;
  if (size == 0) return 0;
  const char* suffix = (data[0] & 1) ? ".json" : ".toml";
  std::string file = fuzz::ScratchFile(data + 1, size - 1, suffix);
  fuzz::Expect([&] { LoadScenario(fuzz::Humanoid(), file); });
  return 0;
}
