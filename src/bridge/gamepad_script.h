// A gamepad script: timed events that drive Unitree's wireless controller
// (rt/wirelesscontroller and rt/wireless_controller, WirelessController_: lx, ly, rx, ry, keys) as
// the bridge publishes it, and the `wireless_remote` bytes of LowState_.
//
// File format (text, one statement per line or several separated by `;`):
//
//   # Stand up, walk forward for a second, then turn.
//   t = 2.0: start                    # start pressed for 0.1 s
//   t = 3.0: lx = 0.5 for 1.0 s       # lx at 0.5 from 3.0 s, back to 0 at 4.0 s
//   t = 5: rx = -0.3; t = 6: rx = 0   # rx held at -0.3 from 5 s until 6 s
//   t = 7: A for 2 s, L2              # several actions at once, separated by `,`
//
// - `#` starts a comment that runs to the end of the line. Blank statements are ignored; an
//   empty file is an empty script (the pad stays at rest).
// - A statement is `t = T: ACTION[, ACTION ...]`; spaces are optional. T is the simulated time
//   in seconds, a number >= 0.
// - An ACTION is one of
//     BUTTON              the button pressed for 0.1 s (a press a 50 Hz controller sees)
//     BUTTON for D s      the button held for D seconds (D > 0; the trailing `s` is optional)
//     AXIS = V            the stick axis set to V, held until a later event sets that axis
//     AXIS = V for D s    the stick axis set to V for D seconds, then back to 0
//   BUTTON is one of kButtonNames (R1 L1 start select R2 L2 F1 F2 A B X Y up right down left),
//   AXIS one of lx ly rx ry; both are case-insensitive. V is in [-1, 1].
// - Statements may come in any time order. An axis takes the value of its event with the
//   latest start <= t (of events starting at the same time, the one written last); when that
//   event was given a duration which has passed, the axis is 0. A button is held while any of
//   its presses holds: press [start, start + D) contains t.
// - A mistake is reported as a ValueError "SOURCE:LINE: ..." saying what was found and what
//   to write instead; text from the script is quoted through Echo (at most 60 characters,
//   bytes that would not print as \xNN).
// - A UTF-8 byte order mark at the start is skipped. A line may hold at most 4096 bytes, a
//   file (Load) at most 4 MiB: a script is read as ReadInputFile reads it (a FIFO or a device
//   is refused).

#ifndef PLUMB_SRC_BRIDGE_GAMEPAD_SCRIPT_H_
#define PLUMB_SRC_BRIDGE_GAMEPAD_SCRIPT_H_

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace plumb::bridge {

// The pad at one instant.
struct GamepadState {
  double lx = 0, ly = 0, rx = 0, ry = 0;  // sticks, each in [-1, 1]
  std::uint16_t keys = 0;                 // one bit per button (kButtonNames order)

  bool operator==(const GamepadState& o) const {
    return lx == o.lx && ly == o.ly && rx == o.rx && ry == o.ry && keys == o.keys;
  }
  bool operator!=(const GamepadState& o) const { return !(*this == o); }
};

// Unitree's key bits: bit i is the button kButtonNames[i].
extern const std::array<const char*, 16> kButtonNames;

// The bit of a button name (case-insensitive), or -1.
int ButtonBit(const std::string& name);

// A parsed script: At() is the pad at a time, Begun() the events' texts for the flight log.
// At() costs O(log n) per axis plus the presses that start within the longest press before t.
// Not thread-safe for Begun(); At() is const and may be called from any thread.
class GamepadScript {
 public:
  GamepadScript() = default;

  // @throws ValueError naming source:line, what was found and what to write instead.
  static GamepadScript Parse(const std::string& text, const std::string& source);
  // Reads the file at `path` and parses it (errors name `path` as the source).
  // @throws IoError when the file is missing, not a regular file or over 4 MiB (InputCap),
  // ValueError as Parse.
  static GamepadScript Load(const std::string& path);

  // The pad at simulated time t (s).
  GamepadState At(double t) const;

  bool empty() const { return log_.empty(); }

  // The texts of events that begin at or before t since the last call, in time order (ties in
  // file order), e.g. "gamepad: start pressed for 0.1 s", "gamepad: lx = 0.5 for 1 s". Each
  // event's text is returned once.
  std::vector<std::string> Begun(double t);

  // The time after which the pad no longer changes (0 for an empty script).
  double end() const { return end_; }

 private:
  struct Press {
    double start, stop;
    int bit;
  };
  struct AxisEvent {
    double start, stop;  // stop is +infinity for a hold
    double value;
  };

  std::vector<Press> presses_;                       // by start
  double longest_press_ = 0;                         // the longest D among presses_
  std::array<std::vector<AxisEvent>, 4> axes_;       // lx ly rx ry, by start then file order
  std::vector<std::pair<double, std::string>> log_;  // (start, text) by start then file order
  std::size_t logged_ = 0;                           // log_ entries Begun() has returned
  double end_ = 0;
};

// Packs the pad into the 40-byte `wireless_remote` field of Unitree's LowState_ (the layout of
// the SDK's xRockerBtnDataStruct): bytes 0-1 head (0), 2-3 keys (little-endian, same bits),
// 4 lx, 8 rx, 12 ry, 16 L2 (1 when L2 is held, else 0), 20 ly (little-endian IEEE floats),
// 24-39 zero.
void PackWirelessRemote(const GamepadState& pad, std::uint8_t out[40]);

}  // namespace plumb::bridge

#endif  // PLUMB_SRC_BRIDGE_GAMEPAD_SCRIPT_H_
