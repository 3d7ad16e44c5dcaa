// Robot logs (CSV) against the pendulum and the humanoid, and column maps (TOML); a log is
// replayed when it loads, since what it holds drives the simulation.

#include "fuzz_common.h"
#include "plumb/replay.h"
#include "plumb/robot_log.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace plumb;
  std::string file = fuzz::ScratchFile(data, size, ".csv");
  for (const Model* model : {&fuzz::Pendulum(), &fuzz::Humanoid()}) {
    fuzz::Expect([&] {
      RobotLog log = LoadRobotLog(*model, file, (*model)->opt.timestep);
      if (log.end - log.start < 0.05) {  // short logs only: a fuzzer must stay fast
        ReplayOptions windows;
        windows.window = 0.01;
        Replay(*model, log, {});
        Replay(*model, log, windows);
      }
    });
  }
  std::string map = fuzz::ScratchFile(data, size, ".toml");
  fuzz::Expect([&] { LoadColumnMap(map); });
  return 0;
}
