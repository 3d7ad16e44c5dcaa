// plumb.render: pictures of the model as uint8 numpy arrays, and plumb.Frames, a run's
// pictures, which save to PNG or MP4.

#include "plumb/render.h"

#include <fmt/format.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "common.h"
#include "plumb/error.h"
#include "plumb/image.h"
#include "plumb/report.h"
#include "plumb/timing.h"
#include "plumb/video.h"
#include "trajectory.h"

PLUMB_PYTHON_ARG(StateArg, "mujoco.MjData | Trajectory")

namespace plumb::python {
namespace {

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

void BindFrames(nb::module_& m) {
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
            std::string file = PathArg(path, "path");
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
}

// What a render call draws, checked before anything is drawn.
struct RenderRequest {
  std::shared_ptr<PyModel> model;
  RenderOptions options;
  const Trajectory* samples = nullptr;  // state= a plumb.Trajectory: each sample
  nb::handle mjdata;                    // state= a mujoco.MjData: its state as it is
  std::vector<Assignment> start;        // else the start (keyframe, set) ...
  double at = 0;                        // ... run to `at` s for a picture
  std::optional<double> until;          // ... or filmed to `until` s
  double fps = 30;
  bool sequence() const { return samples != nullptr || until.has_value(); }
};

RenderOptions ReadRenderOptions(const std::string& camera, int width, int height,
                                StringsArg highlight, bool msaa, int shadow_size,
                                const std::string& gl) {
  RenderOptions options;
  try {
    std::tie(options.width, options.height) = ParseImageSize(fmt::format("{}x{}", width, height));
  } catch (const ArgumentError&) {
    bool bad_width = width < 1 || width > 8192;
    throw ArgumentError(bad_width ? "width" : "height", std::to_string(bad_width ? width : height),
                        "give 1 to 8192 pixels");
  }
  options.camera = camera;
  options.highlight = StringList(highlight, "highlight");
  options.msaa = msaa;
  options.shadow_size = shadow_size;
  options.backend = gl;
  return options;
}

// Which state is drawn: a given one (an MjData, a Trajectory's samples) is drawn as it is, so
// the arguments that make a start or a run are refused beside it.
void ReadState(nb::handle state, const std::vector<std::string>& sets,
               const std::optional<std::string>& keyframe, RenderRequest* r) {
  bool trajectory = nb::isinstance<Trajectory>(state);
  bool mjdata = IsMjData(state);
  if (!state.is_none() && !trajectory && !mjdata) {
    throw nb::type_error("state: expected None, a mujoco.MjData or a plumb.Trajectory");
  }
  if ((mjdata || trajectory) && (r->until || r->at != 0 || !sets.empty() || keyframe)) {
    const char* given = r->until ? "until" : r->at != 0 ? "at" : keyframe ? "keyframe" : "set";
    throw ArgumentError(given, "",
                        "a given state is drawn as it is: leave until, at, set and keyframe out "
                        "(or draw from the start without state)");
  }
  if (r->until && r->at != 0) {
    throw ArgumentError("at", "", "at is for pictures; a video starts at t = 0");
  }
  if (trajectory) r->samples = nb::inst_ptr<Trajectory>(state);
  if (mjdata) r->mjdata = state;
}

// Draws what `r` asks into `f` (its pictures one after the other in `pixels`).
void Draw(const RenderRequest& r, Frames* f, std::vector<std::uint8_t>* pixels) {
  std::unique_ptr<Data> owned;
  {
    MujocoCallScope scope;
    f->owner = r.samples ? r.samples->model : r.model;
    f->model = r.samples ? r.samples->ran : r.model->EditableFor(r.start);
    owned = std::make_unique<Data>(*f->model);
    if (r.mjdata) CopyMjData(*f->model, r.mjdata, *owned);
  }
  Data& data = *owned;
  std::size_t size = static_cast<std::size_t>(f->width) * f->height * 3;
  RunLong([&](StopToken stop) {
    if (!r.mjdata && !r.samples) ApplyAssignments(*f->model, data, r.start);
    Renderer renderer(*f->model, r.options);
    f->how = fmt::format("{}, camera {}", renderer.backend(), renderer.camera());
    double dt = (*f->model)->opt.timestep;
    auto add = [&](const Image& frame) {
      pixels->insert(pixels->end(), frame.rgb.begin(), frame.rgb.end());
      f->times.push_back(data->time);
      ++f->frames;
    };
    if (r.samples) {
      pixels->reserve(size * r.samples->rows);
      try {
        RenderSamples(*f->model, data, renderer, r.samples->columns, r.samples->values,
                      r.samples->rows, stop, add);
      } catch (const ArgumentError&) {
        throw;
      } catch (const ValueError& e) {
        throw ArgumentError("state", "Trajectory", e.what());
      }
      f->fps = 1.0 / r.samples->every;
    } else if (r.until) {
      FilmPlan plan = PlanFilm(dt, *r.until, r.fps);
      // every frame is kept in the array: refuse a film this machine cannot hold
      RequireMemoryFor(
          static_cast<double>(size) * plan.frames,
          fmt::format("the {} frames of {}x{} pixels", plan.frames, f->width, f->height), "until",
          fmt::format("{:g}", *r.until));
      pixels->reserve(size * plan.frames);
      f->fps = plan.fps;
      f->result = RenderFilm(*f->model, data, renderer, plan, stop, add);
    } else {
      Image picture;
      f->result = RenderAt(*f->model, data, renderer, r.at, stop, &picture);
      if (f->result.diverged) {
        throw ValueError(fmt::format(
            "the run diverged at t = {:.6g} s: {}. Render an earlier `at` to see the state "
            "before it.",
            f->result.steps * dt, f->result.divergence ? f->result.divergence->reason : ""));
      }
      add(picture);
    }
    TakeMujocoWarnings();
    return 0;
  });
}

// render(model, state, camera, width, height) as plumb 0.1 took them: camera, width and height
// are keyword-only now (mujoco.Renderer takes height before width), and the old positional use
// still works, with a FutureWarning.
void ReadPositional(const nb::args& positional, NameOrId* camera, int* width, int* height) {
  if (positional.size() == 0) return;
  if (positional.size() > 3) {
    throw nb::type_error(
        fmt::format("render() takes model and state by position, and {} more were given: give "
                    "the rest by keyword (camera=, width=, height=, ...)",
                    positional.size())
            .c_str());
  }
  const char* names[] = {"camera", "width", "height"};
  if (PyErr_WarnEx(PyExc_FutureWarning,
                   "render(): give camera, width and height by keyword (width=640, "
                   "height=480): they are keyword-only, as mujoco.Renderer(model, height, "
                   "width) takes the size the other way round",
                   1) != 0) {
    throw nb::python_error();
  }
  RenderOptions defaults;
  for (std::size_t k = 0; k < positional.size(); ++k) {
    bool twice = k == 0   ? camera->text != defaults.camera
                 : k == 1 ? *width != defaults.width
                          : *height != defaults.height;
    if (twice) {
      throw nb::type_error(
          fmt::format("render(): {} given twice, by position and by keyword", names[k]).c_str());
    }
    bool ok = k == 0 ? nb::try_cast(positional[k], *camera)
                     : nb::try_cast(positional[k], k == 1 ? *width : *height);
    if (!ok) {
      throw nb::type_error(fmt::format("render(): {} expects {}, not {}", names[k],
                                       k == 0 ? "str | int" : "int",
                                       nb::type_name(positional[k].type()).c_str())
                               .c_str());
    }
  }
}

nb::object Render(ModelArg model, StateArg state, const nb::args& positional, NameOrId camera,
                  int width, int height, SetArg set, std::optional<NameOrId> keyframe, double at,
                  std::optional<double> until, double fps, StringsArg highlight, bool msaa,
                  int shadow_size, std::string gl, std::optional<FileArg> output) {
  ReadPositional(positional, &camera, &width, &height);
  RenderRequest r;
  CallNotices notices;
  r.model = ToModel(model, notices.sink());
  r.options = ReadRenderOptions(camera, width, height, highlight, msaa, shadow_size, gl);
  r.at = at;
  r.until = until;
  r.fps = fps;
  std::vector<std::string> sets = SetTexts(set);
  ReadState(state.object, sets, keyframe, &r);
  {
    MujocoCallScope scope;
    r.start = StartAssignments(r.model->model(), r.model->Spec(keyframe, "", "", sets),
                               notices.sink());
  }
  notices.Issue();
  std::string out = OptionalPathArg(output, "output");
  internal::RefuseOutputsOntoInputs({{"output", out}}, {{"the model", r.model->name()}});
  auto f = std::make_shared<Frames>();
  f->width = r.options.width;
  f->height = r.options.height;
  std::vector<std::uint8_t> pixels;
  Draw(r, f.get(), &pixels);
  f->rgb = pixels.data();
  auto h = static_cast<std::size_t>(f->height), w = static_cast<std::size_t>(f->width);
  f->array = r.sequence()
                 ? OwnedArray(std::move(pixels), {static_cast<std::size_t>(f->frames), h, w, 3})
                 : OwnedArray(std::move(pixels), {h, w, 3});
  if (!out.empty()) {
    RunLong([&](StopToken) {
      SaveFrames(*f, out, r.sequence() ? -1 : 0);
      return 0;
    });
  }
  return r.sequence() ? nb::cast(f) : f->array;
}

}  // namespace

void BindRender(nb::module_& m) {
  BindFrames(m);
  m.def("render", &Render, nb::arg("model"), nb::arg("state") = nb::none(), nb::arg("args"),
        nb::arg("camera") = NameOrId{RenderOptions{}.camera}, nb::arg("width") = RenderOptions{}.width,
        nb::arg("height") = RenderOptions{}.height, nb::arg("set") = nb::none(),
        nb::arg("keyframe") = nb::none(), nb::arg("at") = kPictureTime,
        nb::arg("until") = nb::none(), nb::arg("fps") = kFilmFps, nb::arg("highlight") = nb::none(),
        nb::arg("msaa") = RenderOptions{}.msaa,
        nb::arg("shadow_size") = RenderOptions{}.shadow_size,
        nb::arg("gl") = RenderOptions{}.backend, nb::arg("output") = nb::none(),
        "Draws the model without a window (plumb render). A picture, as a height x width x 3 "
        "uint8 numpy array: of the start (`set`, `keyframe`), of the state a run reaches at `at` "
        "s, or of `state`, a mujoco.MjData of this model (read, not changed). A sequence, as "
        "plumb.Frames: the run to `until` s at about `fps` frames per second, or each sample of "
        "a plumb.Trajectory (`state`). `output` also writes the PNG or MP4. camera: a camera of "
        "the model by name or id, else auto, track or fixed (plumb:track etc. always mean "
        "plumb's own); width and height by keyword; highlight: bodies, geoms or joints to "
        "colour. Raises "
        "plumb.UnavailableError when this machine cannot render.");
}

}  // namespace plumb::python
