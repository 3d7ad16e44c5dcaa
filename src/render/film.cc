// Pictures and videos of runs (include/plumb/render.h): what `plumb render` and the Python
// module's plumb.render draw.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "plumb/error.h"
#include "plumb/render.h"
#include "plumb/timing.h"

namespace plumb {

std::pair<int, int> ParseImageSize(const std::string& text) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') ||
      w < 1 || h < 1 || w > 8192 || h > 8192) {
    throw ArgumentError("size", Quoted(text),
                        "give WIDTHxHEIGHT in pixels, each 1 to 8192, e.g. 640x480");
  }
  return {w, h};
}

RunResult RenderAt(const Model& model, Data& data, Renderer& renderer, double at, StopToken stop,
                   Image* image) {
  double dt = model->opt.timestep;
  RunSpec spec;
  spec.every = dt;
  spec.until = RequireStepsToReach(at, dt, "at") * dt;
  spec.stop = stop;
  NullSink sink;
  RunResult result = Run(model, data, spec, sink);
  if (result.diverged) return result;
  // after mj_step the positions still describe the state before it: draw the one reached
  if (result.steps > 0) RefreshDerived(model, data);
  renderer.Render(data, image);
  return result;
}

FilmPlan PlanFilm(double timestep, double until, double fps) {
  if (!(fps > 0) || !std::isfinite(fps) || fps > 1000) {
    throw ArgumentError("fps", fmt::format("{:g}", fps), "give a frame rate above 0, at most 1000");
  }
  FilmPlan plan;
  plan.steps = RequireStepsToReach(until, timestep, "until");
  plan.stride = std::max(1L, std::lround(1.0 / (fps * timestep)));
  plan.fps = 1.0 / (plan.stride * timestep);
  plan.frames = plan.steps / plan.stride + 1;
  return plan;
}

RunResult RenderFilm(const Model& model, Data& data, Renderer& renderer, const FilmPlan& plan,
                     StopToken stop, const std::function<void(const Image&)>& add) {
  double dt = model->opt.timestep;
  Image frame;
  renderer.Render(data, &frame);
  add(frame);
  RunSpec spec;
  spec.every = dt;
  spec.until = plan.steps * dt;
  spec.stop = stop;
  DerivedRefresher refresh(model);
  spec.after_step = [&](const mjData*, long step) {
    if (step % plan.stride == 0) {
      // after mj_step the positions still describe the state before it: the frame shows this one
      refresh(data);
      renderer.Render(data, &frame);
      add(frame);
    }
  };
  NullSink sink;
  return Run(model, data, spec, sink);
}

void RenderSamples(Model& model, Data& data, Renderer& renderer, const std::vector<Path>& columns,
                   const double* values, long rows, StopToken stop,
                   const std::function<void(const Image&)>& add) {
  long qpos = 0;
  for (const Path& p : columns) qpos += p.field == "qpos" ? p.count : 0;
  if (qpos < model->nq) {
    throw ValueError(
        fmt::format("the samples hold {} of the {} qpos elements; to draw them, "
                    "sample every one (the default columns do)",
                    qpos, model->nq));
  }
  std::size_t width = columns.size();
  Image frame;
  for (long r = 0; r < rows; ++r) {
    if (stop.stop_requested()) {
      throw Interrupted(fmt::format("interrupted drawing sample {} of {}", r, rows));
    }
    for (std::size_t c = 0; c < width; ++c) {
      const Path& p = columns[c];
      if (p.writable && (p.role == Role::kState || p.role == Role::kInput)) {
        WriteValues(model, data, p, {values[r * width + c]});
      }
    }
    data.Forward();
    renderer.Render(data, &frame);
    add(frame);
  }
}

}  // namespace plumb
