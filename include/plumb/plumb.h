// Everything of plumb's public API in one include, layer by layer (plumb::mpi's rollouts
// across MPI ranks, an optional library, are in plumb/mpi_rollout.h):
//
//   #include <plumb/plumb.h>
//   plumb::Model model = plumb::Model::Load("pendulum.xml");
//   plumb::VerifyReport report = plumb::Verify(model, {});
//
// Each header stands alone too; including only what is used compiles faster.

#ifndef PLUMB_INCLUDE_PLUMB_PLUMB_H_
#define PLUMB_INCLUDE_PLUMB_PLUMB_H_

// the model, paths and results
#include "plumb/check.h"
#include "plumb/describe.h"
#include "plumb/error.h"
#include "plumb/keyframe.h"
#include "plumb/load.h"
#include "plumb/model.h"
#include "plumb/notice.h"
#include "plumb/path.h"
#include "plumb/sleep.h"
#include "plumb/statistics.h"
#include "plumb/stop.h"
#include "plumb/version.h"

// simulating
#include "plumb/analytic.h"
#include "plumb/random.h"
#include "plumb/run.h"
#include "plumb/timing.h"
#include "plumb/trajectory.h"

// files and formats
#include "plumb/image.h"
#include "plumb/json_output.h"
#include "plumb/model_edit.h"
#include "plumb/repro.h"
#include "plumb/robot_log.h"
#include "plumb/run_estimate.h"
#include "plumb/sample_writer.h"
#include "plumb/video.h"

// scenarios and metrics
#include "plumb/metric.h"
#include "plumb/scenario.h"

// the checks and batches
#include "plumb/accept.h"
#include "plumb/audit.h"
#include "plumb/batch.h"
#include "plumb/converge.h"
#include "plumb/identify.h"
#include "plumb/identify_job.h"
#include "plumb/regression.h"
#include "plumb/replay.h"
#include "plumb/rollout.h"
#include "plumb/rollout_csv.h"
#include "plumb/store.h"
#include "plumb/stored_run.h"
#include "plumb/sweep.h"
#include "plumb/verify.h"

// pictures, reports, the bridge
#include "plumb/bridge.h"
#include "plumb/check_table.h"
#include "plumb/render.h"
#include "plumb/report.h"
#include "plumb/result_json.h"
#include "plumb/result_table.h"

#endif  // PLUMB_INCLUDE_PLUMB_PLUMB_H_
