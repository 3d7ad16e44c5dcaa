// A run's samples kept in memory: which columns a run samples and how often (the rules
// `plumb run` and the Python module's plumb.run share), and a sink that writes every sample
// into one row-major buffer allocated once, sized from the schedule before the run starts.
//
// Example:
//   double dt = plumb::RunTimestep(model, sets);
//   plumb::RunSpec spec;
//   spec.every = plumb::RunEvery(std::nullopt, dt);             // 0.1 s on whole steps
//   spec.columns = plumb::RunColumns(model, {"time,qpos[hinge]"});
//   plumb::TrajectorySink sink(plumb::SampleCount(plumb::MakeSchedule(dt, 2, spec.every)));
//   plumb::Run(model, data, spec, sink);
//   std::vector<double> values = sink.Take();                 // sink.rows() x columns
//
// Thread-safety: the functions keep no state and only read the model. A TrajectorySink serves
// one run at a time.

#ifndef PLUMB_INCLUDE_PLUMB_TRAJECTORY_H_
#define PLUMB_INCLUDE_PLUMB_TRAJECTORY_H_

#include <optional>
#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/path.h"
#include "plumb/run.h"

namespace plumb {

// Splits a comma-separated list of paths, keeping commas inside [...] together
// ("time,xpos[link][2]" -> "time", "xpos[link][2]").
std::vector<std::string> SplitPathList(const std::string& text);

// The columns a run samples: each of `texts` is a path or a comma-separated list of them
// (SplitPathList), with `*` rows expanded (ExpandPath) and blocks split into one column per
// element (ScalarPaths); DefaultColumns(model) when `texts` is empty.
// @throws PathError as ExpandPath does (the message names the path, not the argument).
std::vector<Path> RunColumns(const Model& model, const std::vector<std::string>& texts);

// The sampling interval (s) of a run at `timestep`: `every` when given; else 0.1 s when that
// is a whole number of steps, else the whole number of steps nearest to it (DefaultEvery).
double RunEvery(std::optional<double> every, double timestep);

// The rows a run on `schedule` gives when it does not diverge: the start, then every
// stride-th step.
long SampleCount(const Schedule& schedule);

// Keeps every sample of a run in one buffer of `rows` x columns doubles (row major), made in
// Begin, so a long run costs its samples' memory once and nothing more.
class TrajectorySink : public SampleSink {
 public:
  // `rows`: the most samples the run gives (SampleCount).
  explicit TrajectorySink(long rows);
  void Begin(const std::vector<Path>& columns) override;
  // @throws InternalError when the run gives more rows than the sink was made for.
  void Sample(const std::vector<double>& row) override;

  const std::vector<std::string>& names() const { return names_; }
  long rows() const { return rows_; }
  // The samples, rows() x names().size() (fewer rows than planned when the run diverged or was
  // stopped); the buffer is handed over without a copy (names() and rows() stay).
  std::vector<double> Take();

 private:
  long capacity_;
  long rows_ = 0;
  std::vector<std::string> names_;
  std::vector<double> values_;
};

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_TRAJECTORY_H_
