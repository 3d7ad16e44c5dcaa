// What a run says besides its samples, on the call's channel (plumb/notice.h): MuJoCo's
// warnings during the run, which the plumb command prints and Python issues.
//
// Thread-safety: AddRunWarnings only reads its arguments.

#ifndef PLUMB_SRC_SIM_RUN_NOTICES_H_
#define PLUMB_SRC_SIM_RUN_NOTICES_H_

#include <string>
#include <vector>

#include "plumb/notice.h"
#include "plumb/run.h"

namespace plumb::internal {

// Adds to `notices` a warning (topic kOther) per kind of MuJoCo warning `result` summarises,
// "MuJoCo KIND raised N time(s), first in step S (t = T s): MESSAGE", then one per message of
// `others` (the calling thread's pending MuJoCo warnings: TakeMujocoWarnings) that no summary
// holds already, "MuJoCo: MESSAGE" (a summarised message differs from MuJoCo's own text only
// by its " Time = ..." suffix).
void AddRunWarnings(const RunResult& result, const std::vector<std::string>& others,
                    Notices* notices);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_SIM_RUN_NOTICES_H_
