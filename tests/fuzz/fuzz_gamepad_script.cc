// The bridge's gamepad script (src/bridge/gamepad_script.h): the parser, then the pad it
// describes at a few times, and the LowState bytes it packs. Both the text given to Parse and
// the file Load reads (with a byte order mark, NULs, long lines).

#include <cmath>

#include "bridge/gamepad_script.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace plumb;
  std::string text = fuzz::Text(data, size);
  fuzz::Expect([&] {
    bridge::GamepadScript script = bridge::GamepadScript::Parse(text, "events.txt");
    double end = std::isfinite(script.end()) ? script.end() : 1e9;
    std::uint8_t remote[40];
    for (double t : {0.0, 0.05, 1.0, end / 2, end, end + 1}) {
      bridge::PackWirelessRemote(script.At(t), remote);
      script.Begun(t);
    }
  });
  std::string file = fuzz::ScratchFile(data, size, ".gamepad");
  fuzz::Expect([&] { bridge::GamepadScript::Load(file); });
  return 0;
}
