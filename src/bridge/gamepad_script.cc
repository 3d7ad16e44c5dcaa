// Gamepad scripts (gamepad_script.h).

#include "bridge/gamepad_script.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <string_view>

#include "core/input_file.h"
#include "core/strings.h"
#include "plumb/error.h"

namespace plumb::bridge {
using internal::Echo;
using internal::EqualsIgnoreCase;
using internal::InputKind;
using internal::ParseNumber;
using internal::ReadInputFile;
using internal::Split;
using internal::Trim;

const std::array<const char*, 16> kButtonNames = {"R1", "L1",    "start", "select", "R2", "L2",
                                                  "F1", "F2",    "A",     "B",      "X",  "Y",
                                                  "up", "right", "down",  "left"};

namespace {

constexpr std::array<const char*, 4> kAxisNames = {"lx", "ly", "rx", "ry"};
constexpr double kTapSeconds = 0.1;
constexpr int kL2Bit = 5;
// A line of a script holds at most this many bytes (a few hundred actions): a line of millions
// of presses would cost the realtime loop its periods (At() walks the presses that start
// together).
constexpr std::size_t kMaxLineBytes = 4096;

int AxisIndex(std::string_view name) {
  for (std::size_t i = 0; i < kAxisNames.size(); ++i) {
    if (EqualsIgnoreCase(name, kAxisNames[i])) return static_cast<int>(i);
  }
  return -1;
}

std::vector<std::string_view> Words(std::string_view s) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    std::size_t begin = i;
    while (i < s.size() && !std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    if (i > begin) words.push_back(s.substr(begin, i - begin));
  }
  return words;
}

// The finite number that is all of `s` (plumb's number rule, ParseNumber), or nothing.
std::optional<double> Number(std::string_view s) {
  std::optional<double> value = ParseNumber(s);
  if (!value || !std::isfinite(*value)) return std::nullopt;
  return value;
}

std::string ButtonList() {
  std::string list;
  for (const char* name : kButtonNames) {
    if (!list.empty()) list += ", ";
    list += name;
  }
  return list;
}

// One parsed action before sorting.
struct Action {
  double start;
  int button;        // bit, or -1 for an axis
  int axis;          // 0-3, or -1 for a button
  double value;      // an axis's value
  double duration;   // +infinity for an axis held until changed
  std::string text;  // for Begun()
};

class Parser {
 public:
  explicit Parser(const std::string& source) : source_(source) {}

  std::vector<Action> Run(std::string_view text) {
    // a UTF-8 byte order mark (as some editors write) is no part of the first statement
    if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
    int line_number = 0;
    for (std::string_view line : Split(text, '\n')) {
      line_ = ++line_number;
      if (line.size() > kMaxLineBytes) {
        Fail(
            fmt::format("the line is {} bytes; a line of a gamepad script may be at most {} "
                        "(write the actions over several lines, one statement each: "
                        "t = 2.0: start)",
                        line.size(), kMaxLineBytes));
      }
      line = line.substr(0, line.find('#'));
      for (std::string_view statement : Split(line, ';')) {
        statement = Trim(statement);
        if (!statement.empty()) Statement(statement);
      }
    }
    return std::move(actions_);
  }

 private:
  [[noreturn]] void Fail(const std::string& what) const {
    throw ValueError(fmt::format("{}:{}: {}", source_, line_, what));
  }

  void Statement(std::string_view statement) {
    std::size_t colon = statement.find(':');
    std::string_view head = Trim(statement.substr(0, colon));
    bool has_t = colon != std::string_view::npos && !head.empty() &&
                 (head[0] == 't' || head[0] == 'T') && Trim(head.substr(1)).substr(0, 1) == "=";
    if (!has_t && colon == std::string_view::npos && !head.empty() &&
        (head[0] == 't' || head[0] == 'T') && Trim(head.substr(1)).substr(0, 1) == "=") {
      Fail(fmt::format("\"{}\": missing \":\" after the time (write e.g. \"t = 2.0: start\")",
                       Echo(statement)));
    }
    if (!has_t) {
      Fail(fmt::format(
          "\"{}\": missing \"t = SECONDS:\" before the actions (write e.g. \"t = 2.0: start\")",
          Echo(statement)));
    }
    std::string_view time_text = Trim(Trim(head.substr(1)).substr(1));
    if (time_text.empty()) {
      Fail("\"t =\" without a time (write seconds of simulated time >= 0, e.g. \"t = 2.0:\")");
    }
    std::optional<double> time = Number(time_text);
    if (!time) {
      Fail(
          fmt::format("t = {}: the time is not a number (write seconds of simulated time >= 0, "
                      "e.g. \"t = 2.0:\")",
                      Echo(time_text)));
    }
    if (*time < 0) {
      Fail(
          fmt::format("t = {}: the time is negative (write seconds from the start of the run, "
                      ">= 0)",
                      Echo(time_text)));
    }
    std::string_view actions = Trim(statement.substr(colon + 1));
    if (actions.empty()) {
      Fail(
          fmt::format("t = {}: no action after \":\" (write a button, e.g. \"start\", or a "
                      "stick, e.g. \"lx = 0.5\")",
                      Echo(time_text)));
    }
    for (std::string_view action : Split(actions, ',')) {
      action = Trim(action);
      if (action.empty()) {
        Fail(
            fmt::format("t = {}: an empty action between commas (write a button or a stick "
                        "between each pair of \",\")",
                        Echo(time_text)));
      }
      Act(*time, action);
    }
  }

  [[noreturn]] void Unknown(std::string_view name) const {
    Fail(fmt::format("\"{}\": not a button or stick (buttons: {}; sticks: lx, ly, rx, ry)",
                     Echo(name), ButtonList()));
  }

  void Act(double time, std::string_view action) {
    std::size_t equals = action.find('=');
    if (equals == std::string_view::npos) {
      std::vector<std::string_view> words = Words(action);
      std::string name(words[0]);
      if (AxisIndex(name) >= 0) {
        Fail(
            fmt::format("\"{}\": a stick needs a value (write \"{} = 0.5\" or \"{} = 0.5 for 1 "
                        "s\", values in [-1, 1])",
                        Echo(action), Echo(name), Echo(name)));
      }
      int bit = ButtonBit(name);
      if (bit < 0) Unknown(name);
      double duration = For(action, words, 1).value_or(kTapSeconds);
      actions_.push_back(
          {time, bit, -1, 0, duration,
           fmt::format("gamepad: {} pressed for {} s", kButtonNames[bit], duration)});
      return;
    }
    std::string name(Trim(action.substr(0, equals)));
    int axis = AxisIndex(name);
    if (axis < 0) {
      if (ButtonBit(name) >= 0) {
        Fail(
            fmt::format("\"{}\": a button takes no value (write \"{}\" for a press or \"{} for "
                        "0.5 s\" to hold it)",
                        Echo(action), Echo(name), Echo(name)));
      }
      Unknown(name.empty() ? std::string(action) : name);
    }
    std::vector<std::string_view> words = Words(action.substr(equals + 1));
    if (words.empty()) {
      Fail(
          fmt::format("\"{}\": no value after \"=\" (write a number in [-1, 1], e.g. \"{} = "
                      "0.5\")",
                      Echo(action), Echo(name)));
    }
    std::optional<double> value = Number(words[0]);
    if (!value) {
      Fail(
          fmt::format("\"{}\": \"{}\" is not a number (write a stick value in [-1, 1], e.g. "
                      "\"{} = 0.5\")",
                      Echo(action), Echo(words[0]), Echo(name)));
    }
    if (*value < -1 || *value > 1) {
      Fail(fmt::format("\"{}\": {} is out of range (a stick value is in [-1, 1])", action,
                       Echo(words[0])));
    }
    std::optional<double> duration = For(action, words, 1);
    std::string text = fmt::format("gamepad: {} = {}", kAxisNames[axis], *value);
    if (duration) text += fmt::format(" for {} s", *duration);
    actions_.push_back({time, -1, axis, *value,
                        duration.value_or(std::numeric_limits<double>::infinity()),
                        std::move(text)});
  }

  // The duration of `for D s` in words[i...], or nothing when there are no more words.
  std::optional<double> For(std::string_view action, const std::vector<std::string_view>& words,
                            std::size_t i) const {
    if (i >= words.size()) return std::nullopt;
    if (!EqualsIgnoreCase(words[i], "for")) {
      Fail(
          fmt::format("\"{}\": unexpected \"{}\" (after the action write only \"for SECONDS "
                      "s\", e.g. \"for 0.5 s\")",
                      Echo(action), Echo(words[i])));
    }
    if (i + 1 >= words.size()) {
      Fail(
          fmt::format("\"{}\": \"for\" without a duration (write a positive number of "
                      "seconds, e.g. \"for 0.5 s\")",
                      Echo(action)));
    }
    std::string_view number = words[i + 1];
    if (number.size() > 1 && (number.back() == 's' || number.back() == 'S')) {
      number.remove_suffix(1);
    }
    std::optional<double> duration = Number(number);
    if (!duration || *duration <= 0) {
      Fail(
          fmt::format("\"{}\": \"for {}\" is not a positive duration (write a number of "
                      "seconds > 0, e.g. \"for 0.5 s\")",
                      Echo(action), Echo(words[i + 1])));
    }
    std::size_t next = i + 2;
    if (next < words.size() && number.size() == words[i + 1].size() &&
        EqualsIgnoreCase(words[next], "s")) {
      ++next;
    }
    if (next < words.size()) {
      Fail(
          fmt::format("\"{}\": unexpected \"{}\" after the duration (write \"for SECONDS s\", "
                      "e.g. \"for 0.5 s\"; separate actions with \",\")",
                      Echo(action), Echo(words[next])));
    }
    return *duration;
  }

  const std::string& source_;
  int line_ = 0;
  std::vector<Action> actions_;
};

void PutFloat(float value, std::uint8_t* out) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  for (int i = 0; i < 4; ++i) out[i] = static_cast<std::uint8_t>(bits >> (8 * i));
}

}  // namespace

int ButtonBit(const std::string& name) {
  for (std::size_t i = 0; i < kButtonNames.size(); ++i) {
    if (EqualsIgnoreCase(name, kButtonNames[i])) return static_cast<int>(i);
  }
  return -1;
}

GamepadScript GamepadScript::Parse(const std::string& text, const std::string& source) {
  std::vector<Action> actions = Parser(source).Run(text);
  // File order breaks ties between events that start at the same time.
  std::stable_sort(actions.begin(), actions.end(),
                   [](const Action& a, const Action& b) { return a.start < b.start; });
  GamepadScript script;
  for (Action& a : actions) {
    double stop = a.start + a.duration;
    if (a.button >= 0) {
      script.presses_.push_back({a.start, stop, a.button});
      script.longest_press_ = std::max(script.longest_press_, a.duration);
      script.end_ = std::max(script.end_, stop);
    } else {
      script.axes_[a.axis].push_back({a.start, stop, a.value});
      script.end_ = std::max(script.end_, std::isinf(stop) ? a.start : stop);
    }
    script.log_.emplace_back(a.start, std::move(a.text));
  }
  return script;
}

GamepadScript GamepadScript::Load(const std::string& path) {
  // a FIFO or a device (/dev/zero) is refused, not read; the file is at most 4 MiB
  return Parse(ReadInputFile(path, InputKind::kGamepadScript), path);
}

GamepadState GamepadScript::At(double t) const {
  std::array<double, 4> sticks = {0, 0, 0, 0};
  for (std::size_t i = 0; i < axes_.size(); ++i) {
    const std::vector<AxisEvent>& events = axes_[i];
    // The last event starting at or before t (the last written among equal starts).
    auto after = std::upper_bound(events.begin(), events.end(), t,
                                  [](double time, const AxisEvent& e) { return time < e.start; });
    if (after != events.begin() && t < std::prev(after)->stop) sticks[i] = std::prev(after)->value;
  }
  GamepadState pad{sticks[0], sticks[1], sticks[2], sticks[3], 0};
  // Presses that could hold t start in (t - longest_press_, t]: walk back from the last one
  // starting at or before t until start + longest_press_ <= t (then every earlier press is over).
  auto after = std::upper_bound(presses_.begin(), presses_.end(), t,
                                [](double time, const Press& p) { return time < p.start; });
  for (auto p = after; p != presses_.begin();) {
    --p;
    if (p->start + longest_press_ <= t) break;
    if (t < p->stop) pad.keys |= static_cast<std::uint16_t>(1u << p->bit);
  }
  return pad;
}

std::vector<std::string> GamepadScript::Begun(double t) {
  std::vector<std::string> said;
  while (logged_ < log_.size() && log_[logged_].first <= t) said.push_back(log_[logged_++].second);
  return said;
}

void PackWirelessRemote(const GamepadState& pad, std::uint8_t out[40]) {
  std::memset(out, 0, 40);
  out[2] = static_cast<std::uint8_t>(pad.keys & 0xff);
  out[3] = static_cast<std::uint8_t>(pad.keys >> 8);
  PutFloat(static_cast<float>(pad.lx), out + 4);
  PutFloat(static_cast<float>(pad.rx), out + 8);
  PutFloat(static_cast<float>(pad.ry), out + 12);
  PutFloat((pad.keys >> kL2Bit) & 1u ? 1.0f : 0.0f, out + 16);
  PutFloat(static_cast<float>(pad.ly), out + 20);
}

}  // namespace plumb::bridge
