// The chapter's program, built from examples/01_hello, prints the chapter's lines.

#include <gtest/gtest.h>

#include <cstdio>
#include <sstream>

#include "fixture.h"

namespace plumb {
namespace {

TEST(HelloTest, PrintsTheChaptersLines) {
  testing::CommandResult r =
      testing::RunShell(std::string("'") + PLUMB_HELLO + "' '" + testing::kPendulum + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream lines(r.out);
  std::string line;
  std::vector<std::string> got;
  while (std::getline(lines, line)) got.push_back(line);
  ASSERT_EQ(got.size(), 20u);  // t = 0.1 ... 2.0
  // the chapter's printed lines, character for character
  EXPECT_EQ(got[0], "t= 0.10 q=0.65403 dq=-0.89118");
  EXPECT_EQ(got[1], "t= 0.20 q=0.52386 dq=-1.66939");
  EXPECT_EQ(got[2], "t= 0.30 q=0.32596 dq=-2.23353");
  EXPECT_EQ(got[3], "t= 0.40 q=0.08646 dq=-2.49511");
  EXPECT_EQ(got[4], "t= 0.50 q=-0.16156 dq=-2.40852");
  EXPECT_EQ(got[19].substr(0, 7), "t= 2.00");
}

TEST(HelloTest, PrintsTheWholeLoadErrorAndFails) {
  testing::TempDir dir;
  testing::WriteFile(dir.File("neg.xml"),
                     "<mujoco>\n<worldbody>\n<geom name=\"g\" size=\"-1\"/>\n</worldbody>\n"
                     "</mujoco>\n");
  testing::CommandResult r =
      testing::RunShell(std::string("'") + PLUMB_HELLO + "' '" + dir.File("neg.xml") + "'");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(testing::NamesLine(r.err, 3)) << r.err;
}

TEST(HelloTest, ChecksItsArguments) {
  testing::CommandResult r = testing::RunShell(std::string("'") + PLUMB_HELLO + "'");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("usage"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace plumb
