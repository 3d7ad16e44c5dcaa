// MujocoHandlerMode::kAroundCalls: plumb's MuJoCo handler only inside MujocoCallScope, only for
// the threads inside one, chained to the handler it replaced. The mode is process-wide, so this
// is a test program of its own.

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <string>
#include <thread>

#include "core/mujoco_compat.h"
#include "plumb/error.h"
#include "plumb/model.h"

namespace plumb {
namespace {

#if PLUMB_MUJOCO_HAS_LOG_HANDLER

// The "other user" of MuJoCo (as the mujoco package): its handler raises its own exception.
struct OtherUsersError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
std::atomic<int> g_other_warnings{0};

void OtherUsersHandler(const mjLogMessage* message) {
  if (message->level == mjLOG_ERROR) throw OtherUsersError(message->subject);
  if (message->level == mjLOG_WARNING) ++g_other_warnings;
}

class HandlerScopeTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    mju_setLogHandler(&OtherUsersHandler);
    SetMujocoHandlerMode(MujocoHandlerMode::kAroundCalls);
    InstallMujocoHandlers();
  }
};

TEST_F(HandlerScopeTest, OutsideAScopeMujocoErrorsAreTheOtherUsers) {
  EXPECT_THROW(mju_error("outside"), OtherUsersError);
  // and plumb installed nothing: the other user's handler is the active one
  mjfLogHandler active = mju_setLogHandler(&OtherUsersHandler);
  EXPECT_EQ(active, &OtherUsersHandler);
}

TEST_F(HandlerScopeTest, InsideAScopeTheyArePlumbsAndWarningsAreCollected) {
  {
    MujocoCallScope scope;
    EXPECT_THROW(mju_error("inside"), MujocoError);
    TakeMujocoWarnings();
    int before = g_other_warnings.load();
    mju_warning("a warning inside");
    std::vector<std::string> warnings = TakeMujocoWarnings();
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0], "a warning inside");
    EXPECT_EQ(g_other_warnings.load(), before);
  }
  EXPECT_THROW(mju_error("after"), OtherUsersError);
  EXPECT_EQ(mju_setLogHandler(&OtherUsersHandler), &OtherUsersHandler);
}

TEST_F(HandlerScopeTest, AnotherThreadDuringAScopeStaysTheOtherUsers) {
  MujocoCallScope scope;
  bool others = false, plumbs = false;
  std::thread outside([&] {
    try {
      mju_error("on another thread");
    } catch (const OtherUsersError&) {
      others = true;
    }
  });
  outside.join();
  std::thread inside([&] {
    MujocoCallScope own;  // a plumb worker thread
    try {
      mju_error("on a plumb thread");
    } catch (const MujocoError&) {
      plumbs = true;
    }
  });
  inside.join();
  EXPECT_TRUE(others);
  EXPECT_TRUE(plumbs);
}

TEST_F(HandlerScopeTest, ScopesNestAndTheLastOneOutRestores) {
  {
    MujocoCallScope outer;
    {
      MujocoCallScope inner;
      EXPECT_THROW(mju_error("nested"), MujocoError);
    }
    EXPECT_THROW(mju_error("still inside"), MujocoError);
  }
  EXPECT_THROW(mju_error("outside again"), OtherUsersError);
}

TEST_F(HandlerScopeTest, AModelLoadedInAScopeWorksAndAWrongOneIsALoadError) {
  MujocoCallScope scope;
  Model model = Model::FromXmlString(
      "<mujoco><worldbody><body><joint/><geom size='0.1'/></body></worldbody></mujoco>");
  Model borrowed = Model::Borrow(model.get_mutable(), "borrowed");
  EXPECT_FALSE(borrowed.owned());
  EXPECT_EQ(borrowed.get(), model.get());
  EXPECT_THROW(Model::FromXmlString("<mujoco><worldbody><geom size='-1'/></worldbody></mujoco>"),
               LoadError);
}

#else

TEST(HandlerScopeTest, NeedsMujocosLogHandler) {
  EXPECT_THROW(SetMujocoHandlerMode(MujocoHandlerMode::kAroundCalls), UnavailableError);
}

#endif

}  // namespace
}  // namespace plumb
