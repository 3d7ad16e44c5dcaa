// How a rehearsal's client ended, by name (include/plumb/rehearse.h).

#include "plumb/rehearse.h"

namespace plumb {

const char* ClientEndingName(ClientEnding::Kind kind) {
  switch (kind) {
    case ClientEnding::Kind::kStopped:
      return "stopped";
    case ClientEnding::Kind::kKilled:
      return "killed";
    case ClientEnding::Kind::kExitedEarly:
      return "exited early";
    case ClientEnding::Kind::kNotStarted:
      return "not started";
  }
  return "not started";
}

}  // namespace plumb
