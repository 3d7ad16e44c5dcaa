// plumb's error hierarchy.
//
// Every expected failure (missing file, XML error, unknown path, bad value, MuJoCo
// calling mju_error) is reported as a subclass of plumb::Error carrying the whole
// story: what failed, where (file, line, option), and what to do about it. The
// command-line tool maps each class to an exit code in one place
// (apps/plumb/cli_common.cc): bad input is 2, divergence is 3, a failed engine adapter is 6.
//
// A broken internal contract is not an expected failure: it is an InternalError, which
// derives from std::logic_error and not from plumb::Error, so that code handling bad input
// does not swallow a bug (the command-line tool exits with 70).
//
// Thread-safety: every class here is an immutable value; copies may be read from any thread.

#ifndef PLUMB_INCLUDE_PLUMB_ERROR_H_
#define PLUMB_INCLUDE_PLUMB_ERROR_H_

#include <stdexcept>
#include <string>
#include <utility>

namespace plumb {

// Base of every error plumb throws. what() is a complete, human-readable paragraph.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// A model file could not be read or compiled. what() holds the file name and
// MuJoCo's complete error text (element, name, id, line); hint() adds advice for
// known pitfalls (e.g. `range` without `limited` on MuJoCo 2.x), or is empty.
class LoadError : public Error {
 public:
  LoadError(const std::string& message, std::string hint)
      : Error(message), hint_(std::move(hint)) {}
  const std::string& hint() const { return hint_; }

 private:
  std::string hint_;
};

// A path such as `qpos[hinge]` names no array, element or name in the model. what()
// lists the nearest valid names.
class PathError : public Error {
 public:
  using Error::Error;
};

// A value is unusable: non-numeric, NaN/Inf, out of range, or inconsistent with the
// model (e.g. a sampling interval that is not a multiple of the timestep).
class ValueError : public Error {
 public:
  using Error::Error;
};

// A value the caller passed as one of a function's arguments is unusable. argument() names
// that argument in the library's words, the same as the field of the options struct (and
// the Python keyword): "set", "vary", "randomize", "until", "every", "keyframe", "metric",
// "ctrl_noise", ...; value() is what was passed, as the message shows it ("'qpos[hinge]=x'",
// "0.5"; "" when the argument as a whole is wrong); problem() what is wrong with it and what to
// do. what() is "ARGUMENT VALUE: PROBLEM". The command-line tool names the flag instead
// (--set, --ctrl-noise: "--" and the argument with '-' for '_').
class ArgumentError : public ValueError {
 public:
  ArgumentError(std::string argument, std::string value, std::string problem);
  const std::string& argument() const { return argument_; }
  const std::string& value() const { return value_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string argument_, value_, problem_;
};

// `text` in single quotes, as an ArgumentError's value shows a text the caller passed.
std::string Quoted(const std::string& text);

// MuJoCo reported a fatal error through mju_error (e.g. out of stack memory). The
// mjData involved is left in an undefined state and must be reset before reuse.
class MujocoError : public Error {
 public:
  using Error::Error;
};

// A file could not be written (unwritable directory, disk full, ...).
class IoError : public Error {
 public:
  using Error::Error;
};

// Something plumb needs from the machine is not there: the renderer in this build, a GL
// library that can make a headless context, or the ffmpeg program. what() names it and
// how to get it (the command-line tool exits with 5).
class UnavailableError : public Error {
 public:
  using Error::Error;
};

// The engine adapter (plumb crosscheck's Python process that runs MuJoCo Warp or MJX,
// docs/engine-protocol.md) failed: it died, broke the protocol, did not answer in time, or the
// engine raised on a model it had accepted. what() says which, with the adapter's exit status
// or signal and its last lines on stderr (the command-line tool exits with 6).
class EngineError : public Error {
 public:
  using Error::Error;
};

// The engine refuses the model or one of its options (a solver, a geom type it does not
// support). what() is the engine's own message, verbatim. plumb crosscheck reports it as a
// failed row, not as an error that ends the command.
class EngineRefused : public EngineError {
 public:
  using EngineError::EngineError;
};

// The run was stopped by a signal (SIGINT/SIGTERM) before it finished.
class Interrupted : public Error {
 public:
  using Error::Error;
};

// A contract inside plumb was broken: a bug in plumb, never the caller's input (that is a
// plumb::Error). Thrown by PLUMB_DEMAND where code would otherwise go on with a state it
// does not expect; what() names the source file, the line and the condition that failed.
// The process is not ended: a library user (a notebook's kernel, a test runner) gets the
// exception and may report it.
class InternalError : public std::logic_error {
 public:
  InternalError(const char* file, int line, const std::string& condition);
  // The source file (from the project's root, e.g. "src/core/worker_pool.cc") and line.
  const std::string& file() const { return file_; }
  int line() const { return line_; }

 private:
  std::string file_;
  int line_;
};

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_ERROR_H_
