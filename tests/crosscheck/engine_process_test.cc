// The engine adapter's process (docs/engine-protocol.md) against a stand-in adapter,
// tests/crosscheck/fake_adapter.py: arrays bit for bit, refusals, an adapter that dies, lies,
// hangs or floods its stderr, and no process left behind.

#include "crosscheck/engine_process.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "plumb/error.h"
#include "plumb/stop.h"

namespace plumb {
using internal::EngineArray;
using internal::EngineProcess;
using internal::EngineReply;

namespace {

using Clock = std::chrono::steady_clock;

std::vector<std::string> Adapter(const std::string& mode, const std::string& n = "") {
  std::vector<std::string> argv = {PLUMB_TEST_PYTHON,
                                   PLUMB_SOURCE_DIR "/tests/crosscheck/fake_adapter.py", mode};
  if (!n.empty()) argv.push_back(n);
  return argv;
}

// This test program's children, zombies included (read from /proc).
int CountChildren() {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator("/proc")) {
    std::ifstream stat(entry.path() / "stat");
    std::string text;
    if (!std::getline(stat, text)) continue;
    std::size_t close = text.rfind(')');
    if (close == std::string::npos) continue;
    char state = 0;
    long ppid = 0;
    if (std::sscanf(text.c_str() + close + 1, " %c %ld", &state, &ppid) == 2 && ppid == getpid()) {
      ++count;
    }
  }
  return count;
}

// The process `pid` is gone and reaped: no signal reaches it, and it is no child to wait for.
void ExpectGone(pid_t pid) {
  ASSERT_GT(pid, 0);
  EXPECT_EQ(kill(pid, 0), -1);
  EXPECT_EQ(errno, ESRCH);
  EXPECT_EQ(waitpid(pid, nullptr, WNOHANG), -1);
  EXPECT_EQ(errno, ECHILD);
}

bool SameBits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

// What the EngineError that `call` throws says; a test failure when it throws none, or throws a
// refusal.
template <typename Call>
std::string EngineErrorOf(Call call) {
  try {
    call();
  } catch (const EngineRefused& e) {
    ADD_FAILURE() << "a refusal, not an EngineError: " << e.what();
    return e.what();
  } catch (const EngineError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no EngineError";
  return "";
}

bool Says(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(EngineProcessTest, ArraysMakeTheRoundTripBitForBitIncludingTwentyMegabytes) {
  EngineProcess adapter(Adapter("echo"));
  double nan_with_payload;
  std::uint64_t bits = 0x7ff8000000012345ull;
  std::memcpy(&nan_with_payload, &bits, sizeof bits);
  EngineArray odd{"odd",
                  {2, 3},
                  {-0.0, std::numeric_limits<double>::infinity(), nan_with_payload,
                   std::numeric_limits<double>::denorm_min(), 1e308, 0.1}};
  EngineArray empty{"empty", {0, 4}, {}};
  EngineArray scalar{"scalar", {}, {42.5}};
  EngineArray big{"big", {640, 4096}, std::vector<double>(640 * 4096)};  // 20 MiB
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> uniform(-1e6, 1e6);
  for (double& v : big.values) v = uniform(random);

  nlohmann::json header = {{"op", "stages"}, {"arrays", "replaced"}, {"note", "é"}};
  EngineReply reply = adapter.Request(header, {odd, empty, scalar, big}, 120);
  const nlohmann::json& request = reply.header["request"];
  EXPECT_EQ(request["note"], "é");
  EXPECT_EQ(request["arrays"], nlohmann::json::parse(R"([{"name": "odd", "shape": [2, 3]},
      {"name": "empty", "shape": [0, 4]}, {"name": "scalar", "shape": []},
      {"name": "big", "shape": [640, 4096]}])"));
  ASSERT_EQ(reply.arrays.size(), 8u);
  for (const EngineArray* sent : {&odd, &empty, &scalar, &big}) {
    const EngineArray& back = reply.Get(sent->name);
    EXPECT_EQ(back.shape, sent->shape) << sent->name;
    EXPECT_TRUE(SameBits(back.values, sent->values)) << sent->name;
  }
  std::vector<double> doubled = big.values;
  for (double& v : doubled) v *= 2;
  EXPECT_TRUE(SameBits(reply.Get("big:doubled").values, doubled));
  EXPECT_EQ(reply.Get("scalar:doubled").values, std::vector<double>{85.0});

  // a second request on the same adapter, without arrays: no "arrays" goes out
  EngineReply plain = adapter.Request({{"op", "hello"}, {"protocol", 1}});
  EXPECT_FALSE(plain.header["request"].contains("arrays"));
  EXPECT_TRUE(plain.arrays.empty());
  EXPECT_EQ(plain.Find("big"), nullptr);
  std::string said = EngineErrorOf([&] { plain.Get("qacc"); });
  EXPECT_TRUE(Says(said, "no array 'qacc'")) << said;
}

TEST(EngineProcessTest, ARefusalIsEngineRefusedVerbatimAndTheAdapterServesOn) {
  EngineProcess adapter(Adapter("refuse"));
  try {
    adapter.Request({{"op", "load"}, {"model", "/tmp/model.xml"}});
    ADD_FAILURE() << "no EngineRefused";
  } catch (const EngineRefused& e) {
    EXPECT_STREQ(e.what(), "NotImplementedError: mjSOL_PGS is unsupported.");
  }
  std::string said = EngineErrorOf([&] { adapter.Request({{"op", "error"}}); });
  EXPECT_TRUE(Says(said, "'engine_error'")) << said;
  EXPECT_TRUE(Says(said, "ValueError: it broke")) << said;
  EngineReply reply = adapter.Request({{"op", "hello"}}, {{"x", {1}, {3.0}}});
  EXPECT_EQ(reply.Get("x:doubled").values, std::vector<double>{6.0});
}

TEST(EngineProcessTest, AnAdapterThatDiesMidReplyIsAnEngineErrorWithItsStatusAndStderr) {
  EngineProcess adapter(Adapter("die-after", "2"));
  pid_t pid = adapter.pid();
  std::vector<EngineArray> arrays = {{"qpos", {4, 1}, {1, 2, 3, 4}}};
  adapter.Request({{"op", "stages"}}, arrays);
  adapter.Request({{"op", "stages"}}, arrays);
  std::string said = EngineErrorOf([&] { adapter.Request({{"op", "stages"}}, arrays); });
  EXPECT_TRUE(Says(said, "closed its output during 'stages'")) << said;
  EXPECT_TRUE(Says(said, "exited with status 7")) << said;
  EXPECT_TRUE(Says(said, "RuntimeError: the fake adapter dies after 2 requests")) << said;
  EXPECT_NE(adapter.StderrTail().find("Traceback (most recent call last):"), std::string::npos);
  EXPECT_EQ(adapter.pid(), -1);
  ExpectGone(pid);
  said = EngineErrorOf([&] { adapter.Request({{"op", "hello"}}); });
  EXPECT_TRUE(Says(said, "is gone")) << said;
}

// This program does not ignore SIGPIPE: a write to an adapter that has gone must fail, not
// end the program.
TEST(EngineProcessTest, AnAdapterThatExitsBeforeReadingALargeRequestIsAnEngineError) {
  EngineProcess adapter(
      {PLUMB_TEST_PYTHON, "-c", "import sys; print('bye', file=sys.stderr); sys.exit(5)"});
  pid_t pid = adapter.pid();
  EngineArray big{"qpos", {1 << 22}, std::vector<double>(1 << 22, 1.0)};  // 32 MiB
  std::string said = EngineErrorOf([&] { adapter.Request({{"op", "stages"}}, {big}, 60); });
  EXPECT_TRUE(Says(said, "during 'stages'; it exited with status 5")) << said;
  EXPECT_TRUE(Says(said, "Its last lines on stderr:\n  bye")) << said;
  ExpectGone(pid);
}

TEST(EngineProcessTest, AReplyThatIsNotJsonIsAnEngineErrorAndTheAdapterIsKilled) {
  EngineProcess adapter(Adapter("garbage"));
  pid_t pid = adapter.pid();
  std::string said = EngineErrorOf([&] { adapter.Request({{"op", "hello"}}); });
  EXPECT_TRUE(Says(said, "broke the protocol in its reply to 'hello'")) << said;
  EXPECT_TRUE(Says(said, "'this is not JSON'")) << said;
  EXPECT_TRUE(Says(said, "plumb killed it")) << said;
  EXPECT_TRUE(Says(said, "fake adapter: mode garbage")) << said;
  ExpectGone(pid);
}

TEST(EngineProcessTest, AReplyArrayWithANegativeExtentIsAnEngineError) {
  EngineProcess adapter(Adapter("echo"));
  std::string said = EngineErrorOf([&] { adapter.Request({{"op", "bad-shape"}}); });
  EXPECT_TRUE(Says(said, "the array 'x' with the shape [-1]")) << said;
}

TEST(EngineProcessTest, AnAdapterThatDoesNotReplyInTimeIsKilled) {
  EngineProcess adapter(Adapter("hang"));
  pid_t pid = adapter.pid();
  auto start = Clock::now();
  std::string said = EngineErrorOf([&] {
    adapter.Request({{"op", "rollout"}}, {{"qpos", {1, 1}, {0.5}}}, 1.0);
  });
  EXPECT_TRUE(Says(said, "did not reply to 'rollout' within 1 s")) << said;
  EXPECT_TRUE(Says(said, "plumb killed it")) << said;
  double took = Seconds(start);
  EXPECT_GE(took, 0.9);
  EXPECT_LT(took, 3.0);
  ExpectGone(pid);
}

TEST(EngineProcessTest, TheDestructorLeavesNoProcessBehind) {
  int before = CountChildren();
  pid_t working = -1, hanging = -1;
  auto start = Clock::now();
  {
    EngineProcess echo(Adapter("echo"));
    EngineProcess hang(Adapter("hang"));  // reads quit and never answers: killed after 2 s
    working = echo.pid();
    hanging = hang.pid();
    echo.Request({{"op", "hello"}});
    EXPECT_EQ(CountChildren(), before + 2);
  }
  EXPECT_LT(Seconds(start), 6.0);
  EXPECT_EQ(CountChildren(), before);
  ExpectGone(working);
  ExpectGone(hanging);
}

TEST(EngineProcessTest, AStopRequestKillsTheAdapterAndIsInterrupted) {
  EngineProcess adapter(Adapter("hang"));
  pid_t pid = adapter.pid();
  StopSource source;
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    source.RequestStop();
  });
  auto start = Clock::now();
  EXPECT_THROW(adapter.Request({{"op", "throughput"}}, {}, 0, source.token()), Interrupted);
  stopper.join();
  EXPECT_LT(Seconds(start), 2.0);
  ExpectGone(pid);
  EXPECT_THROW(adapter.Request({{"op", "hello"}}), EngineError);
}

TEST(EngineProcessTest, AFloodOnStderrWhileARequestIsWrittenDoesNotDeadlock) {
  EngineProcess adapter(Adapter("noisy-stderr"));
  EngineArray state{"qpos", {512, 1024}, std::vector<double>(512 * 1024, 0.25)};  // 4 MiB
  EngineReply reply = adapter.Request({{"op", "stages"}}, {state}, 60);
  EXPECT_TRUE(SameBits(reply.Get("qpos").values, state.values));
  std::string tail = adapter.StderrTail();
  EXPECT_EQ(tail.substr(tail.size() - 21), "noisy: the last line\n");
  EXPECT_EQ(std::count(tail.begin(), tail.end(), '\n'), 40);
}

TEST(EngineProcessTest, TheExtraEnvironmentIsSetOnTopOfPlumbs) {
  setenv("PLUMB_FAKE_INHERITED", "kept", 1);
  setenv("PLUMB_FAKE_REPLACED", "old", 1);
  EngineProcess adapter(Adapter("echo"),
                        {{"PLUMB_FAKE_REPLACED", "new"}, {"PLUMB_FAKE_NEW", "a b"}});
  auto value = [&](const char* name) {
    return adapter.Request({{"op", "env"}, {"name", name}}).header["value"];
  };
  EXPECT_EQ(value("PLUMB_FAKE_INHERITED"), "kept");
  EXPECT_EQ(value("PLUMB_FAKE_REPLACED"), "new");
  EXPECT_EQ(value("PLUMB_FAKE_NEW"), "a b");
  unsetenv("PLUMB_FAKE_INHERITED");
  unsetenv("PLUMB_FAKE_REPLACED");
}

TEST(EngineProcessTest, AProgramThatDoesNotExistIsAnEngineError) {
  int before = CountChildren();
  std::string said = EngineErrorOf([] { EngineProcess adapter({"/nonexistent/python3", "a.py"}); });
  EXPECT_TRUE(Says(said, "cannot start the engine adapter '/nonexistent/python3'")) << said;
  EXPECT_EQ(CountChildren(), before);
}

}  // namespace
}  // namespace plumb
