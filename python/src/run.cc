// plumb.run and plumb.inspect: a run's samples as one numpy array, and a model's description.

#include "plumb/run.h"

#include <fmt/format.h>
#include <stdio.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <iterator>

#include "common.h"
#include "plumb/describe.h"
#include "plumb/error.h"
#include "plumb/image.h"
#include "plumb/json_output.h"
#include "plumb/keyframe.h"
#include "plumb/render.h"
#include "plumb/report.h"
#include "plumb/result_table.h"
#include "plumb/sample_writer.h"
#include "plumb/timing.h"
#include "plumb/trajectory.h"
#include "plumb/video.h"
#include "sim/run_notices.h"
#include "sim/start_hints.h"
#include "trajectory.h"

namespace plumb::python {
namespace {

// The start a call runs from (PyModel::Spec): the call's keyframe, pose file and whole qpos,
// then the load's and the call's `set`; their warnings go to `notices`.
std::vector<Assignment> CallStart(const PyModel& model, const std::optional<std::string>& keyframe,
                                  const std::string& pose, QposArg qpos,
                                  const std::vector<std::string>& sets, Notices* notices) {
  return StartAssignments(model.model(), model.Spec(keyframe, pose, QposText(qpos), sets),
                          notices);
}

// The text a sample writer of `format` writes for `rows` (row indices) of the samples.
std::string SampleText(SampleFormat format, const std::vector<Path>& columns, const double* values,
                       const std::vector<long>& rows) {
  char* buffer = nullptr;
  std::size_t size = 0;
  FILE* out = open_memstream(&buffer, &size);
  if (out == nullptr) throw IoError("could not open a memory stream for the samples' text");
  std::string text;
  try {
    std::unique_ptr<SampleSink> writer = MakeSampleWriter(format, out);
    writer->Begin(columns);
    std::vector<double> row(columns.size());
    for (long r : rows) {
      std::copy(values + r * columns.size(), values + (r + 1) * columns.size(), row.begin());
      writer->Sample(row);
    }
    writer->End();
  } catch (...) {
    std::fclose(out);
    std::free(buffer);
    throw;
  }
  std::fclose(out);
  text.assign(buffer, size);
  std::free(buffer);
  return text;
}

nb::object WarningList(const RunResult& result) {
  return FromJson(WarningsToJson(result.warnings));
}

void BindTrajectory(nb::module_& m) {
  nb::class_<Trajectory>(m, "Trajectory",
                         "plumb.run's samples: .columns (the paths) and .array, one rows x "
                         "columns float64 numpy array (no Python object per sample); "
                         "t['qpos[hinge]'] is a column (a view). to_json() is what `plumb run "
                         "--format jsonl` prints.")
      .def_prop_ro("columns", &Trajectory::Names, "the sampled paths, in column order")
      .def_prop_ro(
          "array", [](const Trajectory& t) { return t.array; },
          "the samples, rows x columns float64 (row k is at t = k x every)")
      .def_prop_ro(
          "time", [](const Trajectory& t) { return ColumnView(t, t.Column("time")); },
          "the time column (s)")
      .def_prop_ro(
          "every", [](const Trajectory& t) { return t.every; }, "the sampling interval, s")
      .def_prop_ro(
          "steps", [](const Trajectory& t) { return t.result.steps; }, "steps taken")
      .def_prop_ro("diverged", [](const Trajectory& t) { return t.result.diverged; })
      .def_prop_ro(
          "divergence",
          [](const Trajectory& t) -> nb::object {
            if (!t.result.divergence) return nb::none();
            nb::dict d;
            d["reason"] = t.result.divergence->reason;
            d["element"] = t.result.divergence->element;
            d["last_good"] = FromJson(StateToJson(t.result.divergence->last_good));
            return d;
          },
          "why and where the run diverged (reason, element, last good state), or None")
      .def_prop_ro(
          "warnings", [](const Trajectory& t) { return WarningList(t.result); },
          "MuJoCo's warnings of the run, one dict per kind")
      .def_ro("notices", &Trajectory::notices,
              "what the call said besides its samples (each also issued as a "
              "plumb.PlumbWarning subclass): a list of plumb.Notice")
      .def("__len__", [](const Trajectory& t) { return t.rows; })
      .def(
          "__getitem__",
          [](const Trajectory& t, const std::string& name) {
            return ColumnView(t, t.Column(name));
          },
          nb::arg("column"), "a column by its path (a view of the array)")
      .def("to_json", &Trajectory::Jsonl,
           "the samples as `plumb run --format jsonl` prints them (one JSON object a line)")
      .def(
          "to_dict",
          [](const Trajectory& t) {
            nb::list rows;
            for (nb::handle line : nb::str(t.Jsonl().c_str()).attr("splitlines")()) {
              rows.append(FromJson(nb::cast<std::string>(line)));
            }
            return rows;
          },
          "to_json() as Python objects: a list of {path: value} dicts, one per sample")
      .def(
          "to_pandas",
          [](const Trajectory& t) {
            std::vector<std::pair<std::string, nb::object>> columns;
            for (std::size_t c = 0; c < t.columns.size(); ++c) {
              columns.emplace_back(t.columns[c].text, ColumnView(t, c));
            }
            return DataFrame(columns);
          },
          "the samples as a pandas.DataFrame, one column per path")
      .def(
          "_repr_html_",
          [](Trajectory& t) {
            if (t.html.empty()) {
              t.html = RunLong([&](StopToken) {
                return ReportHtml([&](const std::string& path) {
                  WriteRunReport(path, *t.ran, t.Names(), t.values, t.rows, t.result,
                                 PythonReportInfo("run", false));
                });
              });
            }
            return t.html;
          },
          "an HTML page charting each column over time")
      .def("__repr__", &Trajectory::Table, "the table `plumb run` prints (a long run elided)");
}

void BindRunCall(nb::module_& m) {
  m.def(
      "run",
      [](ModelArg model, double until, std::optional<double> every, StringsArg columns, SetArg set,
         std::optional<NameOrId> keyframe, std::optional<FileArg> pose, QposArg qpos) {
        auto t = std::make_shared<Trajectory>();
        CallNotices notices;
        std::string pose_file = OptionalPathArg(pose, "pose");
        t->model = ToModel(model, notices.sink());
        std::vector<std::string> sets = SetTexts(set);
        std::vector<std::string> column_texts = StringList(columns, "columns");
        std::vector<double> samples;
        {
          MujocoCallScope scope;
          std::vector<Assignment> start =
              CallStart(*t->model, keyframe, pose_file, qpos, sets, notices.sink());
          t->ran = t->model->EditableFor(start);
          double dt = RunTimestep(*t->ran, start);
          try {
            t->columns = RunColumns(*t->ran, column_texts);
          } catch (const PathError& e) {
            throw PathError(std::string("columns: ") + e.what());
          }
          t->every = RunEvery(every, dt);
          // refuses a bad until or every before the run, and sizes the samples' buffer
          const long rows = SampleCount(MakeSchedule(dt, until, t->every));
          RequireMemoryFor(8.0 * static_cast<double>(rows) * t->columns.size(),
                           fmt::format("the {} samples of {} columns", rows, t->columns.size()),
                           "until", fmt::format("{:g}", until));
          t->result = RunLong([&](StopToken stop) {
            Data data(*t->ran);
            ApplyAssignments(*t->ran, data, start);
            internal::AddStartHints(*t->ran, data, "set", notices.sink());
            RunSpec spec;
            spec.until = until;
            spec.every = t->every;
            spec.columns = t->columns;
            spec.clock_time = true;  // .time is MjData.time
            spec.stop = stop;
            // one buffer, sized from the schedule, that the numpy array takes over
            TrajectorySink sink(rows);
            RunResult result = Run(*t->ran, data, spec, sink);
            t->rows = sink.rows();
            samples = sink.Take();
            internal::AddRunWarnings(result, TakeMujocoWarnings(), notices.sink());
            return result;
          });
        }
        std::size_t width = t->columns.size();
        t->values = samples.data();
        t->array = Matrix(std::move(samples), static_cast<std::size_t>(t->rows), width);
        notices.Issue();
        t->notices = notices.all();
        return t;
      },
      nb::arg("model"), nb::arg("until") = RunSpec{}.until, nb::arg("every") = nb::none(),
      nb::arg("columns") = nb::none(), nb::arg("set") = nb::none(),
      nb::arg("keyframe") = nb::none(), nb::arg("pose") = nb::none(), nb::arg("qpos") = nb::none(),
      "Steps the model with mj_step to `until` s and samples `columns` every `every` s (plumb "
      "run): the default columns are time, qpos and qvel of every joint, ctrl and sensordata; "
      "`every` defaults to 0.1 s on whole steps. `columns` takes paths as the CLI's --columns "
      "('qpos[*]', 'xpos[link][2]', a list or one comma-separated string). Returns a "
      "Trajectory, whose samples live in one numpy array written in place during the run. A "
      "diverged run returns the samples up to the divergence (.diverged, .divergence).");
}

// plumb.Description: plumb inspect's tables as data.
struct Description {
  std::shared_ptr<PyModel> owner;  // keeps a wrapped MjModel alive as long as `model`
  std::shared_ptr<Model> model;
  ModelDescription description;
  std::vector<Notice> notices;  // what the call said (plumb.Notice)
  std::string html;
  std::string Json() const {
    return JsonWithNotices(DescriptionToJson(description, MujocoVersion()), notices);
  }
};

// inspect's JSON lists: each a property (a list of dicts) and a to_pandas() table
constexpr const char* kDescriptionTables[] = {"bodies",  "joints", "actuators",
                                              "sensors", "delays", "roles"};

void BindInspect(nb::module_& m) {
  nb::class_<Description> type(
      m, "Description",
      "plumb.inspect's result: the model's sizes, options, bodies, joints, "
      "actuators, sensors and delays with their units, as `plumb inspect "
      "--format json` gives them (each list a list of dicts).");
  for (const char* key : kDescriptionTables) {
    type.def_prop_ro(key,
                     [key](const Description& d) { return nb::object(FromJson(d.Json())[key]); });
  }
  AddNoticesProperty(type);
  type.def_prop_ro("units",
                   [](const Description& d) { return nb::object(FromJson(d.Json())["units"]); })
      .def_prop_ro("sizes",
                   [](const Description& d) {
                     nb::dict out;
                     for (const auto& [name, value] : d.description.sizes)
                       out[name.c_str()] = value;
                     return out;
                   })
      .def_prop_ro(
          "timestep", [](const Description& d) { return d.description.timestep; }, "s")
      .def_prop_ro("integrator", [](const Description& d) { return d.description.integrator; })
      .def_prop_ro(
          "gravity",
          [](const Description& d) {
            return Array({d.description.gravity.begin(), d.description.gravity.end()});
          },
          "m/s^2")
      .def_prop_ro(
          "total_mass", [](const Description& d) { return d.description.total_mass; }, "kg")
      .def("to_json", &Description::Json, "the JSON `plumb inspect --format json` prints")
      .def(
          "to_dict", [](const Description& d) { return FromJson(d.Json()); },
          "to_json() as Python objects")
      .def(
          "to_pandas",
          [](const Description& d, const std::string& table) {
            if (std::none_of(std::begin(kDescriptionTables), std::end(kDescriptionTables),
                             [&](const char* key) { return table == key; })) {
              throw ArgumentError("table", Quoted(table),
                                  "give bodies, joints, actuators, sensors, delays or roles");
            }
            nb::object rows = FromJson(d.Json());
            DataFrame(
                std::vector<std::pair<std::string, nb::object>>{});  // ImportError without pandas
            return nb::module_::import_("pandas").attr("DataFrame")(rows[table.c_str()]);
          },
          nb::arg("table") = "bodies", "one table as a pandas.DataFrame")
      .def(
          "_repr_html_",
          [](Description& d) {
            if (d.html.empty()) {
              MujocoCallScope scope;
              d.html = ReportHtml([&](const std::string& path) {
                WriteInspectReport(path, *d.model, d.description,
                                   PythonReportInfo("inspect", false));
              });
            }
            return d.html;
          },
          "the tables as an HTML page")
      .def(
          "__repr__",
          [](const Description& d) { return DescriptionTable(d.description, MujocoVersion()); },
          "the table `plumb inspect` prints");

  m.def(
      "inspect",
      [](ModelArg model, SetArg set) {
        auto d = std::make_shared<Description>();
        CallNotices notices;
        std::shared_ptr<PyModel> pm = ToModel(model, notices.sink());
        std::vector<std::string> sets = SetTexts(set);
        {
          MujocoCallScope scope;
          std::vector<Assignment> start = pm->Start(sets, notices.sink());
          d->owner = pm;
          d->model = pm->EditableFor(start);
          if (!start.empty()) {
            Data data(*d->model);
            ApplyAssignments(*d->model, data, start);
          }
          d->description = Describe(*d->model);
        }
        notices.Issue();
        d->notices = notices.all();
        return d;
      },
      nb::arg("model"), nb::arg("set") = nb::none(),
      "Describes the model (plumb inspect): sizes, options, bodies, joints, actuators, sensors, "
      "delays and what is a parameter, state, input or derived, with units. `set` edits a copy "
      "first. Returns a Description.");
}

}  // namespace

std::vector<std::string> Trajectory::Names() const {
  std::vector<std::string> out;
  for (const Path& p : columns) out.push_back(p.text);
  return out;
}

std::size_t Trajectory::Column(const std::string& name) const {
  for (std::size_t c = 0; c < columns.size(); ++c) {
    if (columns[c].text == name) return c;
  }
  std::string names;
  for (const Path& p : columns) names += (names.empty() ? "" : ", ") + p.text;
  throw nb::key_error(fmt::format("no column '{}'; the columns: {}", name, names).c_str());
}

std::string Trajectory::Jsonl() const {
  std::vector<long> all(static_cast<std::size_t>(rows));
  for (long r = 0; r < rows; ++r) all[r] = r;
  return SampleText(SampleFormat::kJsonl, columns, values, all);
}

std::string Trajectory::Table() const {
  constexpr long kHead = 20, kTail = 5;
  std::vector<long> shown;
  for (long r = 0; r < rows; ++r) {
    if (rows <= kHead + kTail || r < kHead || r >= rows - kTail) shown.push_back(r);
  }
  std::string text = SampleText(SampleFormat::kTable, columns, values, shown);
  if (rows > kHead + kTail) {
    // the elision goes after the header and the first kHead rows
    std::size_t at = 0;
    for (long line = 0; line < kHead + 1; ++line) at = text.find('\n', at) + 1;
    text.insert(at, fmt::format("  ... {} rows in all ...\n", rows));
  }
  if (result.diverged && result.divergence) text += "diverged: " + result.divergence->reason + "\n";
  return text;
}

nb::object ColumnView(const Trajectory& t, std::size_t c) {
  return t.array[nb::make_tuple(nb::slice(nb::none(), nb::none(), nb::none()), c)];
}

void BindRun(nb::module_& m) {
  BindTrajectory(m);
  BindRunCall(m);
  BindInspect(m);
}

}  // namespace plumb::python
