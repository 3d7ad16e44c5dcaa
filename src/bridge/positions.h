// Where a name of the bridge's configuration was written (BridgeConfig::positions), for the
// messages of the parts that bind names to the model.
//
// Thread-safety: pure.

#ifndef PLUMB_SRC_BRIDGE_POSITIONS_H_
#define PLUMB_SRC_BRIDGE_POSITIONS_H_

#include <string>

#include "plumb/bridge.h"

namespace plumb::bridge {

// "FILE:LINE:COLUMN: " where `key` ("motors[2]", "imu.body", ...) was written, or "" when it
// was not read from a file.
inline std::string Place(const BridgePositions& positions, const std::string& key) {
  auto found = positions.find(key);
  return found == positions.end() ? std::string() : found->second + ": ";
}

}  // namespace plumb::bridge

#endif  // PLUMB_SRC_BRIDGE_POSITIONS_H_
