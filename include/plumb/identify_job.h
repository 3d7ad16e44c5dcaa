// The identify job: what `plumb identify` and `plumb.identify` do between parsing their
// arguments and presenting the result, in one call. It checks the request, reads the logs (and
// the held-out one), fits (Identify), makes the fitted model (FittedModel), replays the held-out
// log on both models (ReplayHeldOut) and writes the fitted MJCF when asked (SaveFittedModel).
// What it has to say besides the result (a log whose last line was cut) goes to the request's
// Notices and stays on the result's `notices`.
//
// Example:
//   plumb::IdentifyRequest request;
//   request.logs = {"decay.csv"};
//   request.options.fit = {"dof_damping[hinge]"};
//   request.validate = "held-out.csv";
//   plumb::IdentifyJobResult r = plumb::RunIdentifyJob(model, request);
//   r.fit.estimates[0].value, r.held_out.fitted.fit, r.fitted->get()
//
// Thread-safety: as Identify: `model` is only read, so jobs may run at once on one Model.

#ifndef PLUMB_INCLUDE_PLUMB_IDENTIFY_JOB_H_
#define PLUMB_INCLUDE_PLUMB_IDENTIFY_JOB_H_

#include <memory>
#include <string>
#include <vector>

#include "plumb/identify.h"
#include "plumb/model.h"
#include "plumb/notice.h"
#include "plumb/robot_log.h"
#include "plumb/stop.h"

namespace plumb {

struct IdentifyRequest {
  std::vector<std::string> logs;  // the logs fitted (CSV), one experiment each: at least one
  std::string columns;            // a column map (TOML) for every log; "" none
  std::string validate;           // a log held out of the fit, replayed on both models; "" none
  IdentifyOptions options;        // at least one parameter in `fit`; its stops become `stop`
  // Where to write the MJCF with the fitted values (SaveFittedModel); "" nowhere. `source` is the
  // MJCF they go into ("" the file the model was loaded from).
  std::string output, source;
  StopToken stop;              // when it asks, the job ends with Interrupted
  Notices* notices = nullptr;  // what the job says (a cut log), as it comes; may be null
};

// What the job made. Move it, do not copy it: held_out.log points into `validation`.
struct IdentifyJobResult {
  std::vector<RobotLog> logs;
  std::vector<RobotLog> validation;    // none or the held-out log
  DelayKind delay = DelayKind::kNone;  // the delay estimated (the request's options.delay)
  IdentifyResult fit;
  std::shared_ptr<Model> fitted;  // the model with the estimates (FittedModel)
  HeldOutLog held_out;            // when there is a validation log
  std::vector<Notice> notices;    // every notice the job added, in order

  IdentifyJobResult() = default;
  IdentifyJobResult(IdentifyJobResult&&) = default;
  IdentifyJobResult& operator=(IdentifyJobResult&&) = default;
  IdentifyJobResult(const IdentifyJobResult&) = delete;
  IdentifyJobResult& operator=(const IdentifyJobResult&) = delete;

  // &held_out when there is a validation log, else null (as the tables, JSON and report take it).
  const HeldOutLog* HeldOut() const { return validation.empty() ? nullptr : &held_out; }
};

// Checks a request before anything is read: @throws ArgumentError (argument "log" for no log,
// "fit" for no parameter, else as CheckIdentifyOptions).
void CheckIdentifyRequest(const IdentifyRequest& request);

// Runs the job on `model` (the parameters a caller set are already in it). Everything wrong with
// the request is found before the fit starts: the request (CheckIdentifyRequest), an `output`
// this MuJoCo cannot write (UnavailableError before 3.10), the parameters (ResolveFitParameters),
// then the logs. @throws as CheckIdentifyRequest, ResolveFitParameters,
// LoadRobotLogs, Identify, ReplayHeldOut and SaveFittedModel do; Interrupted when `stop` asks.
IdentifyJobResult RunIdentifyJob(const Model& model, const IdentifyRequest& request);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_IDENTIFY_JOB_H_
