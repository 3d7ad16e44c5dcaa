// Inputs that are not files, as a user gives them on the command line (issue 46): a FIFO is
// refused at once (it hung), /dev/zero and a directory are refused (/dev/zero ran out of memory).

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <string>

#include "fixture.h"

namespace plumb {
namespace {

// `plumb args` under `timeout` (exit 124 when it hangs), with how long it took.
testing::CommandResult RunGuarded(const std::string& args, const std::string& dir,
                                  double* seconds) {
  auto start = std::chrono::steady_clock::now();
  testing::CommandResult r =
      testing::RunShell(std::string("timeout -s KILL 30 '") + PLUMB_CLI + "' " + args, dir);
  *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

TEST(CliInputFilesTest, AFifoAsTheModelIsRefusedAtOnce) {
  testing::TempDir dir;
  ASSERT_EQ(mkfifo(dir.File("p").c_str(), 0600), 0);
  double seconds = 0;
  auto r = RunGuarded("inspect p", dir.path(), &seconds);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_LT(seconds, 10);
  EXPECT_NE(r.err.find("'p' is a FIFO (named pipe), not a file: plumb reads a model file only "
                       "from a regular file"),
            std::string::npos)
      << r.err;
}

TEST(CliInputFilesTest, ADeviceOrADirectoryAsAnInputIsRefused) {
  testing::TempDir dir;
  double seconds = 0;
  auto r = RunGuarded("inspect /dev/zero", dir.path(), &seconds);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("'/dev/zero' is a character device"), std::string::npos) << r.err;
  r = RunGuarded("inspect .", dir.path(), &seconds);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("'.' is a directory, not a file"), std::string::npos) << r.err;
  ASSERT_EQ(mkfifo(dir.File("p").c_str(), 0600), 0);
  r = RunGuarded("diff p '" + testing::kPendulum + "'", dir.path(), &seconds);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("plumb reads a snapshot only from a regular file"), std::string::npos)
      << r.err;
  r = RunGuarded("audit '" + testing::kPendulum + "' --accept p", dir.path(), &seconds);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("plumb reads an accept list only from a regular file"), std::string::npos)
      << r.err;
}

}  // namespace
}  // namespace plumb
