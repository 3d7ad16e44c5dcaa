// Report headers, model pictures and the atomic write.

#include "report/page_start.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <ctime>

#include "plumb/atomic_file.h"
#include "plumb/error.h"
#include "plumb/hash.h"
#include "plumb/render.h"
#include "plumb/run.h"
#include "plumb/strings.h"
#include "plumb/version.h"

namespace plumb::report {
namespace {

constexpr int kPictureWidth = 480, kPictureHeight = 360;
constexpr int kThumbWidth = 240, kThumbHeight = 180;
// shadow maps for small pictures: MuJoCo's default 4096 costs a software rasteriser about
// 10 ms a frame to clear and draw, 1024 about a tenth of that, and looks the same at this size
constexpr int kShadowSize = 1024;

// A report's picture: the model's camera choice, the report's shadow map.
RenderOptions SmallPicture(int width, int height) {
  RenderOptions options;
  options.width = width;
  options.height = height;
  options.shadow_size = kShadowSize;
  return options;
}

std::string UtcNow() {
  std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%d %H:%M:%S UTC", &utc);
  return text;
}

std::string CommandLine(const std::vector<std::string>& argv) {
  std::string line;
  for (const std::string& a : argv) line += (line.empty() ? "" : " ") + ShellQuote(a);
  return line;
}

// The model with the start assignments applied, and its data at the start state.
struct Start {
  Model model;
  Data data;
  explicit Start(const Model& original, const std::vector<Assignment>& sets)
      : model(original.Clone()), data(model) {
    ApplyAssignments(model, data, sets);
    data.Forward();
  }
};

}  // namespace

Page StartPage(const std::string& command, const Model& model, const ReportInfo& info) {
  Page page("plumb " + command + " " + model.file());
  page.Meta("model", model.file());
  page.Meta("model hash", HashModel(model));
  page.Meta("plumb", PLUMB_VERSION);
  page.Meta("MuJoCo", MujocoVersion());
  page.Meta("command line", info.argv.empty() ? "(library call)" : CommandLine(info.argv));
  page.Meta("date", UtcNow());
  return page;
}

void AddModelPictures(Page* page, const Model& model, const std::vector<Assignment>& sets,
                      const ReportInfo& info) {
  if (!info.pictures) {
    page->Meta("renderer", "pictures not asked for");
    return;
  }
  try {
    Start start(model, sets);
    // one renderer for the stills and the animation: making one costs as much as several
    // frames of a meshed robot on a software rasteriser (bench/RESULTS.md)
    Renderer renderer(start.model, SmallPicture(kPictureWidth, kPictureHeight));
    page->Meta("renderer", renderer.backend() + "; camera " + renderer.camera());
    std::string first = EncodePng(renderer.Render(start.data));

    const mjModel* m = start.model.get();
    double dt = m->opt.timestep;
    long steps = std::max(1L, std::lround(info.nominal_until / dt));
    long stride = std::max(1L, steps / std::max(1, info.frames));
    std::vector<std::string> frames = {first};
    Image frame;
    RunSpec spec;
    spec.until = steps * dt;
    spec.every = dt * stride;
    spec.after_step = [&](const mjData*, long step) {
      if (step % stride == 0 && info.frames > 0) {
        renderer.Render(start.data, &frame);
        frames.push_back(EncodePng(frame, PngEffort::kFast));
      }
    };
    NullSink sink;
    RunResult result = Run(start.model, start.data, spec, sink);
    TakeMujocoWarnings();
    std::string end_caption =
        result.diverged
            ? fmt::format("diverged at t = {:.4g} s: the last good state", result.steps * dt)
            : fmt::format("t = {:.4g} s, the end of the nominal run", result.steps * dt);
    std::string last = EncodePng(renderer.Render(start.data));
    page->Pictures({{first, "t = 0, the start state"}, {last, end_caption}});
    if (frames.size() < 2) return;
    page->Flipbook(frames, int(std::lround(1000.0 * info.nominal_until / frames.size())),
                   fmt::format("the nominal run, {} frames over {:.3g} s (real time)",
                               frames.size(), result.steps * dt));
  } catch (const UnavailableError& e) {
    page->Meta("renderer", "none");
    page->Paragraph(std::string("No pictures: ") + e.what(), "note");
  }
}

std::vector<std::string> HighlightThumbnails(const Model& model,
                                             const std::vector<Assignment>& sets,
                                             const std::vector<std::string>& elements,
                                             std::string* why) {
  std::vector<std::string> thumbs;
  if (elements.empty()) return thumbs;
  try {
    Start start(model, sets);
    Renderer renderer(start.model, SmallPicture(kThumbWidth, kThumbHeight));
    Image image;
    for (const std::string& name : elements) {
      renderer.Highlight({name});
      renderer.Render(start.data, &image);
      thumbs.push_back(EncodePng(image, PngEffort::kFast));
    }
  } catch (const UnavailableError& e) {
    *why = e.what();
    thumbs.clear();
  }
  return thumbs;
}

void WritePage(const Page& page, const std::string& path) {
  std::string html = page.Render();
  AtomicFile file(path);
  if (std::fwrite(html.data(), 1, html.size(), file.stream()) != html.size()) {
    throw IoError("cannot write the report '" + path + "'");
  }
  file.Commit();
}

}  // namespace plumb::report
