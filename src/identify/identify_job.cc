// The identify job (plumb/identify_job.h): the pipeline plumb identify and plumb.identify share.

#include "plumb/identify_job.h"

#include "plumb/error.h"
#include "plumb/model_edit.h"

namespace plumb {

void CheckIdentifyRequest(const IdentifyRequest& request) {
  if (request.logs.empty()) throw ArgumentError("log", "", "give at least one log to fit");
  if (request.options.fit.empty()) {
    throw ArgumentError("fit", "", "give at least one parameter to fit (a plumb path)");
  }
  CheckIdentifyOptions(request.options);
}

IdentifyJobResult RunIdentifyJob(const Model& model, const IdentifyRequest& request) {
  CheckIdentifyRequest(request);
  if (!request.output.empty() && !CanSaveEditedXml()) {
    // says why (UnavailableError), before the work
    SaveXmlWithParameters(request.source.empty() ? model.file() : request.source, model, {},
                          request.output);
  }
  IdentifyJobResult out;
  // the job's own notices, each handed on to the caller's as it comes
  Notices notices([&request](const Notice& n) { AddTo(request.notices, n); });
  ResolveFitParameters(model, request.options.fit, request.options.bounds);  // before the logs
  out.logs = LoadRobotLogs(model, request.logs, request.columns, &notices);
  if (!request.validate.empty()) {
    out.validation = LoadRobotLogs(model, {request.validate}, request.columns, &notices);
  }
  IdentifyOptions options = request.options;
  options.stop = request.stop;
  options.replay.stop = request.stop;
  out.delay = options.delay;
  out.fit = Identify(model, out.logs, options);
  out.fitted = std::make_shared<Model>(FittedModel(model, out.fit));
  if (!out.validation.empty()) {
    out.held_out = ReplayHeldOut(model, *out.fitted, out.validation.front(), options, out.fit);
  }
  if (!request.output.empty()) {
    SaveFittedModel(model, *out.fitted, out.fit, request.output, request.source);
  }
  out.notices = notices.all();
  return out;
}

}  // namespace plumb
