// The rehearsal's client process (src/rehearse/client_process.h) with small shell commands: its
// output's tail and file, how it ended, its working directory and environment, and nothing it
// started left behind.

#include "rehearse/client_process.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "plumb/error.h"

namespace plumb {
using internal::ClientProcess;

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

class ClientProcessTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("plumb_client_process_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
};

// `pid` runs: it exists and is no zombie (an init that reaps no orphans keeps those).
bool Running(pid_t pid) {
  if (kill(pid, 0) != 0) return false;
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text;
  if (!std::getline(stat, text)) return false;
  std::size_t close = text.rfind(')');
  return close != std::string::npos && close + 2 < text.size() && text[close + 2] != 'Z';
}

// Waits up to `seconds` for `pid` to stop running.
bool Gone(pid_t pid, double seconds) {
  const auto deadline = Clock::now() + std::chrono::duration<double>(seconds);
  while (Running(pid)) {
    if (Clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

// Polls until its output has `count` lines (or it ends), at most 2 s.
void WaitForLines(ClientProcess& client, std::size_t count) {
  const auto deadline = Clock::now() + std::chrono::seconds(2);
  while (client.Tail().size() < count && Clock::now() < deadline) {
    if (client.Poll(0.02)) break;
  }
}

TEST_F(ClientProcessTest, ItsLastLinesAndExitStatusAreKept) {
  ClientProcess client(
      "for i in 1 2 3 4 5; do echo line $i; done; echo err >&2; printf tail; exit 3", "", {}, 4,
      "");
  ASSERT_TRUE(client.Poll(5));
  EXPECT_FALSE(client.running());
  EXPECT_EQ(client.exit_code(), 3);
  EXPECT_EQ(client.signal(), 0);
  EXPECT_EQ(client.HowItEnded(), "exited with status 3");
  EXPECT_EQ(client.Tail(), (std::vector<std::string>{"line 4", "line 5", "err", "tail"}));
  EXPECT_FALSE(client.Stop(SIGINT, 1));  // nothing to stop
  EXPECT_EQ(client.HowItEnded(), "exited with status 3");
}

TEST_F(ClientProcessTest, ALongLineIsCutInTheTail) {
  ClientProcess client("head -c 5000 /dev/zero | tr '\\0' x; echo; echo short", "", {}, 5, "");
  ASSERT_TRUE(client.Poll(5));
  std::vector<std::string> tail = client.Tail();
  ASSERT_EQ(tail.size(), 2u);
  EXPECT_EQ(tail[0], std::string(1000, 'x'));
  EXPECT_EQ(tail[1], "short");
}

TEST_F(ClientProcessTest, OneThatIgnoresSigintIsKilledAfterTheGrace) {
  ClientProcess client("trap '' INT; echo ready; sleep 30", "", {}, 5, "");
  WaitForLines(client, 1);
  const auto start = Clock::now();
  EXPECT_TRUE(client.Stop(SIGINT, 0.3));
  double took = std::chrono::duration<double>(Clock::now() - start).count();
  EXPECT_GE(took, 0.29);
  EXPECT_LT(took, 1.5);
  EXPECT_FALSE(client.running());
  EXPECT_EQ(client.signal(), SIGKILL);
  EXPECT_EQ(client.exit_code(), -1);
  EXPECT_EQ(client.HowItEnded(), "killed by SIGKILL after the grace period");
  EXPECT_EQ(client.Tail(), std::vector<std::string>{"ready"});
}

TEST_F(ClientProcessTest, OneThatEndsOnSigintSaysSo) {
  ClientProcess client("echo ready; sleep 30", "", {}, 5, "");
  WaitForLines(client, 1);
  const auto start = Clock::now();
  EXPECT_FALSE(client.Stop(SIGINT, 2));
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - start).count(), 1.0);
  EXPECT_EQ(client.signal(), SIGINT);
  EXPECT_EQ(client.exit_code(), -1);
  EXPECT_EQ(client.HowItEnded(), "ended on SIGINT");
  EXPECT_GT(client.wall(), 0);
  double wall = client.wall();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_EQ(client.wall(), wall);  // stopped at its end
}

TEST_F(ClientProcessTest, ItRunsInItsDirectoryWithItsEnvironment) {
  fs::create_directories(dir_ / "work");
  ClientProcess client("pwd; echo \"$X\"; echo \"$PLUMB_CLIENT_TEST_Y\"", (dir_ / "work").string(),
                       {{"X", "value of x"}, {"PLUMB_CLIENT_TEST_Y", "y"}}, 10, "");
  ASSERT_TRUE(client.Poll(5));
  EXPECT_EQ(client.exit_code(), 0);
  std::vector<std::string> tail = client.Tail();
  ASSERT_EQ(tail.size(), 3u);
  EXPECT_EQ(fs::canonical(tail[0]), fs::canonical(dir_ / "work"));
  EXPECT_EQ(tail[1], "value of x");
  EXPECT_EQ(tail[2], "y");
}

TEST_F(ClientProcessTest, AMissingDirectoryIsRefusedByName) {
  std::string missing = (dir_ / "no such folder").string();
  try {
    ClientProcess client("true", missing, {}, 5, "");
    FAIL() << "a missing directory was taken";
  } catch (const ValueError& e) {
    EXPECT_NE(std::string(e.what()).find("the client's working directory '" + missing +
                                         "' is not a directory: No such file or directory"),
              std::string::npos)
        << e.what();
  }
  std::ofstream(dir_ / "a file") << "x";
  EXPECT_THROW(ClientProcess("true", (dir_ / "a file").string(), {}, 5, ""), ValueError);
}

TEST_F(ClientProcessTest, TheOutputFileHoldsEveryLine) {
  fs::path output = dir_ / "client.log";
  std::ofstream(output) << "an older run's output, longer than this one's\n";
  ClientProcess client("for i in $(seq 1 200); do echo line $i; done; echo oops >&2", "", {}, 3,
                       output.string());
  ASSERT_TRUE(client.Poll(5));
  EXPECT_EQ(client.Tail(), (std::vector<std::string>{"line 199", "line 200", "oops"}));
  EXPECT_EQ(client.output_error(), "");
  std::ifstream in(output);
  std::stringstream text;
  text << in.rdbuf();
  std::string expected;
  for (int i = 1; i <= 200; ++i) expected += "line " + std::to_string(i) + "\n";
  EXPECT_EQ(text.str(), expected + "oops\n");
}

TEST_F(ClientProcessTest, AnOutputFileThatCannotBeWrittenIsAnIoError) {
  EXPECT_THROW(ClientProcess("true", "", {}, 3, (dir_ / "missing" / "client.log").string()),
               IoError);
}

TEST_F(ClientProcessTest, WhatItStartedIsGoneAfterStop) {
  ClientProcess client("sleep 30 & echo $!; wait", "", {}, 5, "");
  WaitForLines(client, 1);
  std::vector<std::string> tail = client.Tail();
  ASSERT_EQ(tail.size(), 1u);
  pid_t grandchild = pid_t(std::stol(tail[0]));
  ASSERT_TRUE(Running(grandchild));
  // the shell ends on SIGINT; its background sleep ignores it (as a non-interactive shell's
  // background commands do) and is killed after the grace
  EXPECT_FALSE(client.Stop(SIGINT, 0.3));
  EXPECT_EQ(client.HowItEnded(), "ended on SIGINT");
  EXPECT_TRUE(Gone(grandchild, 1.0));
}

TEST_F(ClientProcessTest, WhatItLeftBehindIsGoneAfterTheDestructor) {
  pid_t grandchild = -1;
  {
    ClientProcess client("sleep 30 > /dev/null 2>&1 & echo $!", "", {}, 5, "");
    ASSERT_TRUE(client.Poll(5));
    EXPECT_EQ(client.exit_code(), 0);
    grandchild = pid_t(std::stol(client.Tail().at(0)));
    ASSERT_TRUE(Running(grandchild));
  }
  EXPECT_TRUE(Gone(grandchild, 1.0));
}

TEST_F(ClientProcessTest, TheDestructorKillsARunningClient) {
  pid_t grandchild = -1;
  {
    ClientProcess client("trap '' INT TERM; sleep 30 & echo $!; wait", "", {}, 5, "");
    WaitForLines(client, 1);
    grandchild = pid_t(std::stol(client.Tail().at(0)));
    EXPECT_FALSE(client.Poll(0.05));
    EXPECT_TRUE(client.running());
    EXPECT_EQ(client.HowItEnded(), "is still running");
  }
  EXPECT_TRUE(Gone(grandchild, 1.0));
}

}  // namespace
}  // namespace plumb
