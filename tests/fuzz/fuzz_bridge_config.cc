// The bridge's configuration file (TOML), read as plumb bridge reads it, then its names bound to
// a model (motors, [imu], [secondary_imu], [sport_state], [band]) with the positions the file
// gave them, as RunBridge binds them.

#include "bridge/band.h"
#include "bridge/imu.h"
#include "bridge/motor_map.h"
#include "bridge/sport_state.h"
#include "fuzz_common.h"
#include "plumb/bridge.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace plumb;
  std::string file = fuzz::ScratchFile(data, size, ".toml");
  fuzz::Expect([&] {
    BridgeConfig c = LoadBridgeConfig(file);
    const Model& model = fuzz::Humanoid();
    Data d(model);
    d.Forward();
    fuzz::Expect([&] { bridge::MotorMap::Bind(model, c.motors, c.positions); });
    fuzz::Expect([&] { bridge::Imu::Bind(model, c.imu, bridge::kPrimaryImu, c.positions); });
    fuzz::Expect(
        [&] { bridge::Imu::Bind(model, c.secondary_imu, bridge::kSecondaryImu, c.positions); });
    fuzz::Expect([&] { bridge::SportState::Bind(model, c.sport_state, c.positions); });
    fuzz::Expect([&] { bridge::Band(model.get(), d.get(), c.band, c.positions); });
  });
  return 0;
}
