// The bridge's realtime mode keeps pace with the wall clock (its own test program, run
// alone: timing on a loaded machine says more about the machine than about the bridge).

#include <gtest/gtest.h>

#include <future>

#include "bridge/bridge_fixture.h"
#include "fixture.h"

namespace plumb {
namespace {

TEST(BridgeTest, RealtimeKeepsItsPublishRate) {
  Model model = Model::Load(testing::kPendulum);
  BridgeConfig config = PendulumConfig(testing::FreeDomain(), 5.0);
  config.mode = BridgeMode::kRealtime;  // 500 states a second, paced to the wall clock
  Controller controller(config.domain);
  std::atomic<bool> stop{false};
  auto start = std::chrono::steady_clock::now();
  auto bridge = std::async(std::launch::async, [&] { return RunBridge(model, {}, config, &stop); });
  ASSERT_TRUE(controller.Matched());
  State s;
  long received = 0;
  std::uint32_t first = 0, last = 0;
  auto first_at = std::chrono::steady_clock::now(), last_at = first_at;
  while (controller.Next(&s, 2) && s.tick < 4990) {
    if (received++ == 0) {
      first = s.tick;
      first_at = std::chrono::steady_clock::now();
    }
    last = s.tick;
    last_at = std::chrono::steady_clock::now();
    controller.Send(Hold(0.3));
  }
  BridgeStats stats = bridge.get();
  double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  double span = std::chrono::duration<double>(last_at - first_at).count();
  double simulated = (last - first) / 1000.0;
  EXPECT_NEAR(stats.time, 5.0, 1e-9);
  EXPECT_NEAR(wall, 5.0, 0.5);               // paced to the wall clock
  EXPECT_NEAR(simulated / span, 1.0, 0.03);  // simulated time keeps pace within 3 %
  EXPECT_NEAR(received / span, 500, 25);     // and so does the publish rate
}

}  // namespace
}  // namespace plumb
