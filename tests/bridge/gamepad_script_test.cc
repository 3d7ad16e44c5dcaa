// Gamepad scripts: the file format, the pad over time, the log texts and the LowState bytes.

#include "bridge/gamepad_script.h"

#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <future>
#include <string>
#include <utility>

#include "plumb/error.h"

namespace plumb::bridge {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::IsEmpty;

std::uint16_t Bit(const char* name) { return static_cast<std::uint16_t>(1u << ButtonBit(name)); }

// The message Parse gives for `text` as "events.txt", or "" when it parses.
std::string Complaint(const std::string& text) {
  try {
    GamepadScript::Parse(text, "events.txt");
  } catch (const ValueError& e) {
    return e.what();
  }
  return "";
}

float FloatAt(const std::uint8_t* bytes, int offset) {
  std::uint32_t bits = 0;
  for (int i = 0; i < 4; ++i) bits |= static_cast<std::uint32_t>(bytes[offset + i]) << (8 * i);
  float value = 0;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

TEST(GamepadScriptTest, IssueExample) {
  GamepadScript s = GamepadScript::Parse("t = 2.0: start; t = 3.0: lx = 0.5 for 1.0 s", "x");
  EXPECT_FALSE(s.empty());
  EXPECT_EQ(s.At(1.99).keys, 0);
  EXPECT_EQ(s.At(2.0).keys, Bit("start"));
  EXPECT_EQ(s.At(2.09).keys, Bit("start"));
  EXPECT_EQ(s.At(2.1).keys, 0);
  EXPECT_EQ(s.At(2.99).lx, 0);
  EXPECT_EQ(s.At(3.0).lx, 0.5);
  EXPECT_EQ(s.At(3.99).lx, 0.5);
  EXPECT_EQ(s.At(4.0).lx, 0);
  EXPECT_EQ(s.At(4.0), GamepadState{});
  EXPECT_DOUBLE_EQ(s.end(), 4.0);
}

TEST(GamepadScriptTest, EmptyScripts) {
  for (const char* text : {"", "\n\n", "# nothing\n  ;; \n"}) {
    GamepadScript s = GamepadScript::Parse(text, "x");
    EXPECT_TRUE(s.empty()) << text;
    EXPECT_EQ(s.end(), 0);
    EXPECT_EQ(s.At(5), GamepadState{});
    EXPECT_THAT(s.Begun(100), IsEmpty());
  }
  EXPECT_TRUE(GamepadScript().empty());
}

TEST(GamepadScriptTest, AxisWithoutForIsHeld) {
  GamepadScript s = GamepadScript::Parse("t=1:ry=-0.25\nt = 2: rx = 1", "x");
  EXPECT_EQ(s.At(0.5).ry, 0);
  EXPECT_EQ(s.At(1).ry, -0.25);
  EXPECT_EQ(s.At(1000).ry, -0.25);
  EXPECT_EQ(s.At(1000).rx, 1);
  EXPECT_EQ(s.end(), 2);
}

TEST(GamepadScriptTest, ButtonHeldFor) {
  GamepadScript s =
      GamepadScript::Parse("t = 1: A for 2 s\nt = 5: B for 0.5\nt = 7: X for 1s", "x");
  EXPECT_EQ(s.At(2.9).keys, Bit("A"));
  EXPECT_EQ(s.At(3.0).keys, 0);
  EXPECT_EQ(s.At(5.4).keys, Bit("B"));
  EXPECT_EQ(s.At(5.5).keys, 0);
  EXPECT_EQ(s.At(7.5).keys, Bit("X"));
  EXPECT_EQ(s.end(), 8);
}

TEST(GamepadScriptTest, LaterEventOverridesAxis) {
  // A hold, then a timed value over it, then a hold inside the timed one.
  GamepadScript s = GamepadScript::Parse(
      "t = 0: ly = 0.3\nt = 1: ly = 0.8 for 2 s\nt = 5: ly = -0.5 for 10 s\n"
      "t = 6: ly = 0.1",
      "x");
  EXPECT_EQ(s.At(0.5).ly, 0.3);
  EXPECT_EQ(s.At(2).ly, 0.8);
  EXPECT_EQ(s.At(3.5).ly, 0);  // the timed value is over: back to 0, not to the old hold
  EXPECT_EQ(s.At(5.5).ly, -0.5);
  EXPECT_EQ(s.At(6).ly, 0.1);  // a later start wins over a longer earlier event
  EXPECT_EQ(s.At(20).ly, 0.1);
}

TEST(GamepadScriptTest, OutOfOrderStatementsGiveTheSamePad) {
  const char* sorted = "t = 1: lx = 0.5\nt = 2: select for 1 s\nt = 3: lx = -1 for 1 s\nt = 4: up";
  const char* shuffled =
      "t = 4: up\nt = 3: lx = -1 for 1 s\nt = 1: lx = 0.5\nt = 2: select for 1 s";
  GamepadScript a = GamepadScript::Parse(sorted, "a");
  GamepadScript b = GamepadScript::Parse(shuffled, "b");
  for (double t = 0; t < 6; t += 0.01) EXPECT_EQ(a.At(t), b.At(t)) << t;
  EXPECT_EQ(a.end(), b.end());
  EXPECT_THAT(b.Begun(10),
              ElementsAre("gamepad: lx = 0.5", "gamepad: select pressed for 1 s",
                          "gamepad: lx = -1 for 1 s", "gamepad: up pressed for 0.1 s"));
}

TEST(GamepadScriptTest, TiesGoToTheLaterLine) {
  GamepadScript s = GamepadScript::Parse("t = 1: rx = 0.2\nt = 1: rx = 0.7, rx = -0.4", "x");
  EXPECT_EQ(s.At(1).rx, -0.4);
  GamepadScript r = GamepadScript::Parse("t = 1: rx = -0.4\nt = 1: rx = 0.2", "x");
  EXPECT_EQ(r.At(1).rx, 0.2);
  // The later line wins even when it is timed and ends: the axis then returns to 0.
  GamepadScript q = GamepadScript::Parse("t = 1: rx = -0.4\nt = 1: rx = 0.2 for 1 s", "x");
  EXPECT_EQ(q.At(1.5).rx, 0.2);
  EXPECT_EQ(q.At(2.5).rx, 0);
}

TEST(GamepadScriptTest, ButtonsAreOred) {
  GamepadScript s = GamepadScript::Parse(
      "t = 0: L2 for 10 s\nt = 1: R1 for 1 s, A\nt = 1.5: R1 for 3 s\nt = 0.05: L2", "x");
  EXPECT_EQ(s.At(0.07).keys, Bit("L2"));
  EXPECT_EQ(s.At(1.05).keys, Bit("L2") | Bit("R1") | Bit("A"));
  EXPECT_EQ(s.At(2.2).keys, Bit("L2") | Bit("R1"));  // the second R1 press holds it
  EXPECT_EQ(s.At(4.5).keys, Bit("L2"));
  EXPECT_EQ(s.At(10).keys, 0);
  // A long press early on is still found under many short ones after it.
  std::string many = "t = 0: Y for 100 s\n";
  for (int i = 1; i < 500; ++i) many += "t = " + std::to_string(i * 0.1) + ": B\n";
  GamepadScript m = GamepadScript::Parse(many, "x");
  EXPECT_EQ(m.At(49.95).keys, Bit("Y") | Bit("B"));
  EXPECT_EQ(m.At(99.99).keys, Bit("Y"));
  EXPECT_EQ(m.At(100).keys, 0);
}

TEST(GamepadScriptTest, NamesAreCaseInsensitive) {
  GamepadScript s = GamepadScript::Parse("T = 1: START FOR 1 S, Lx = 0.5, r2, Down\n", "x");
  GamepadState pad = s.At(1.05);
  EXPECT_EQ(pad.keys, Bit("start") | Bit("R2") | Bit("down"));
  EXPECT_EQ(pad.lx, 0.5);
  EXPECT_EQ(ButtonBit("sElEcT"), 3);
  EXPECT_EQ(ButtonBit("left"), 15);
  EXPECT_EQ(ButtonBit("R1"), 0);
  EXPECT_EQ(ButtonBit("lx"), -1);
  EXPECT_EQ(ButtonBit(""), -1);
}

TEST(GamepadScriptTest, CommentsAndSeparators) {
  GamepadScript s = GamepadScript::Parse(
      "# a script\n"
      "t = 1: A   # press A; t = 2: B is commented out\n"
      "\n"
      "   ;  t = 3: B ; ; t=4:X   \r\n"
      "#t = 5: Y\n",
      "x");
  EXPECT_EQ(s.At(1).keys, Bit("A"));
  EXPECT_EQ(s.At(2).keys, 0);
  EXPECT_EQ(s.At(3).keys, Bit("B"));
  EXPECT_EQ(s.At(4).keys, Bit("X"));
  EXPECT_EQ(s.At(5).keys, 0);
  EXPECT_DOUBLE_EQ(s.end(), 4.1);
}

TEST(GamepadScriptTest, ErrorsNameTheLineAndWhatToWrite) {
  // (script, a part of the message Parse gives for it)
  const std::pair<const char*, const char*> cases[] = {
      {"t = 1: A\n\nt = 2: jump",
       "events.txt:3: \"jump\": not a button or stick (buttons: R1, L1, start"},
      {"t = 2: jump", "sticks: lx, ly, rx, ry)"},
      {"# x\nlx = 0.5", "events.txt:2: \"lx = 0.5\": missing \"t ="},
      {"start", "events.txt:1: \"start\": missing \"t ="},
      {"t = 2 start", "events.txt:1: \"t = 2 start\": missing \":\""},
      {"\n\nt = -1: A", "events.txt:3: t = -1: the time is negative"},
      {"t = soon: A", "events.txt:1: t = soon: the time is not a number"},
      {"t = nan: A", "events.txt:1: t = nan: the time is not a number"},
      {"t =: A", "events.txt:1: \"t =\" without a time"},
      {"t = 1:", "events.txt:1: t = 1: no action"},
      {"t = 1: A,,B", "events.txt:1: t = 1: an empty action"},
      {"t = 1: A\nt = 2: lx = 1.5",
       "events.txt:2: \"lx = 1.5\": 1.5 is out of range (a stick value is in [-1, 1])"},
      {"t = 1: ry = -1.01", "events.txt:1: \"ry = -1.01\": -1.01 is out"},
      {"t = 1: lx = fast", "events.txt:1: \"lx = fast\": \"fast\" is not a number"},
      {"t = 1: lx =", "events.txt:1: \"lx =\": no value after \"=\""},
      {"t = 1: lx", "events.txt:1: \"lx\": a stick needs a value"},
      {"t = 1: A = 1", "events.txt:1: \"A = 1\": a button takes no value"},
      {"t = 1: A for", "events.txt:1: \"A for\": \"for\" without a duration"},
      {"t = 1: A for 0 s", "events.txt:1: \"A for 0 s\": \"for 0\" is not a positive duration"},
      {"t = 1: lx = 0.5 for -1 s", "\"for -1\" is not a positive"},
      {"t = 1: lx = 0.5 for ever", "\"for ever\" is not a positive"},
      {"t = 1: A B", "events.txt:1: \"A B\": unexpected \"B\""},
      {"t = 1: A for 1 s B", "unexpected \"B\" after the duration"},
      {"t = 1: A for 1s s", "unexpected \"s\" after the duration"},
  };
  for (const auto& [text, expected] : cases) {
    EXPECT_THAT(Complaint(text), HasSubstr(expected)) << text;
  }
}

TEST(GamepadScriptTest, PackWirelessRemoteLayout) {
  GamepadState pad;
  pad.lx = 0.25;
  pad.ly = -0.5;
  pad.rx = 1;
  pad.ry = -0.75;
  pad.keys = static_cast<std::uint16_t>(Bit("L2") | Bit("left") | Bit("R1"));
  std::uint8_t out[40];
  std::memset(out, 0xab, sizeof out);
  PackWirelessRemote(pad, out);
  EXPECT_EQ(out[0], 0);
  EXPECT_EQ(out[1], 0);
  EXPECT_EQ(out[2], 0x21);  // R1 (bit 0) and L2 (bit 5)
  EXPECT_EQ(out[3], 0x80);  // left (bit 15)
  EXPECT_EQ(FloatAt(out, 4), 0.25f);
  EXPECT_EQ(FloatAt(out, 8), 1.0f);
  EXPECT_EQ(FloatAt(out, 12), -0.75f);
  EXPECT_EQ(FloatAt(out, 16), 1.0f);
  EXPECT_EQ(FloatAt(out, 20), -0.5f);
  for (int i = 24; i < 40; ++i) EXPECT_EQ(out[i], 0) << i;

  pad.keys = Bit("R2");
  PackWirelessRemote(pad, out);
  EXPECT_EQ(out[2], 0x10);
  EXPECT_EQ(out[3], 0);
  EXPECT_EQ(FloatAt(out, 16), 0.0f);
}

TEST(GamepadScriptTest, BegunSaysEachEventOnceInTimeOrder) {
  GamepadScript s = GamepadScript::Parse(
      "t = 3.0: lx = 0.5 for 1.0 s\nt = 2.0: start\nt = 3: B for 0.25 s, ry = 1\n", "x");
  EXPECT_THAT(s.Begun(1.9), IsEmpty());
  EXPECT_THAT(s.Begun(2.0), ElementsAre("gamepad: start pressed for 0.1 s"));
  EXPECT_THAT(s.Begun(2.5), IsEmpty());
  EXPECT_THAT(s.Begun(3.5), ElementsAre("gamepad: lx = 0.5 for 1 s",
                                        "gamepad: B pressed for 0.25 s", "gamepad: ry = 1"));
  EXPECT_THAT(s.Begun(100), IsEmpty());
}

TEST(GamepadScriptTest, LoadReadsTheFileAndNamesItInErrors) {
  std::string path = ::testing::TempDir() + "gamepad_script_test_events.txt";
  {
    std::FILE* f = std::fopen(path.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs("t = 1: A\nt = 2: jump\n", f);
    std::fclose(f);
  }
  try {
    GamepadScript::Load(path);
    ADD_FAILURE() << "no error";
  } catch (const ValueError& e) {
    EXPECT_THAT(e.what(), HasSubstr(path + ":2: \"jump\""));
  }
  {
    std::FILE* f = std::fopen(path.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs("t = 1: A\n", f);
    std::fclose(f);
  }
  EXPECT_EQ(GamepadScript::Load(path).At(1).keys, Bit("A"));
  std::remove(path.c_str());
}

TEST(GamepadScriptTest, LoadOfAMissingFileThrowsIoError) {
  EXPECT_THROW(GamepadScript::Load("/nonexistent/dir/events.txt"), IoError);
  try {
    GamepadScript::Load("/nonexistent/dir/events.txt");
  } catch (const IoError& e) {
    EXPECT_THAT(e.what(), HasSubstr("/nonexistent/dir/events.txt"));
  }
}

// Issue 46: a NUL cut the message at the NUL and binary bytes were echoed raw; a long line is
// cut in the message.
TEST(GamepadScriptTest, EchoedTextIsPrintableAndShort) {
  std::string why = Complaint(std::string("t = 1: st\0art\xff", 14));
  EXPECT_THAT(why, HasSubstr("events.txt:1: \"st\\x00art\\xff\": not a button or stick"));
  why = Complaint("t = 1: " + std::string(1000, 'Z'));
  EXPECT_THAT(why, HasSubstr(std::string(60, 'Z') + "\xE2\x80\xA6 (1000 bytes)"));
  EXPECT_LT(why.size(), 300u);
}

// Issue 46: a UTF-8 byte order mark gave "missing t = SECONDS:" on a line that has it.
TEST(GamepadScriptTest, AByteOrderMarkIsSkipped) {
  EXPECT_EQ(Complaint("\xEF\xBB\xBFt = 1: start\n"), "");
  EXPECT_EQ(GamepadScript::Parse("\xEF\xBB\xBFt = 1: A", "e").At(1).keys, Bit("A"));
}

// Issue 46: millions of presses on one line cost the realtime loop its periods.
TEST(GamepadScriptTest, ALineHoldsAtMost4096Bytes) {
  std::string line = "t = 1: A";
  while (line.size() <= 4096) line += ", A";
  EXPECT_THAT(Complaint("t = 0: B\n" + line + "\n"),
              HasSubstr("events.txt:2: the line is 4097 bytes; a line of a gamepad script may "
                        "be at most 4096"));
  std::string fits = "t = 1: A" + std::string(4096 - 8, ' ');
  EXPECT_EQ(Complaint(fits + "\n"), "");
}

// Issue 46: --gamepad /dev/zero ran out of memory, a FIFO hung; a directory stays refused.
TEST(GamepadScriptTest, LoadReadsOnlyARegularFile) {
  auto refusal = [](const std::string& path) {
    try {
      GamepadScript::Load(path);
    } catch (const IoError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_THAT(refusal("/dev/zero"), HasSubstr("'/dev/zero' is a character device"));
  EXPECT_THAT(refusal("/"), HasSubstr("'/' is a directory"));
  char dir[] = "/tmp/plumb-gamepad-XXXXXX";
  ASSERT_NE(mkdtemp(dir), nullptr);
  std::string fifo = std::string(dir) + "/p";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  auto read = std::async(std::launch::async, [&] { return refusal(fifo); });
  if (read.wait_for(std::chrono::seconds(10)) != std::future_status::ready) {
    int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);  // let it go
    if (fd >= 0) ::close(fd);
    ADD_FAILURE() << "Load waited on a FIFO";
  }
  EXPECT_THAT(read.get(), HasSubstr("is a FIFO (named pipe), not a file"));
  std::remove(fifo.c_str());
  rmdir(dir);
}

}  // namespace
}  // namespace plumb::bridge
