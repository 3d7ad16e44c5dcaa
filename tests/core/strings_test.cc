#include "core/strings.h"

#include <gtest/gtest.h>

#include <cmath>

namespace plumb {
using internal::Closest;
using internal::DidYouMean;
using internal::Echo;
using internal::Nearest;
using internal::ParseIndex;
using internal::ParseNumber;
using internal::Plural;
using internal::Split;
using internal::Trim;

namespace {

TEST(StringsTest, ParseNumberIsStrict) {
  EXPECT_EQ(ParseNumber("0.7"), 0.7);
  EXPECT_EQ(ParseNumber(" -1.62 "), -1.62);
  EXPECT_EQ(ParseNumber("1e-3"), 1e-3);
  EXPECT_FALSE(ParseNumber("0.7rad"));
  EXPECT_FALSE(ParseNumber("abc"));
  EXPECT_FALSE(ParseNumber(""));
  EXPECT_FALSE(ParseNumber("0x10"));
  ASSERT_TRUE(ParseNumber("nan"));
  EXPECT_TRUE(std::isnan(*ParseNumber("nan")));  // callers reject it with a message
}

TEST(StringsTest, ParseIndexTakesDigitsOnly) {
  EXPECT_EQ(ParseIndex("3"), 3);
  EXPECT_FALSE(ParseIndex("-1"));
  EXPECT_FALSE(ParseIndex("hinge"));
  EXPECT_FALSE(ParseIndex(""));
}

TEST(StringsTest, SplitKeepsEmptyParts) {
  EXPECT_EQ(Split("0,0,-1.62", ','), (std::vector<std::string>{"0", "0", "-1.62"}));
  EXPECT_EQ(Split("a,,b", ','), (std::vector<std::string>{"a", "", "b"}));
}

TEST(StringsTest, NearestPutsTyposFirst) {
  std::vector<std::string> names = {"torso", "head", "hinge", "hip"};
  std::vector<std::string> near = Nearest("hnge", names, 2);
  ASSERT_FALSE(near.empty());
  EXPECT_EQ(near[0], "hinge");
  EXPECT_EQ(DidYouMean("tors", names).rfind("did you mean: torso", 0), 0u);
}

TEST(StringsTest, ClosestNamesOnlyPlausibleTypos) {
  std::vector<std::string> commands = {"verify",  "audit",   "snapshot", "diff",
                                       "run",     "inspect", "converge", "sweep",
                                       "rollout", "results", "merge"};
  EXPECT_EQ(Closest("rn", commands), std::vector<std::string>{"run"});
  EXPECT_EQ(Closest("verfy", commands), std::vector<std::string>{"verify"});
  EXPECT_EQ(Closest("rnu", commands), std::vector<std::string>{"run"});  // a swap is one edit
  EXPECT_TRUE(Closest("xyzzy", commands).empty());
  std::vector<std::string> options = {"--set", "--until", "--every", "--columns", "-o", "--output"};
  EXPECT_EQ(Closest("--untill", options), std::vector<std::string>{"--until"});
  EXPECT_EQ(Closest("--column", options), std::vector<std::string>{"--columns"});
}

TEST(StringsTest, TrimTakesEveryKindOfWhiteSpace) {
  // three copies trimmed differently: spaces only in metrics and rollouts, all white space in
  // scenarios; one rule now
  EXPECT_EQ(Trim("  qpos[hinge]\t"), "qpos[hinge]");
  EXPECT_EQ(Trim("\n U(0.9, 1.1) \r\n"), "U(0.9, 1.1)");
  EXPECT_EQ(Trim("   "), "");
  EXPECT_EQ(Trim(""), "");
}

}  // namespace
}  // namespace plumb

namespace plumb {
namespace {

TEST(StringsTest, PluralsOfTheNounsThatNameElements) {
  EXPECT_EQ(Plural("body"), "bodies");
  EXPECT_EQ(Plural("actuator"), "actuators");
  EXPECT_EQ(Plural("contact exclude"), "contact excludes");
  EXPECT_EQ(Plural("key"), "keys");
  EXPECT_EQ(Plural("class"), "classes");
  EXPECT_EQ(Plural("mesh"), "meshes");
}

// Text from a user's file in a message (issue 46): control bytes and bytes that are not UTF-8
// escaped, a long text cut with its length.
TEST(StringsTest, EchoEscapesAndCuts) {
  EXPECT_EQ(Echo("start"), "start");
  EXPECT_EQ(Echo(std::string("st\0art", 6)), "st\\x00art");
  EXPECT_EQ(Echo("a\tb\x7f\xff\xc3"), "a\\x09b\\x7f\\xff\\xc3");
  EXPECT_EQ(Echo("caf\xc3\xa9"), "caf\xc3\xa9");  // UTF-8 stays as it is
  std::string key(100000, 'k');
  EXPECT_EQ(Echo(key), std::string(60, 'k') + "\xE2\x80\xA6 (100000 bytes)");
  EXPECT_EQ(Echo(std::string(60, 'k')), std::string(60, 'k'));
  EXPECT_EQ(Echo("abcdef", 3), "abc\xE2\x80\xA6 (6 bytes)");
}

}  // namespace
}  // namespace plumb
