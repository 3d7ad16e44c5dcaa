// plumb.Trajectory, shared by run.cc (plumb.run makes it) and render.cc (plumb.render draws
// its samples).

#ifndef PLUMB_PYTHON_SRC_TRAJECTORY_H_
#define PLUMB_PYTHON_SRC_TRAJECTORY_H_

#include <memory>
#include <string>
#include <vector>

#include "common.h"
#include "plumb/run.h"

namespace plumb::python {

// plumb.Trajectory: what plumb.run sampled, in one rows x columns float64 array.
struct Trajectory {
  std::shared_ptr<PyModel> model;
  std::shared_ptr<Model> ran;  // the model the run used (a copy when `set` edited it)
  std::vector<Path> columns;
  nb::object array;  // owns the samples
  const double* values = nullptr;
  long rows = 0;
  double every = 0;
  RunResult result;
  std::vector<Notice> notices;  // what the call said (plumb.Notice)
  std::string html;

  std::vector<std::string> Names() const;
  // The index of column `name`; KeyError naming the columns when there is none.
  std::size_t Column(const std::string& name) const;
  // What `plumb run --format jsonl` prints.
  std::string Jsonl() const;
  // The CLI's table, the first and last rows of a long run only.
  std::string Table() const;
};

// Column `c` of the samples, a view of the array.
nb::object ColumnView(const Trajectory& t, std::size_t c);

}  // namespace plumb::python

#endif  // PLUMB_PYTHON_SRC_TRAJECTORY_H_
