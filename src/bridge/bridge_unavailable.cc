// RunBridge in a plumb built without CycloneDDS (plumb/bridge.h): it says what to install.

#include "plumb/bridge.h"
#include "plumb/error.h"

namespace plumb {

BridgeStats RunBridge(const Model&, const std::vector<Assignment>&, const BridgeConfig&,
                      const StopToken&, const BridgeNotice&, BridgeObserver*) {
  throw UnavailableError(
      "this plumb was built without the DDS bridge: CycloneDDS was not found when it was "
      "configured. Install it (Debian: apt-get install cyclonedds-dev cyclonedds-tools; "
      "scripts/install-deps.sh does) and rebuild.");
}

}  // namespace plumb
