// The bridge's realtime mode keeps pace with the wall clock (its own test program, run
// alone: timing on a loaded machine says more about the machine than about the bridge).

#include <gtest/gtest.h>

#include <cmath>
#include <future>
#include <string>

#include "bridge/bridge_fixture.h"
#include "fixture.h"

namespace plumb {
namespace {

TEST(BridgeTest, RealtimeKeepsItsPublishRate) {
  Model model = Model::Load(testing::kPendulum);
  BridgeConfig config = PendulumConfig(testing::FreeDomain(), 5.0);
  config.mode = BridgeMode::kRealtime;  // 500 states a second, paced to the wall clock
  Controller controller(config.domain);
  plumb::StopSource stop;
  auto start = std::chrono::steady_clock::now();
  auto bridge =
      std::async(std::launch::async, [&] { return RunBridge(model, {}, config, stop.token()); });
  ASSERT_TRUE(controller.Matched());
  State s;
  long received = 0;
  long first = 0, last = 0;
  auto first_at = std::chrono::steady_clock::now(), last_at = first_at;
  while (controller.Next(&s, 2) && SimMs(s) < 4990) {
    if (received++ == 0) {
      first = SimMs(s);
      first_at = std::chrono::steady_clock::now();
    }
    last = SimMs(s);
    last_at = std::chrono::steady_clock::now();
    controller.Send(Hold(0.3));
  }
  BridgeStats stats = bridge.get();
  double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  double span = std::chrono::duration<double>(last_at - first_at).count();
  double simulated = (last - first) / 1000.0;
  EXPECT_NEAR(stats.time, 5.0, 1e-9);
  EXPECT_NEAR(wall, 5.0, 0.5);                   // paced to the wall clock
  EXPECT_NEAR(simulated / span, 1.0, 0.03);      // simulated time keeps pace within 3 %
  EXPECT_NEAR(received / span, 500, 25);         // and so does the publish rate
  EXPECT_NEAR(stats.realtime_factor, 1.0, 0.1);  // as the bridge measured it
  EXPECT_LE(stats.late_periods, stats.steps);
}

// Hostile peers: ten commands a period from the controller (good ones, bad CRCs, NaN gains)
// and a second controller answering every state too. The bridge keeps its rate, applies only
// the first controller's good commands, counts every other one, and its log holds them all.
TEST(BridgeTest, AFloodOfHostileCommandsNeitherSlowsItNorGoesUnrecorded) {
  Model model = Model::Load(testing::kPendulum);
  testing::TempDir dir;
  BridgeConfig config = PendulumConfig(testing::FreeDomain(), 3.0);
  config.mode = BridgeMode::kRealtime;
  config.log = dir.File("flight.csv");
  Controller controller(config.domain), intruder(config.domain);
  plumb::StopSource stop;
  auto bridge =
      std::async(std::launch::async, [&] { return RunBridge(model, {}, config, stop.token()); });
  ASSERT_TRUE(controller.Matched());
  ASSERT_TRUE(intruder.Matched());
  State s;
  long received = 0, bad = 0, nan = 0, good = 0;
  long first = 0, last = 0;
  auto first_at = std::chrono::steady_clock::now(), last_at = first_at;
  controller.Send(Hold(0.3));  // in charge from the start
  while (controller.Next(&s, 2) && SimMs(s) < 2990) {
    if (received++ == 0) {
      first = SimMs(s);
      first_at = std::chrono::steady_clock::now();
    }
    last = SimMs(s);
    last_at = std::chrono::steady_clock::now();
    for (int k = 0; k < 8; ++k, ++good) controller.Send(Hold(0.3));
    controller.Send(Hold(0.3), /*good_crc=*/false);
    ++bad;
    Cmd poisoned = Hold(0.3);
    poisoned.motor_cmd[0].q = NAN;
    controller.Send(poisoned);
    ++nan;
    intruder.Send(Hold(-0.3));
  }
  stop.RequestStop();
  BridgeStats stats = bridge.get();
  double span = std::chrono::duration<double>(last_at - first_at).count();
#if defined(PLUMB_UNDER_ASAN) || defined(__SANITIZE_THREAD__)
  // under a sanitizer eleven commands a period and their log lines take longer than the
  // period itself, and the flood (the test's own code, not instrumented) outruns the bridge:
  // the pace and the share received are the Release build's to show; the accounting of what
  // arrived is checked here too
  (void)span, (void)first, (void)last;
  const double share = 0.5;
#else
  EXPECT_NEAR((last - first) / 1000.0 / span, 1.0, 0.05) << "simulated time keeps pace";
  EXPECT_NEAR(received / span, 500, 25) << "and so does the publish rate";
  const double share = 0.95;
#endif
  EXPECT_EQ(stats.watchdog_trips, 0);
  EXPECT_NEAR(s.motor_state[0].q, 0.3, 0.02) << "the controller in charge holds the pendulum";
  // best effort on loopback may lose a message under load, never invent one
  EXPECT_LE(stats.bad_crc, bad);
  EXPECT_GE(stats.bad_crc, share * bad);
  EXPECT_LE(stats.non_finite, nan);
  EXPECT_GE(stats.non_finite, share * nan);
  EXPECT_LE(stats.commands, good + 1);
  EXPECT_GE(stats.commands, share * good);
  EXPECT_GE(stats.foreign_commands, share * received);
  // the log holds every command applied and every one dropped
  std::string log = testing::ReadFile(config.log);
  auto count = [&](const std::string& text) { return Occurrences(log, text); };
  EXPECT_EQ(count(",command,"), stats.commands);
  EXPECT_EQ(count("dropped a command with a bad CRC"), stats.bad_crc);
  EXPECT_EQ(count("dropped a command with a NaN"), stats.non_finite);
  EXPECT_EQ(count("a second controller (controller 2)"), 1);
  EXPECT_EQ(count(",state,"), stats.states);
}

}  // namespace
}  // namespace plumb
