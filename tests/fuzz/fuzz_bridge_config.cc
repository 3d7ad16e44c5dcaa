// The bridge's configuration file (TOML).

#include "fuzz_common.h"
#include "plumb/bridge.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace plumb;
  std::string file = fuzz::ScratchFile(data, size, ".toml");
  fuzz::Expect([&] { LoadBridgeConfig(file); });
  return 0;
}
