// What a run will cost before it is spent: time and disk, from a probe of its first steps.
//
// Example:
//   plumb::RunEstimate e = plumb::EstimateRun(model, sets, spec, plumb::SampleFormat::kCsv);
//   std::puts(plumb::DescribeEstimate(e, "csv").c_str());
//   // "2000000 steps and 20001 rows: about 14 s and 48 MB of csv (from a 200000-step probe)"
//
// Thread-safety: EstimateRun only reads `model` (it steps a copy) and may run from any thread;
// the timings are of the calling thread. The formatting functions are pure.

#ifndef PLUMB_INCLUDE_PLUMB_RUN_ESTIMATE_H_
#define PLUMB_INCLUDE_PLUMB_RUN_ESTIMATE_H_

#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/path.h"
#include "plumb/run.h"
#include "plumb/sample_writer.h"

namespace plumb {

struct RunEstimate {
  long steps = 0, rows = 0;
  double seconds = 0;  // wall time of the steps and rows
  double bytes = 0;    // output size
  long probe_steps = 0;
};

// Times up to 200000 steps (at most about 0.1 s) of `model` with `sets` applied on a copy,
// and 1024 rows of `spec.columns` written in `format` into memory. Never changes `model`.
// @throws ArgumentError for a spec's until or every that MakeSchedule refuses; a probe that
// diverges just ends early (the run reports it).
RunEstimate EstimateRun(const Model& model, const std::vector<Assignment>& sets,
                        const RunSpec& spec, SampleFormat format);

// "2.0e+07 steps and 200001 rows: about 14 s and 48 MB of csv (from a 200000-step probe)".
std::string DescribeEstimate(const RunEstimate& e, const std::string& format);

// "512 B", "48 kB", "570 MB", "1.2 GB".
std::string FormatBytes(double bytes);

// "40 s", "12 min", "3.5 h", "2.1 days".
std::string FormatDuration(double seconds);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_RUN_ESTIMATE_H_
