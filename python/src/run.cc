// plumb.run, plumb.inspect and plumb.render: a run's samples as one numpy array, a model's
// description, and pictures or videos of the model.

#include "plumb/run.h"

#include <fmt/format.h>
#include <stdio.h>

#include <cstdint>
#include <cstdlib>

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

namespace plumb::python {

// Arguments of run and render that take several Python types.
struct StateArg {  // mujoco.MjData | plumb.Trajectory (or None)
  nb::handle object;
};

}  // namespace plumb::python

namespace nanobind::detail {
PLUMB_ANY_OBJECT_CASTER(plumb::python::StateArg, "mujoco.MjData | Trajectory")
}  // namespace nanobind::detail

namespace plumb::python {
namespace {

// The start a call runs from (PyModel::Spec): the call's keyframe, pose file and whole qpos,
// then the load's and the call's `set`.
std::vector<Assignment> CallStart(const PyModel& model, const std::optional<std::string>& keyframe,
                                  const std::string& pose, QposArg qpos,
                                  const std::vector<std::string>& sets) {
  return StartAssignments(model.model(), model.Spec(keyframe, pose, QposText(qpos), sets));
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
  std::string html;

  std::vector<std::string> Names() const {
    std::vector<std::string> out;
    for (const Path& p : columns) out.push_back(p.text);
    return out;
  }
  std::size_t Column(const std::string& name) const {
    for (std::size_t c = 0; c < columns.size(); ++c) {
      if (columns[c].text == name) return c;
    }
    std::string names;
    for (const Path& p : columns) names += (names.empty() ? "" : ", ") + p.text;
    throw nb::key_error(fmt::format("no column '{}'; the columns: {}", name, names).c_str());
  }
  std::string Jsonl() const {
    std::vector<long> all(static_cast<std::size_t>(rows));
    for (long r = 0; r < rows; ++r) all[r] = r;
    return SampleText(SampleFormat::kJsonl, columns, values, all);
  }
  // The CLI's table, the first and last rows of a long run only.
  std::string Table() const {
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
    if (result.diverged && result.divergence)
      text += "diverged: " + result.divergence->reason + "\n";
    return text;
  }
};

nb::object ColumnView(const Trajectory& t, std::size_t c) {
  return t.array[nb::make_tuple(nb::slice(nb::none(), nb::none(), nb::none()), c)];
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
         std::optional<std::string> keyframe, std::optional<FileArg> pose, QposArg qpos) {
        auto t = std::make_shared<Trajectory>();
        std::string pose_file = OptionalPathArg(pose);
        t->model = ToModel(model);
        std::vector<std::string> sets = SetTexts(set);
        std::vector<std::string> column_texts = StringList(columns, "columns");
        std::vector<double> samples;
        {
          MujocoCallScope scope;
          std::vector<Assignment> start = CallStart(*t->model, keyframe, pose_file, qpos, sets);
          t->ran = t->model->EditableFor(start);
          double dt = RunTimestep(*t->ran, start);
          try {
            t->columns = RunColumns(*t->ran, column_texts);
          } catch (const PathError& e) {
            throw PathError(std::string("columns: ") + e.what());
          }
          t->every = RunEvery(every, dt);
          MakeSchedule(dt, until, t->every);  // refuses a bad until or every before the run
          t->result = RunLong([&](StopToken stop) {
            Data data(*t->ran);
            ApplyAssignments(*t->ran, data, start);
            RunSpec spec;
            spec.until = until;
            spec.every = t->every;
            spec.columns = t->columns;
            spec.stop = stop;
            // one buffer, sized from the schedule, that the numpy array takes over
            TrajectorySink sink(SampleCount(MakeSchedule(dt, until, t->every)));
            RunResult result = Run(*t->ran, data, spec, sink);
            t->rows = sink.rows();
            samples = sink.Take();
            TakeMujocoWarnings();
            return result;
          });
        }
        std::size_t width = t->columns.size();
        t->values = samples.data();
        t->array = Matrix(std::move(samples), static_cast<std::size_t>(t->rows), width);
        return t;
      },
      nb::arg("model"), nb::arg("until") = 2.0, nb::arg("every") = nb::none(),
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
  std::string html;
  std::string Json() const { return DescriptionToJson(description, MujocoVersion()); }
};

void BindInspect(nb::module_& m) {
  nb::class_<Description>(m, "Description",
                          "plumb.inspect's result: the model's sizes, options, bodies, joints, "
                          "actuators, sensors and delays with their units, as `plumb inspect "
                          "--format json` gives them (each list a list of dicts).")
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
      .def_prop_ro("bodies",
                   [](const Description& d) { return nb::object(FromJson(d.Json())["bodies"]); })
      .def_prop_ro("joints",
                   [](const Description& d) { return nb::object(FromJson(d.Json())["joints"]); })
      .def_prop_ro("actuators",
                   [](const Description& d) { return nb::object(FromJson(d.Json())["actuators"]); })
      .def_prop_ro("sensors",
                   [](const Description& d) { return nb::object(FromJson(d.Json())["sensors"]); })
      .def_prop_ro("delays",
                   [](const Description& d) { return nb::object(FromJson(d.Json())["delays"]); })
      .def_prop_ro("roles",
                   [](const Description& d) { return nb::object(FromJson(d.Json())["roles"]); })
      .def_prop_ro("units",
                   [](const Description& d) { return nb::object(FromJson(d.Json())["units"]); })
      .def("to_json", &Description::Json, "the JSON `plumb inspect --format json` prints")
      .def(
          "to_dict", [](const Description& d) { return FromJson(d.Json()); },
          "to_json() as Python objects")
      .def(
          "to_pandas",
          [](const Description& d, const std::string& table) {
            nb::object rows = FromJson(d.Json());
            if (table != "bodies" && table != "joints" && table != "actuators" &&
                table != "sensors" && table != "delays" && table != "roles") {
              throw ArgumentError("table", Quoted(table),
                                  "give bodies, joints, actuators, sensors, delays or roles");
            }
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
        std::shared_ptr<PyModel> pm = ToModel(model);
        std::vector<std::string> sets = SetTexts(set);
        MujocoCallScope scope;
        std::vector<Assignment> start = pm->Start(sets);
        d->owner = pm;
        d->model = pm->EditableFor(start);
        if (!start.empty()) {
          Data data(*d->model);
          ApplyAssignments(*d->model, data, start);
        }
        d->description = Describe(*d->model);
        return d;
      },
      nb::arg("model"), nb::arg("set") = nb::none(),
      "Describes the model (plumb inspect): sizes, options, bodies, joints, actuators, sensors, "
      "delays and what is a parameter, state, input or derived, with units. `set` edits a copy "
      "first. Returns a Description.");
}

// plumb.Frames: the pictures of a run, in one frames x height x width x 3 uint8 array.
struct Frames {
  std::shared_ptr<PyModel> owner;  // keeps a wrapped MjModel alive as long as `model`
  std::shared_ptr<Model> model;
  nb::object array;
  const std::uint8_t* rgb = nullptr;
  long frames = 0;
  int width = 0, height = 0;
  double fps = 0;
  std::vector<double> times;
  std::string how;  // renderer and camera
  RunResult result;
  std::string html;

  Image Frame(long k) const {
    if (k < 0) k += frames;
    if (k < 0 || k >= frames) {
      throw ArgumentError("frame", std::to_string(k), fmt::format("there are {} frames", frames));
    }
    Image image;
    image.width = width;
    image.height = height;
    std::size_t size = static_cast<std::size_t>(width) * height * 3;
    image.rgb.assign(rgb + k * size, rgb + (k + 1) * size);
    return image;
  }
};

// What a Frames drew (the CLI's render prints no JSON, only this in its closing line).
nb::dict FramesDict(const Frames& f) {
  nb::dict d;
  d["frames"] = f.frames;
  d["width"] = f.width;
  d["height"] = f.height;
  d["fps"] = f.fps;
  d["times"] = nb::cast(f.times);
  d["renderer"] = f.how;
  d["diverged"] = f.result.diverged;
  return d;
}

bool EndsWith(const std::string& text, const std::string& end) {
  return text.size() >= end.size() && text.compare(text.size() - end.size(), end.size(), end) == 0;
}

// Writes frames to `path`: a .mp4 of every frame, or a .png of frame `frame`.
void SaveFrames(const Frames& f, const std::string& path, long frame) {
  if (EndsWith(path, ".png")) {
    WritePng(f.Frame(frame), path);
    return;
  }
  if (!EndsWith(path, ".mp4")) {
    throw ArgumentError("path", Quoted(path), "write a picture (.png) or a video (.mp4)");
  }
  VideoWriter writer(path, f.width, f.height, f.fps);
  for (long k = 0; k < f.frames; ++k) writer.Add(f.Frame(k));
  writer.Finish();
}

// A uint8 numpy array of `shape` that takes over `pixels` without copying.
nb::object Pixels(std::vector<std::uint8_t>&& pixels, std::vector<std::size_t> shape) {
  auto* owned = new std::vector<std::uint8_t>(std::move(pixels));
  nb::capsule owner(owned,
                    [](void* p) noexcept { delete static_cast<std::vector<std::uint8_t>*>(p); });
  return nb::cast(
      nb::ndarray<nb::numpy, std::uint8_t>(owned->data(), shape.size(), shape.data(), owner));
}

// Copies the state of a mujoco.MjData of the same model into `data` (reads it only).
void CopyMjData(const Model& model, nb::handle state, Data& data) {
  if (nb::hasattr(state, "model")) {
    nb::object m = state.attr("model");
    for (const char* size : {"nq", "nv", "na", "nu", "nbody", "nmocap"}) {
      long theirs = nb::cast<long>(m.attr(size));
      long ours = size == std::string("nq")      ? model->nq
                  : size == std::string("nv")    ? model->nv
                  : size == std::string("na")    ? model->na
                  : size == std::string("nu")    ? model->nu
                  : size == std::string("nbody") ? model->nbody
                                                 : model->nmocap;
      if (theirs != ours) {
        throw ArgumentError(
            "state", "MjData",
            fmt::format("it belongs to another model ({} {}, the model's {})", size, theirs, ours));
      }
    }
  }
  auto* source = reinterpret_cast<const mjData*>(nb::cast<std::uintptr_t>(state.attr("_address")));
  std::vector<mjtNum> buffer(
      static_cast<std::size_t>(mj_stateSize(model.get(), mjSTATE_INTEGRATION)));
  mj_getState(model.get(), source, buffer.data(), mjSTATE_INTEGRATION);
  mj_setState(model.get(), data.get(), buffer.data(), mjSTATE_INTEGRATION);
  data.Forward();
}

bool IsMjData(nb::handle value) {
  std::string name = nb::type_name(value.type()).c_str();
  return name == "mujoco._structs.MjData" || name == "MjData";
}

void BindRender(nb::module_& m) {
  nb::class_<Frames>(m, "Frames",
                     "plumb.render's pictures of a run: .array, frames x height x width x 3 "
                     "uint8; .times (s), .fps; save('run.mp4') writes the video, "
                     "save('last.png', frame=-1) one frame.")
      .def_prop_ro("array", [](const Frames& f) { return f.array; })
      .def_prop_ro(
          "times", [](const Frames& f) { return Array(f.times); }, "the time of each frame, s")
      .def_prop_ro("fps", [](const Frames& f) { return f.fps; })
      .def_prop_ro("diverged", [](const Frames& f) { return f.result.diverged; })
      .def("__len__", [](const Frames& f) { return f.frames; })
      .def(
          "__getitem__",
          [](const Frames& f, long k) { return f.array[nb::int_(k < 0 ? k + f.frames : k)]; },
          nb::arg("frame"))
      .def(
          "save",
          [](const Frames& f, FileArg path, long frame) {
            std::string file = PathArg(path);
            RunLong([&](StopToken) {
              SaveFrames(f, file, frame);
              return 0;
            });
          },
          nb::arg("path"), nb::arg("frame") = -1,
          "writes an MP4 video of every frame (H.264 by ffmpeg, at .fps), or a PNG of one "
          "frame (the last by default), whole or not at all")
      .def("to_dict", &FramesDict,
           "what was drawn (the CLI's render prints no JSON): frames, width, height, fps, "
           "times, renderer, diverged")
      .def(
          "to_json",
          [](const Frames& f) {
            return nb::cast<std::string>(
                nb::module_::import_("json").attr("dumps")(FramesDict(f), nb::arg("indent") = 2));
          },
          "to_dict() as JSON text")
      .def(
          "_repr_html_",
          [](Frames& f) {
            if (f.html.empty()) {
              f.html = RunLong([&](StopToken) {
                return ReportHtml([&](const std::string& path) {
                  WriteRenderReport(path, *f.model, f.rgb, f.frames, f.width, f.height, f.fps,
                                    PythonReportInfo("render", false));
                });
              });
            }
            return f.html;
          },
          "an HTML page playing the frames")
      .def("__repr__", [](const Frames& f) {
        return fmt::format(
            "<plumb.Frames {} frames of {}x{} at {:.4g} fps, t = {:g} to {:g} s, {}{}>", f.frames,
            f.width, f.height, f.fps, f.times.empty() ? 0 : f.times.front(),
            f.times.empty() ? 0 : f.times.back(), f.how, f.result.diverged ? ", diverged" : "");
      });

  m.def(
      "render",
      [](ModelArg model, StateArg state_arg, std::string camera, int width, int height, SetArg set,
         std::optional<std::string> keyframe, double at, std::optional<double> until, double fps,
         StringsArg highlight, bool msaa, int shadow_size, std::string gl,
         std::optional<FileArg> output) -> nb::object {
        nb::handle state = state_arg.object;
        std::shared_ptr<PyModel> pm = ToModel(model);
        std::vector<std::string> sets = SetTexts(set);
        RenderOptions options;
        try {
          std::tie(options.width, options.height) =
              ParseImageSize(fmt::format("{}x{}", width, height));
        } catch (const ArgumentError& e) {
          bool bad_width = width < 1 || width > 8192;
          throw ArgumentError(bad_width ? "width" : "height",
                              std::to_string(bad_width ? width : height), "give 1 to 8192 pixels");
        }
        options.camera = camera;
        options.highlight = StringList(highlight, "highlight");
        options.msaa = msaa;
        options.shadow_size = shadow_size;
        options.backend = gl;
        bool trajectory = nb::isinstance<Trajectory>(state);
        bool mjdata = IsMjData(state);
        if (!state.is_none() && !trajectory && !mjdata) {
          throw nb::type_error("state: expected None, a mujoco.MjData or a plumb.Trajectory");
        }
        if ((mjdata || trajectory) && (until || at != 0 || !sets.empty() || keyframe)) {
          const char* given = until ? "until" : at != 0 ? "at" : keyframe ? "keyframe" : "set";
          throw ArgumentError(given, "",
                              "a given state is drawn as it is: leave until, at, set and "
                              "keyframe out (or draw from the start without state)");
        }
        if (until && at != 0)
          throw ArgumentError("at", "", "at is for pictures; a video starts at t = 0");
        std::string out = OptionalPathArg(output);
        const Trajectory* samples = trajectory ? nb::inst_ptr<Trajectory>(state) : nullptr;
        auto f = std::make_shared<Frames>();
        f->width = options.width;
        f->height = options.height;
        std::vector<std::uint8_t> pixels;
        std::vector<Assignment> start;
        std::unique_ptr<Data> owned;
        {
          MujocoCallScope scope;
          start = CallStart(*pm, keyframe, "", QposArg{nb::none()}, sets);
          f->owner = samples ? samples->model : pm;
          f->model = samples ? samples->ran : pm->EditableFor(start);
          owned = std::make_unique<Data>(*f->model);
          if (mjdata) CopyMjData(*f->model, state, *owned);
        }
        Data& data = *owned;
        std::size_t size = static_cast<std::size_t>(f->width) * f->height * 3;
        RunLong([&](StopToken stop) {
          if (!mjdata && !samples) ApplyAssignments(*f->model, data, start);
          Renderer renderer(*f->model, options);
          f->how = fmt::format("{}, camera {}", renderer.backend(), renderer.camera());
          double dt = (*f->model)->opt.timestep;
          auto add = [&](const Image& frame) {
            pixels.insert(pixels.end(), frame.rgb.begin(), frame.rgb.end());
            f->times.push_back(data->time);
            ++f->frames;
          };
          if (samples) {
            pixels.reserve(size * samples->rows);
            try {
              RenderSamples(*f->model, data, renderer, samples->columns, samples->values,
                            samples->rows, stop, add);
            } catch (const ArgumentError&) {
              throw;
            } catch (const ValueError& e) {
              throw ArgumentError("state", "Trajectory", e.what());
            }
            f->fps = 1.0 / samples->every;
          } else if (until) {
            FilmPlan plan = PlanFilm(dt, *until, fps);
            pixels.reserve(size * plan.frames);
            f->fps = plan.fps;
            f->result = RenderFilm(*f->model, data, renderer, plan, stop, add);
          } else {
            Image picture;
            f->result = RenderAt(*f->model, data, renderer, at, stop, &picture);
            if (f->result.diverged) {
              throw ValueError(fmt::format(
                  "the run diverged at t = {:.6g} s: {}. Render an earlier "
                  "`at` to see the state before it.",
                  f->result.steps * dt, f->result.divergence ? f->result.divergence->reason : ""));
            }
            add(picture);
          }
          TakeMujocoWarnings();
          return 0;
        });
        bool sequence = samples != nullptr || until.has_value();
        f->rgb = pixels.data();
        if (!sequence) {
          nb::object image = Pixels(std::move(pixels), {static_cast<std::size_t>(f->height),
                                                        static_cast<std::size_t>(f->width), 3});
          if (!out.empty()) {
            f->array = image;
            RunLong([&](StopToken) {
              SaveFrames(*f, out, 0);
              return 0;
            });
          }
          return image;
        }
        f->array = Pixels(std::move(pixels),
                          {static_cast<std::size_t>(f->frames), static_cast<std::size_t>(f->height),
                           static_cast<std::size_t>(f->width), 3});
        if (!out.empty()) {
          RunLong([&](StopToken) {
            SaveFrames(*f, out, -1);
            return 0;
          });
        }
        return nb::cast(f);
      },
      nb::arg("model"), nb::arg("state") = nb::none(), nb::arg("camera") = "auto",
      nb::arg("width") = 640, nb::arg("height") = 480, nb::arg("set") = nb::none(),
      nb::arg("keyframe") = nb::none(), nb::arg("at") = 0.0, nb::arg("until") = nb::none(),
      nb::arg("fps") = 30.0, nb::arg("highlight") = nb::none(), nb::arg("msaa") = false,
      nb::arg("shadow_size") = 0, nb::arg("gl") = "auto", nb::arg("output") = nb::none(),
      "Draws the model without a window (plumb render). A picture, as a height x width x 3 "
      "uint8 numpy array: of the start (`set`, `keyframe`), of the state a run reaches at `at` "
      "s, or of `state`, a mujoco.MjData of this model (read, not changed). A sequence, as "
      "plumb.Frames: the run to `until` s at about `fps` frames per second, or each sample of "
      "a plumb.Trajectory (`state`). `output` also writes the PNG or MP4. camera: auto, track, "
      "fixed or a camera's name; highlight: bodies, geoms or joints to colour. Raises "
      "plumb.UnavailableError when this machine cannot render.");
}

}  // namespace

void BindRun(nb::module_& m) {
  BindTrajectory(m);
  BindRunCall(m);
  BindInspect(m);
  BindRender(m);
}

}  // namespace plumb::python
