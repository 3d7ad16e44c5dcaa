// Snapshot files, as plumb diff reads them.

#include "fuzz_common.h"
#include "plumb/regression.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace plumb;
  std::string text = fuzz::Text(data, size);
  fuzz::Expect([&] { DiffSnapshot(text, fuzz::Pendulum(), {}, 1e-9); });
  return 0;
}
