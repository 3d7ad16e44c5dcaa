// A time budget as a stop request.

#include "plumb/stop.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

namespace plumb {
namespace {

TEST(StopTimerTest, RequestsTheStopOnceItsTimeHasPassed) {
  StopSource source;
  StopTimer timer(source, 0.05);
  // the deadline passes at some point; how soon is not a test's business (a loaded machine)
  for (int i = 0; i < 2000 && !source.stop_requested(); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_TRUE(source.stop_requested());
  timer.Finish();
  EXPECT_TRUE(timer.Spent());
}

TEST(StopTimerTest, FinishedInTimeOrWithoutABudgetItRequestsNothing) {
  StopSource source;
  {
    StopTimer timer(source, 3600);
    timer.Finish();
    EXPECT_FALSE(timer.Spent());
  }
  StopTimer none(source, 0);
  none.Finish();
  EXPECT_FALSE(none.Spent());
  EXPECT_FALSE(source.stop_requested());
}

}  // namespace
}  // namespace plumb
