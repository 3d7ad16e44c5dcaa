// Realtime pacing on a synthetic clock: late periods are counted and measured, and a spell of
// pacing that resumes is not late; the lockstep command queue keeps order and drops its oldest.

#include "bridge/pacer.h"

#include <gtest/gtest.h>

#include "bridge/command_queue.h"

namespace plumb::bridge {
namespace {

using std::chrono::milliseconds;

TEST(PacerTest, CountsAndMeasuresLatePeriods) {
  Pacer pacer(0.002);
  Pacer::Clock::time_point t0{};
  EXPECT_EQ(pacer.due(t0), t0);  // the first period is due at once
  EXPECT_EQ(pacer.Start(t0), 0);
  EXPECT_EQ(pacer.due(t0), t0 + milliseconds(2));
  // on time, then 1 ms late (caught up: not a late period), then a 33 ms gap
  EXPECT_EQ(pacer.Start(t0 + milliseconds(2)), 0);
  EXPECT_NEAR(pacer.Start(t0 + milliseconds(5)), 0.001, 1e-12);
  EXPECT_EQ(pacer.late_periods(), 0);
  double gap = pacer.Start(t0 + milliseconds(39));
  EXPECT_NEAR(gap, 0.033, 1e-12);
  EXPECT_TRUE(pacer.Late(gap));
  EXPECT_EQ(pacer.late_periods(), 1);
  EXPECT_NEAR(pacer.worst_lateness(), 0.033, 1e-12);
  // the lost time is not made up: one period is caught up, the rest is behind for good
  EXPECT_EQ(pacer.due(t0), t0 + milliseconds(37));
}

TEST(PacerTest, PacingThatResumesIsNotLate) {
  Pacer pacer(0.002);
  Pacer::Clock::time_point t0{};
  pacer.Start(t0);
  pacer.Restart();  // unpaced periods in between (lockstep between two spells of damping)
  Pacer::Clock::time_point later = t0 + std::chrono::seconds(10);
  EXPECT_EQ(pacer.due(later), later);
  EXPECT_EQ(pacer.Start(later), 0);
  EXPECT_EQ(pacer.late_periods(), 0);
}

Arrived Command(double q) {
  MotorCommand c;
  c.q = q;
  return {{c}, 0};
}

TEST(CommandQueueTest, KeepsOrderAndDropsTheOldestWhenFull) {
  CommandQueue queue(3);
  EXPECT_TRUE(queue.Push(Command(1)));
  EXPECT_TRUE(queue.Push(Command(2)));
  EXPECT_TRUE(queue.Push(Command(3)));
  EXPECT_FALSE(queue.Push(Command(4)));  // full: 1 is dropped
  ASSERT_EQ(queue.size(), 3u);
  for (double q : {2, 3, 4}) EXPECT_EQ(queue.Pop().command[0].q, q);
  EXPECT_TRUE(queue.empty());
  EXPECT_TRUE(queue.Push({}));  // a lost command still takes its period
  EXPECT_TRUE(queue.Pop().command.empty());
}

}  // namespace
}  // namespace plumb::bridge
