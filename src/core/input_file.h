// Reading a text input the user named (a model, a bridge configuration, a gamepad script, ...):
// one rule for every such file, so that no input can hang plumb or exhaust its memory.
//
// - The file is opened without blocking (O_NONBLOCK): a FIFO with no writer does not stop
//   plumb at open(), before any signal handling could help.
// - Only a regular file is read. A FIFO, a directory, a character device (/dev/zero,
//   /dev/stdin on a terminal), a block device or a socket is refused with a message that names
//   the path, says what it is and what to give instead.
// - Each kind of input has a size cap (InputCap), generous for real use: at most cap + 1 bytes
//   are ever read, so a file that grows while it is read is refused too.
//
// Thread-safety: the functions keep no state: call them from any thread, at once.

#ifndef PLUMB_SRC_CORE_INPUT_FILE_H_
#define PLUMB_SRC_CORE_INPUT_FILE_H_

#include <sys/types.h>

#include <cstddef>
#include <string>

namespace plumb::internal {

enum class InputKind {
  kModel,          // MJCF (XML) or a compiled model (.mjb)
  kBridgeConfig,   // the bridge's TOML
  kGamepadScript,  // the bridge's timed gamepad events
  kScenario,       // a scenario (TOML or JSON)
  kAcceptList,     // an audit accept list (TOML)
  kPoseFile,       // a start pose (qpos numbers or NAME=VALUE lines)
  kRobotLog,       // a robot log or flight recorder log (CSV)
  kColumnMap,      // a robot log's column map (TOML)
  kSnapshot,       // a plumb snapshot (JSON)
};

// What a file of mode `mode` (stat's st_mode) is, in words: "a FIFO (named pipe)", "a
// directory", "a character device" (/dev/zero, a terminal), "a block device", "a
// socket", "a regular file".
const char* FileTypeName(mode_t mode);

// The kind in words for messages: "model file", "bridge config", "gamepad script", ...
const char* InputKindName(InputKind kind);

// The most bytes a file of `kind` may hold (docs/hostile-input.md lists them and why):
// models 256 MiB (a compiled .mjb carries its meshes and textures), robot logs 1 GiB (minutes
// of a humanoid's flight recorder at 500 Hz), snapshots and scenarios 64 MiB, gamepad scripts
// and accept lists 4 MiB, bridge configs, pose files and column maps 1 MiB.
std::size_t InputCap(InputKind kind);

// The whole of `path`, a regular file of at most InputCap(kind) bytes.
// @throws IoError naming the path: "no bridge config 'x.toml' (No such file or directory)",
// "'p' is a FIFO (named pipe), not a file: ...", "'big.txt' is 5000000 bytes (or more); a
// gamepad script may be at most 4194304 (4 MiB) ...", or a read error.
std::string ReadInputFile(const std::string& path, InputKind kind);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_CORE_INPUT_FILE_H_
