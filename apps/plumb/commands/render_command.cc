// plumb render: a picture (PNG) of the model at one time, or a video (MP4) of a run,
// without a window.

#include <fmt/format.h>

#include <cstdio>
#include <optional>

#include "cli_common.h"
#include "plumb/error.h"
#include "plumb/image.h"
#include "plumb/render.h"
#include "plumb/run.h"
#include "plumb/video.h"

namespace plumb::cli {
using internal::RefuseOutputsOntoInputs;

namespace {

struct RenderCommandOptions {
  std::string model;
  std::vector<std::string> sets;
  std::string keyframe;
  StartPose pose;
  double at = kPictureTime;
  std::optional<double> until;
  double fps = kFilmFps;
  std::string camera = RenderOptions{}.camera;
  std::string size = fmt::format("{}x{}", RenderOptions{}.width, RenderOptions{}.height);
  std::vector<std::string> highlight;
  bool msaa = RenderOptions{}.msaa;
  int shadow_size = RenderOptions{}.shadow_size;
  std::string gl = RenderOptions{}.backend;
  std::string output;
};

bool EndsWith(const std::string& text, const std::string& end) {
  return text.size() >= end.size() && text.compare(text.size() - end.size(), end.size(), end) == 0;
}

void SayDiverged(const RunResult& result, double dt, const std::string& shown) {
  std::fprintf(stderr, "plumb: the run diverged at t = %.6g s: %s. %s\n", result.steps * dt,
               result.divergence ? result.divergence->reason.c_str() : "", shown.c_str());
}

int RunRender(const RenderCommandOptions& o) {
  RefuseOutputsOntoInputs({{"-o", o.output}}, ModelInputs(o.model, o.pose));
  bool video = EndsWith(o.output, ".mp4");
  if (!video && !EndsWith(o.output, ".png")) {
    throw ValueError("-o '" + o.output + "': write a picture (.png) or a video (.mp4)");
  }
  if (video != o.until.has_value()) {
    throw ValueError(video ? "a video needs --until T (and --fps F): how long a run to show"
                           : "--until makes a video: write it to a .mp4 file, or use --at T "
                             "for one picture");
  }
  if (video && o.at != 0) throw ValueError("--at is for pictures; a video starts at t = 0");
  auto [width, height] = ParseImageSize(o.size);
  Model model = LoadModel(o.model);
  Data data(model);
  ApplyAssignments(model, data, StartAssignments(model, o.keyframe, o.pose, o.sets));
  data.Forward();
  RenderOptions options;
  options.width = width;
  options.height = height;
  options.camera = o.camera;
  options.highlight = o.highlight;
  options.msaa = o.msaa;
  options.shadow_size = o.shadow_size;
  options.backend = o.gl;
  Renderer renderer(model, options);
  double dt = model->opt.timestep;
  StopToken stop = CommandStop().token();
  std::string how = fmt::format("{}x{}, {}, camera {}{}", width, height, renderer.backend(),
                                renderer.camera(), o.msaa ? ", MSAA" : "");
  if (!video) {
    Image picture;
    RunResult result = RenderAt(model, data, renderer, o.at, stop, &picture);
    TakeMujocoWarnings();
    if (result.diverged) {
      SayDiverged(result, dt,
                  "Nothing was written: render an earlier --at to see the state "
                  "before it.");
      return kExitDiverged;
    }
    WritePng(picture, o.output);
    std::printf("plumb: wrote %s: t = %.6g s, %s\n", o.output.c_str(), data->time, how.c_str());
    return kExitOk;
  }
  FilmPlan plan = PlanFilm(dt, *o.until, o.fps);
  VideoWriter writer(o.output, width, height, plan.fps);
  RunResult result =
      RenderFilm(model, data, renderer, plan, stop, [&](const Image& frame) { writer.Add(frame); });
  TakeMujocoWarnings();
  writer.Finish();
  std::printf("plumb: wrote %s: %d frames at %.4g fps (every %ld steps), t = 0 to %.6g s, %s\n",
              o.output.c_str(), writer.frames(), plan.fps, plan.stride, result.steps * dt,
              how.c_str());
  if (result.diverged) {
    SayDiverged(result, dt, "The video shows the run up to the last good state.");
    return kExitDiverged;
  }
  return kExitOk;
}

}  // namespace

void SetupRenderCommand(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<RenderCommandOptions>();
  CLI::App* cmd = AddCommand(
      app, "render", "Draw the model without a window: a PNG at one time, or an MP4 of a run",
      "Examples:\n"
      "  plumb render models/pendulum.xml --set 'qpos[hinge]=0.7' -o pendulum.png\n"
      "  plumb render models/pendulum.xml --set 'qpos[hinge]=0.7' --until 4 --fps 30 -o swing.mp4\n"
      "  plumb render humanoid.xml --at 1.5 --camera track --highlight torso -o fall.png\n"
      "MuJoCo's OpenGL renderer runs on Mesa through EGL (surfaceless), else OSMesa; the\n"
      "output line says which ran. Videos are H.264 (yuv420p) made by ffmpeg.\n"
      "Exit codes: 0 ok, 2 bad input, 3 the run diverged, 4 MuJoCo fatal error,\n"
      "5 no renderer in this build, no GL context, or no ffmpeg.");
  AddModelOptions(cmd, &o->model, &o->sets, "before the run");
  AddKeyframeOption(cmd, &o->keyframe);
  AddStartPoseOptions(cmd, &o->pose);
  cmd->add_option("--at", o->at, "time of the picture, s (a PNG)")->capture_default_str();
  cmd->add_option_function<double>(
      "--until", [o](double v) { o->until = v; }, "length of the run a video shows, s (an MP4)");
  cmd->add_option("--fps", o->fps, "video frames per second (rounded to whole steps)")
      ->capture_default_str();
  cmd->add_option("--camera", o->camera,
                  "a camera of the model (its name, or #ID), else auto, track (follow a free "
                  "body's centre of mass) or fixed (frame the whole model); plumb:track etc. "
                  "always mean plumb's own")
      ->capture_default_str();
  cmd->add_option("--size", o->size, "WIDTHxHEIGHT in pixels")->capture_default_str();
  cmd->add_option("--highlight", o->highlight,
                  "colour a body, geom or joint so it stands out (repeatable)");
  cmd->add_flag("--msaa", o->msaa, "multisample anti-aliasing (off: slow on a software GL)");
  cmd->add_option("--shadow-size", o->shadow_size,
                  "shadow map side in texels (0: the model's, MuJoCo's default 4096; 1024 draws "
                  "several times faster on a software GL)")
      ->capture_default_str()
      ->check(CLI::Range(0, 8192));
  cmd->add_option("--gl", o->gl, "GL backend: auto (EGL, else OSMesa), egl or osmesa")
      ->check(CLI::IsMember({"auto", "egl", "osmesa"}))
      ->capture_default_str();
  cmd->add_option("-o,--output", o->output, "the picture (.png) or video (.mp4) to write")
      ->required();
  cmd->callback([o, &ctx] { ctx.action = [o] { return RunRender(*o); }; });
}

}  // namespace plumb::cli
