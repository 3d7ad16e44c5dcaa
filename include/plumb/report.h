// One self-contained HTML report per command (--report FILE.html on verify, audit, converge,
// sweep and rollout): a header with the model, its hash, the plumb and MuJoCo versions, the
// command line, the date and pictures of the model; the command's table in PASS / WARN /
// FAIL / SKIP colours; and charts drawn by Chart.js (inlined, with drag-to-zoom), each with
// a short "how to read this". The file needs nothing else: it opens offline from file://
// and makes no network request. It is written through AtomicFile: absent or complete.
//
// Pictures need the renderer (plumb/render.h); without it the report says why they are
// missing and is otherwise the same.
//
// Example:
//   plumb::VerifyReport result = plumb::Verify(model, options);
//   plumb::ReportInfo info{argv};
//   plumb::WriteVerifyReport("pendulum.html", model, options.sets, result, info);
//
// Thread-safety: the writers only read their arguments and keep no state; with pictures they
// run a copy of the model and render on the calling thread (render.h says how renderers may be
// shared) and drop its pending MuJoCo warnings. A BatchCollector is not synchronised: Add to it
// from one thread at a time.

#ifndef PLUMB_INCLUDE_PLUMB_REPORT_H_
#define PLUMB_INCLUDE_PLUMB_REPORT_H_

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "plumb/audit.h"
#include "plumb/converge.h"
#include "plumb/crosscheck.h"
#include "plumb/describe.h"
#include "plumb/identify.h"
#include "plumb/model.h"
#include "plumb/path.h"
#include "plumb/regression.h"
#include "plumb/rehearse.h"
#include "plumb/replay.h"
#include "plumb/robot_log.h"
#include "plumb/run.h"
#include "plumb/verify.h"

namespace plumb {

// A report's model pictures being drawn on a thread of their own (StartPictures).
class PicturesAhead;

struct ReportInfo {
  std::vector<std::string> argv;  // the command line, shown in the header
  // Pictures of the model (t = 0, the end of the nominal run, a short animation) when the
  // renderer can run; false leaves them out (faster; tests of the page alone).
  bool pictures = true;
  double nominal_until = 2.0;  // the nominal run the pictures show, s
  // Frames of the nominal run's animation (0: the two stills only). Each costs about as
  // much as a check on a meshed robot drawn by a software rasteriser: 0.1-0.2 s for a Go2.
  int frames = 12;
  // One picture only, the start state: no nominal run is drawn (a notebook's light view of a
  // result; with frames 0, the page's pictures cost one render).
  bool start_only = false;
  // The pictures, when StartPictures began them before the check; the report waits for them
  // instead of drawing them itself. Null: drawn when the report is written.
  std::shared_ptr<PicturesAhead> ahead = nullptr;
};

// Begins drawing the model pictures of a report (`info`'s pictures, nominal_until and frames,
// started from `sets`) on a thread of their own, and returns them for ReportInfo::ahead. They
// need only the model and its start, so a command starts them before its check and the check's
// time covers theirs: on a software rasteriser they cost a Go2's verify about as much as the
// check itself (bench/RESULTS.md). Null when info.pictures is false. Errors come out of the
// report that waits for them. `model` must outlive the thread (the report waits for it; so
// does the returned object's last owner).
std::shared_ptr<PicturesAhead> StartPictures(const Model& model,
                                             const std::vector<Assignment>& sets,
                                             const ReportInfo& info);

// @throws IoError naming `path` when it cannot be written (nothing is left behind then);
// with pictures, ValueError / PathError when the model refuses `sets`, and MujocoError.
void WriteVerifyReport(const std::string& path, const Model& model,
                       const std::vector<Assignment>& sets, const VerifyReport& report,
                       const ReportInfo& info);

// Each finding that names a body, geom or joint gets a thumbnail with it highlighted.
// @throws as WriteVerifyReport does.
void WriteAuditReport(const std::string& path, const Model& model,
                      const std::vector<Assignment>& sets, const AuditReport& report,
                      const ReportInfo& info);

// @throws as WriteVerifyReport does.
void WriteConvergeReport(const std::string& path, const Model& model,
                         const std::vector<Assignment>& sets,
                         const std::vector<ConvergenceResult>& results, int integrator,
                         const ReportInfo& info);

// plumb diff --report: the snapshot's versions and assignments, the notes, then every change
// beyond tolerance and what another release's compiler derived differently, in tables (kind,
// path, old, new, in words). `snapshot` is the snapshot as the caller named it. @throws
// IoError as WriteVerifyReport does.
void WriteDiffReport(const std::string& path, const Model& model, const SnapshotDiff& diff,
                     const std::string& snapshot, const ReportInfo& info);

// The cases of a sweep or a rollout batch, gathered as they finish for the report. It keeps
// every case up to `most` and a uniform sample beyond (reservoir sampling with a fixed
// seed, so the same batch gives the same report), so memory stays flat however large the
// batch is; the counts are over every case, the charts over the cases kept.
class BatchCollector {
 public:
  BatchCollector(std::vector<std::string> parameters, std::vector<std::string> metrics,
                 std::size_t most = 20000);

  // One case: its parameter values, its metrics (NaN when not measured), and whether it
  // diverged.
  void Add(const std::vector<double>& parameters, const std::vector<double>& metrics,
           bool diverged);

  struct Case {
    std::vector<double> parameters, metrics;
    bool diverged = false;
  };
  const std::vector<std::string>& parameters() const { return parameters_; }
  const std::vector<std::string>& metrics() const { return metrics_; }
  const std::vector<Case>& kept() const { return kept_; }
  long total() const { return total_; }
  long diverged() const { return diverged_; }

 private:
  std::vector<std::string> parameters_, metrics_;
  std::size_t most_;
  std::vector<Case> kept_;
  long total_ = 0, diverged_ = 0;
  std::uint64_t random_ = 0x9e3779b97f4a7c15ULL;
};

// `kind` is "sweep" or "rollout": each metric against each parameter (diverged cases
// marked), and a histogram of each metric. @throws as WriteVerifyReport does.
void WriteBatchReport(const std::string& path, const std::string& kind, const Model& model,
                      const std::vector<Assignment>& sets, const BatchCollector& batch,
                      const ReportInfo& info);

// plumb replay --report: per measured signal, logged against simulated with the rms error
// band, and the error over time. @throws IoError as WriteVerifyReport does.
void WriteReplayReport(const std::string& path, const Model& model, const RobotLog& log,
                       const ReplayResult& result, const ReplayOptions& options,
                       const ReportInfo& info);

// How the replay and identify reports mark a signal's fit, judged against the log's noise
// (SignalFit::noise), not a fixed percentage: PASS when the rms error is within
// kFitNoiseMargin (plumb/replay.h) times the noise; else FAIL below kFitFailPercent, WARN above.
constexpr double kFitFailPercent = 80;
CheckStatus FitStatus(const SignalFit& fit);

// plumb crosscheck --report: the engine and how the model was sent, the rows of the five
// checks, and when each signal parted in the engine against the chaos baseline. `until` is the
// runs' length, s. @throws as WriteVerifyReport does.
void WriteCrosscheckReport(const std::string& path, const Model& model,
                           const std::vector<Assignment>& sets, const CrosscheckReport& result,
                           double until, const ReportInfo& info);

// plumb identify --report: the estimates with their 95 % intervals, the correlation matrix,
// the cost per iteration, the delay scan, and per log (and for the held-out log, when given)
// logged against simulated before and after the fit. @throws IoError as WriteVerifyReport does.
void WriteIdentifyReport(const std::string& path, const Model& model,
                         const std::vector<RobotLog>& logs, const IdentifyResult& result,
                         const ReportInfo& info, const HeldOutLog* validation = nullptr);

// A rehearsal (plumb/rehearse.h, plumb bridge with a client): the verdict and its rows; the
// asserted signals over simulated time, each with its bound when the assertion's row carries
// one (a dashed line) and the events (faults, watchdog, gamepad, band) marked on it; each
// motor's commanded position against its measured one, four motors to a chart; the events
// with their times; how the client ended and its output's last lines (shown as text, never as
// markup); what plumb saw of its commands (period, per motor: targets outside the range,
// saturation, tracking error); and the bridge's counts. `start` is the rehearsal's start (for
// the pictures). @throws as WriteVerifyReport does.
void WriteRehearsalReport(const std::string& path, const Model& model,
                          const std::vector<Assignment>& start, const RehearsalResult& result,
                          const ReportInfo& info);

// The pages of results the command-line tool prints as text only (plumb inspect, run and
// render), for a library user's notebook. They draw no pictures of their own (`info.pictures`
// is not read). @throws IoError as WriteVerifyReport does.

// A model's description (plumb/describe.h): sizes and options, bodies, joints, actuators,
// sensors and delays as tables, each quantity with its unit.
void WriteInspectReport(const std::string& path, const Model& model,
                        const ModelDescription& description, const ReportInfo& info);

// A run's samples: `values` holds `rows` rows of `columns.size()` numbers (row major), as a
// TrajectorySink keeps them. A chart of each column over the `time` column (over the sample
// number when there is none), the first 24 columns; the run's warnings and divergence.
void WriteRunReport(const std::string& path, const Model& model,
                    const std::vector<std::string>& columns, const double* values, long rows,
                    const RunResult& result, const ReportInfo& info);

// Frames drawn by a Renderer: `frames` pictures of width x height RGB bytes one after the other
// (rows top-down, as plumb::Image), shown as an animation at `fps` (a still for one frame).
void WriteRenderReport(const std::string& path, const Model& model, const std::uint8_t* rgb,
                       long frames, int width, int height, double fps, const ReportInfo& info);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_REPORT_H_
