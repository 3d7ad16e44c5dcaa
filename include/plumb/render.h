// Pictures of a model without a window: MuJoCo's classic OpenGL renderer (mjv_ / mjr_)
// running offscreen on a headless GL context from Debian's Mesa.
//
// The context comes from EGL on Mesa's surfaceless platform (the default: no X server, no
// device file) or, when that cannot be made, from OSMesa (Mesa's software renderer behind
// its own API). MuJoCo's GL loader binds to one of them per process, so the first Renderer
// of a process fixes the backend; later ones share it. backend() says which one ran.
//
// The renderer is an optional part of the build (PLUMB_WITH_RENDER). Without it, or when no
// GL context can be made, constructing a Renderer throws UnavailableError saying so.
//
// Example:
//   plumb::RenderOptions options;            // 640x480, camera chosen for the model
//   options.highlight = {"pole"};            // colour a body so it stands out
//   plumb::Renderer renderer(model, options);
//   data.Forward();
//   plumb::WritePng(renderer.Render(data), "pendulum.png");
//
// Thread-safety: use a Renderer from one thread at a time: Render makes its GL context current
// on the calling thread (renderers on several threads at once are not tested). Making a context
// fixes the backend under a lock and sets MUJOCO_GL (setenv): construct renderers while no other
// thread reads the environment. `model` is only read; RendererBuilt is pure.

#ifndef PLUMB_INCLUDE_PLUMB_RENDER_H_
#define PLUMB_INCLUDE_PLUMB_RENDER_H_

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "plumb/image.h"
#include "plumb/model.h"
#include "plumb/path.h"
#include "plumb/run.h"
#include "plumb/stop.h"

namespace plumb {

struct RenderOptions {
  int width = 640;  // pixels; the offscreen buffer is made at least this large
  int height = 480;
  // A camera of the model by its name, or by its id as "#2"; else plumb's own: "auto": "track"
  // for a model with a free-floating body, else "fixed"; "track": follow the centre of mass of
  // the first free-floating body's subtree; "fixed": frame the whole model (its bounding
  // sphere) from MuJoCo's default viewpoint. The model's cameras come first (a camera named
  // "track" is the model's); "plumb:auto", "plumb:track" and "plumb:fixed" always name
  // plumb's own (ChooseRenderCamera).
  std::string camera = "auto";
  // Names of bodies, geoms or joints to colour so they stand out (a body's or joint's
  // geoms are coloured; everything else is drawn faded).
  std::vector<std::string> highlight;
  // Multisample anti-aliasing. Off by default: on Mesa's software rasteriser it costs more
  // than it shows; on turns on the model's offsamples (4 unless the model says otherwise).
  bool msaa = false;
  // Side of the shadow map in texels; 0 keeps the model's <visual><quality shadowsize>
  // (MuJoCo's default is 4096, which a software rasteriser clears and draws every frame:
  // most of a small picture's cost). Reports use 1024 for their small pictures.
  int shadow_size = 0;
  // "auto" (EGL surfaceless, else OSMesa), "egl" or "osmesa".
  std::string backend = "auto";
};

class Renderer {
 public:
  // Makes the GL context (or joins the process's), MuJoCo's scene and its render context
  // for `model`, which must outlive the renderer.
  // @throws UnavailableError when this build has no renderer or no GL context can be made;
  //         ValueError for a size below 1 or above 8192 pixels, an unknown camera or
  //         highlight name (the message lists the valid ones), or an unknown backend;
  //         MujocoError when MuJoCo cannot set up its render context on the GL context.
  Renderer(const Model& model, RenderOptions options);
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;
  ~Renderer();

  // Replaces the highlighted elements (as RenderOptions::highlight; empty: none), so one
  // renderer draws many thumbnails. @throws ValueError for an unknown name.
  void Highlight(const std::vector<std::string>& names);

  // Draws the state `data` holds (its positions must be current: after mj_forward or
  // mj_step) into `image`, reusing its buffer. Rows come out top-down.
  // @throws UnavailableError when the GL context cannot be made current again; MujocoError.
  void Render(Data& data, Image* image);
  Image Render(Data& data);

  // "EGL (surfaceless)" or "OSMesa", then the GL renderer string, e.g.
  // "EGL (surfaceless), llvmpipe (LLVM 15.0.6, 256 bits)".
  const std::string& backend() const;
  // The camera in use, said for a person: "tracking body 'torso'", "fixed: whole model",
  // "model camera 'side'".
  const std::string& camera() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The camera RenderOptions::camera names in `model`: a camera of the model (`id` >= 0), else
// plumb's own `builtin` ("auto", "track" or "fixed"). The model's cameras are looked up first,
// by name, then by id ("#2"), so a model camera named "track" can be chosen; plumb's own are
// also named "plumb:auto", "plumb:track", "plumb:fixed", which always mean them.
// @throws ArgumentError naming `camera` for a name that is neither, listing the model's
// cameras; for an id out of range.
struct CameraChoice {
  int id = -1;
  std::string builtin;
};
CameraChoice ChooseRenderCamera(const Model& model, const std::string& camera);
// How a person reads camera `id` of `model`: "'side'", or "#2" when it has no name.
std::string CameraLabel(const Model& model, int id);

// True when this build has the renderer (PLUMB_WITH_RENDER); a GL context may still be
// impossible to make on the machine (then Renderer throws UnavailableError).
bool RendererBuilt();

// "WIDTHxHEIGHT" in pixels ("640x480"), each 1 to 8192.
// @throws ArgumentError (argument "size") otherwise.
std::pair<int, int> ParseImageSize(const std::string& text);

// Steps `data` from its state to `at` s (up to whole timesteps, as RequireStepsToReach) with
// the model's timestep and draws the state it reaches (positions recomputed after the last
// step) into `image`. When the run diverges nothing is drawn (the result says so).
// @throws ArgumentError (argument "at") for a time that is not a finite number >= 0 or is more
// than 2^53 steps; Interrupted when `stop` asks; as Run and Renderer::Render do.
RunResult RenderAt(const Model& model, Data& data, Renderer& renderer, double at, StopToken stop,
                   Image* image);

// The defaults of plumb render's --at and --fps and plumb.render's at= and fps= (the rest are
// RenderOptions'): a picture of the start, a video at about 30 frames per second.
inline constexpr double kPictureTime = 0;  // s
inline constexpr double kFilmFps = 30;

// The frames of a video of a run to `until` s at about `fps` frames per second: frames a whole
// number of steps apart (so the video plays in real time at that spacing), the first at the
// start.
struct FilmPlan {
  long steps = 0;   // of the run
  long stride = 1;  // steps between frames
  double fps = 0;   // the frame rate that spacing gives, 1 / (stride x timestep)
  long frames = 0;  // when the run does not diverge: the start, then every stride-th step
};

// @throws ArgumentError (argument "until") for a time that is not a finite number >= 0 or takes
// more than 2^53 steps (RequireStepsToReach), and
// (argument "fps") for a rate not above 0 or above 1000.
FilmPlan PlanFilm(double timestep, double until, double fps);

// Runs `data` from its state on `plan`'s schedule, drawing a frame at the start and every
// stride-th step and giving each to `add` (the image is reused: copy what you keep). Each
// frame shows the state at its time (positions recomputed after the step, DerivedRefresher). A
// diverged run ends the film at its last good state (the result says so).
// @throws Interrupted when `stop` asks; as Run and Renderer::Render do; what `add` throws.
RunResult RenderFilm(const Model& model, Data& data, Renderer& renderer, const FilmPlan& plan,
                     StopToken stop, const std::function<void(const Image&)>& add);

// Draws each row of a run's samples (as a TrajectorySink keeps them: `rows` rows of
// columns.size() values, row major): the row's state and input columns (time, qpos, qvel, act,
// ctrl, ...) are written into `data`, mj_forward computes the rest, and the frame goes to `add`
// (the image is reused). `model` is written only through `data`'s state.
// @throws ValueError when the columns lack some of qpos (the picture would not show the row);
// Interrupted when `stop` asks; as Renderer::Render does; what `add` throws.
void RenderSamples(Model& model, Data& data, Renderer& renderer, const std::vector<Path>& columns,
                   const double* values, long rows, StopToken stop,
                   const std::function<void(const Image&)>& add);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_RENDER_H_
