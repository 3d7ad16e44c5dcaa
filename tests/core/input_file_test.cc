// Reading a file the user named: only a regular file, never waiting on a FIFO, and never more
// than the kind's cap (issue 46).

#include "core/input_file.h"

#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <future>
#include <string>

#include "fixture.h"
#include "plumb/error.h"

namespace plumb {
using internal::InputCap;
using internal::InputKind;
using internal::InputKindName;
using internal::ReadInputFile;

namespace {

using ::testing::HasSubstr;
using testing::TempDir;
using testing::WriteFile;

// The message ReadInputFile gives for `path`, or "" when it reads it.
std::string Refusal(const std::string& path, InputKind kind) {
  try {
    ReadInputFile(path, kind);
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

TEST(InputFileTest, ReadsARegularFileWhole) {
  TempDir dir;
  std::string text(
      "\xEF\xBB\xBF"
      "family = \"go\"\n\0tail",
      23);
  WriteFile(dir.File("b.toml"), text);
  EXPECT_EQ(ReadInputFile(dir.File("b.toml"), InputKind::kBridgeConfig), text);
  WriteFile(dir.File("empty"), "");
  EXPECT_EQ(ReadInputFile(dir.File("empty"), InputKind::kGamepadScript), "");
}

TEST(InputFileTest, AFifoIsRefusedAtOnce) {
  TempDir dir;
  std::string fifo = dir.File("p");
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  auto read = std::async(std::launch::async, [&] { return Refusal(fifo, InputKind::kModel); });
  if (read.wait_for(std::chrono::seconds(10)) != std::future_status::ready) {
    // it waits for a writer: be that writer so that the test ends
    int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
    if (fd >= 0) ::close(fd);
    ADD_FAILURE() << "ReadInputFile waited on a FIFO";
  }
  std::string why = read.get();
  EXPECT_THAT(why, HasSubstr("'" + fifo + "' is a FIFO (named pipe), not a file"));
  EXPECT_THAT(why, HasSubstr("model file"));
  EXPECT_THAT(why, HasSubstr("Give the MJCF model"));
}

TEST(InputFileTest, ADirectoryADeviceAndASocketAreRefused) {
  TempDir dir;
  EXPECT_THAT(Refusal(dir.path(), InputKind::kBridgeConfig),
              HasSubstr("'" + dir.path() +
                        "' is a directory, not a file: plumb reads a bridge "
                        "config only from a regular file. Give the bridge configuration's .toml"));
  EXPECT_THAT(Refusal("/dev/zero", InputKind::kGamepadScript),
              HasSubstr("'/dev/zero' is a character device"));
  std::string socket_path = dir.File("s");
  int s = ::socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(s, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  ASSERT_LT(socket_path.size(), sizeof address.sun_path);
  socket_path.copy(address.sun_path, socket_path.size());
  ASSERT_EQ(::bind(s, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  EXPECT_THAT(Refusal(socket_path, InputKind::kScenario), HasSubstr("is a socket, not a file"));
  ::close(s);
}

TEST(InputFileTest, AMissingFileIsNamed) {
  EXPECT_THAT(Refusal("nonexist.toml", InputKind::kBridgeConfig),
              HasSubstr("no bridge config 'nonexist.toml' (No such file or directory)"));
}

TEST(InputFileTest, AFileOverTheCapIsRefused) {
  TempDir dir;
  std::size_t cap = InputCap(InputKind::kBridgeConfig);
  EXPECT_EQ(cap, std::size_t{1} << 20);
  WriteFile(dir.File("at-cap.toml"), std::string(cap, '#'));
  EXPECT_EQ(ReadInputFile(dir.File("at-cap.toml"), InputKind::kBridgeConfig).size(), cap);
  WriteFile(dir.File("big.toml"), std::string(cap + 1, '#'));
  EXPECT_THAT(Refusal(dir.File("big.toml"), InputKind::kBridgeConfig),
              HasSubstr("is 1048577 bytes; a bridge config may be at most 1048576 (1 MiB)"));
}

TEST(InputFileTest, EveryKindHasANameAndACap) {
  for (InputKind kind : {InputKind::kModel, InputKind::kBridgeConfig, InputKind::kGamepadScript,
                         InputKind::kScenario, InputKind::kAcceptList, InputKind::kPoseFile,
                         InputKind::kRobotLog, InputKind::kColumnMap, InputKind::kSnapshot}) {
    EXPECT_GE(InputCap(kind), std::size_t{1} << 20) << InputKindName(kind);
    EXPECT_STRNE(InputKindName(kind), "input file");
  }
}

}  // namespace
}  // namespace plumb
