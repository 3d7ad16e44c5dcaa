#include "plumb/error.h"

#include <gtest/gtest.h>

#include <string>

#include "core/demand.h"
#include "plumb/model.h"
#include "plumb/path.h"

namespace plumb {
namespace {

int Halve(int even) {
  PLUMB_DEMAND(even % 2 == 0);
  return even / 2;
}

TEST(InternalErrorTest, ADemandThatFailsThrowsNamingFileLineAndCondition) {
  EXPECT_EQ(Halve(4), 2);
  int line = __LINE__ - 6;  // the PLUMB_DEMAND in Halve
  try {
    Halve(3);
    FAIL() << "PLUMB_DEMAND let a broken contract through";
  } catch (const InternalError& e) {
    EXPECT_EQ(e.file(), "tests/core/error_test.cc");
    EXPECT_EQ(e.line(), line);
    std::string what = e.what();
    EXPECT_NE(what.find("tests/core/error_test.cc:" + std::to_string(line)), std::string::npos)
        << what;
    EXPECT_NE(what.find("even % 2 == 0"), std::string::npos) << what;
    EXPECT_NE(what.find("bug in plumb"), std::string::npos) << what;
  }
}

TEST(InternalErrorTest, ABugIsNotBadInput) {
  // code that handles plumb::Error (bad input, with advice for the user) does not swallow a
  // bug: the library's caller sees a std::logic_error and the process goes on
  bool as_bad_input = false, as_bug = false;
  try {
    try {
      Halve(1);
    } catch (const Error&) {
      as_bad_input = true;
    }
  } catch (const std::logic_error&) {
    as_bug = true;
  }
  EXPECT_FALSE(as_bad_input);
  EXPECT_TRUE(as_bug);
}

// A library caller learns which of its arguments was wrong, in the library's words: no
// command-line flag in the message.
TEST(ArgumentErrorTest, NamesTheArgumentItsValueAndTheProblemWithoutAFlag) {
  Model model = Model::FromXmlString(R"(<mujoco><worldbody><body>
      <joint name="hinge" axis="0 1 0"/><geom size="0.1" mass="1"/></body></worldbody></mujoco>)");
  try {
    ParseAssignment(model, "qpos[hinge]=x");
    FAIL() << "'x' is not a number";
  } catch (const ArgumentError& e) {
    EXPECT_EQ(e.argument(), "set");
    EXPECT_EQ(e.value(), "'qpos[hinge]=x'");
    EXPECT_EQ(e.problem(), "'x' is not a number.");
    EXPECT_EQ(std::string(e.what()), "set 'qpos[hinge]=x': 'x' is not a number.");
  }
  // it is a ValueError: code that handles bad values handles it
  EXPECT_THROW(ParseAssignment(model, "qpos[hinge]"), ValueError);
  ArgumentError whole("metric", "", "a sweep needs at least one metric");
  EXPECT_EQ(std::string(whole.what()), "metric: a sweep needs at least one metric");
}

}  // namespace
}  // namespace plumb
