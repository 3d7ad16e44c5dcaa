// Report headers, model pictures and the atomic write.

#include "report/page_start.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <future>
#include <memory>
#include <optional>
#include <thread>
#include <utility>

#include "core/strings.h"
#include "io/atomic_file.h"
#include "io/hash.h"
#include "plumb/error.h"
#include "plumb/render.h"
#include "plumb/run.h"
#include "plumb/version.h"

namespace plumb::report {
using internal::AtomicFile;
using internal::HashModel;
using internal::ShellQuote;

namespace {

constexpr int kPictureWidth = 480, kPictureHeight = 360;
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

// The pictures AddModelPictures puts on a page, drawn (outside the anonymous namespace:
// plumb::PicturesAhead holds them).
struct ModelPictures {
  std::string renderer;     // the header's "renderer" line
  std::string unavailable;  // why there are none ("" when there are)
  std::vector<std::pair<std::string, std::string>> stills;  // PNG, caption
  std::vector<std::string> frames;                          // the animation's PNGs
  int interval_ms = 0;
  std::string animation;  // its caption
};

// Draws the stills and the animation of `info`'s nominal run with `renderer`, from the start
// state in `data` (which it runs on).
ModelPictures DrawModelPictures(Renderer& renderer, const Model& model, Data& data,
                                const ReportInfo& info) {
  ModelPictures out;
  out.renderer = renderer.backend() + "; camera " + renderer.camera();
  std::string first = EncodePng(renderer.Render(data));
  if (info.start_only) {
    out.stills = {{first, "t = 0, the start state"}};
    return out;
  }
  double dt = model->opt.timestep;
  long steps = std::max(1L, std::lround(info.nominal_until / dt));
  long stride = std::max(1L, steps / std::max(1, info.frames));
  std::vector<std::string> frames = {first};
  Image frame;
  RunSpec spec;
  spec.until = steps * dt;
  spec.every = dt * stride;
  spec.after_step = [&](const mjData*, long step) {
    if (step % stride == 0 && info.frames > 0) {
      renderer.Render(data, &frame);
      frames.push_back(EncodePng(frame, PngEffort::kFast));
    }
  };
  NullSink sink;
  RunResult result = Run(model, data, spec, sink);
  std::string end_caption =
      result.diverged
          ? fmt::format("diverged at t = {:.4g} s: the last good state", result.steps * dt)
          : fmt::format("t = {:.4g} s, the end of the nominal run", result.steps * dt);
  std::string last = EncodePng(renderer.Render(data));
  out.stills = {{first, "t = 0, the start state"}, {last, end_caption}};
  if (frames.size() < 2) return out;
  out.interval_ms = int(std::lround(1000.0 * info.nominal_until / frames.size()));
  out.animation = fmt::format("the nominal run, {} frames over {:.3g} s (real time)", frames.size(),
                              result.steps * dt);
  out.frames = std::move(frames);
  return out;
}

// `image` at half its size, each pixel the mean of a 2 x 2 block.
Image Half(const Image& image) {
  Image out;
  out.width = image.width / 2;
  out.height = image.height / 2;
  out.rgb.resize(std::size_t(out.width) * out.height * 3);
  for (int y = 0; y < out.height; ++y) {
    for (int x = 0; x < out.width; ++x) {
      for (int c = 0; c < 3; ++c) {
        int sum = image.at(2 * x, 2 * y)[c] + image.at(2 * x + 1, 2 * y)[c] +
                  image.at(2 * x, 2 * y + 1)[c] + image.at(2 * x + 1, 2 * y + 1)[c];
        out.rgb[(std::size_t(y) * out.width + x) * 3 + c] = std::uint8_t((sum + 2) / 4);
      }
    }
  }
  return out;
}

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

}  // namespace plumb::report

namespace plumb {

// One thread with one renderer (making one costs a meshed robot as much as several frames on
// a software rasteriser): it draws the pictures, then waits for the elements to highlight (a
// report's thumbnails, known only once the check is done) and draws those from the start
// state, at half the pictures' size.
class PicturesAhead {
 public:
  PicturesAhead(const Model& model, const std::vector<Assignment>& sets, const ReportInfo& info)
      : pictures_done_(pictures_.get_future()),
        elements_asked_(elements_.get_future()),
        thumbnails_done_(thumbnails_.get_future()),
        thread_([this, &model, sets, info] { Work(model, sets, info); }) {}
  ~PicturesAhead() {
    if (!asked_) elements_.set_value({});
    thread_.join();
  }
  PicturesAhead(const PicturesAhead&) = delete;
  PicturesAhead& operator=(const PicturesAhead&) = delete;

  const report::ModelPictures& Pictures() { return pictures_done_.get(); }

  // Thumbnails (PNG) of the start state with each of `elements` highlighted; empty, with `why`
  // set, when the renderer cannot run. Asked once.
  std::vector<std::string> Thumbnails(const std::vector<std::string>& elements, std::string* why) {
    asked_ = true;
    elements_.set_value(elements);
    std::vector<std::string> thumbs = thumbnails_done_.get();
    if (thumbs.empty() && !elements.empty()) *why = Pictures().unavailable;
    return thumbs;
  }

 private:
  void Work(const Model& model, const std::vector<Assignment>& sets, const ReportInfo& info) {
    std::optional<report::Start> start;
    std::optional<Renderer> renderer;
    std::optional<Data> initial;
    try {
      start.emplace(model, sets);
      initial.emplace(start->data.Clone());
      report::ModelPictures pictures;
      try {
        renderer.emplace(start->model,
                         report::SmallPicture(report::kPictureWidth, report::kPictureHeight));
        pictures = report::DrawModelPictures(*renderer, start->model, start->data, info);
      } catch (const UnavailableError& e) {
        renderer.reset();
        pictures = report::ModelPictures{};
        pictures.renderer = "none";
        pictures.unavailable = e.what();
      }
      pictures_.set_value(std::move(pictures));
    } catch (...) {
      pictures_.set_exception(std::current_exception());
      thumbnails_.set_exception(std::current_exception());
      TakeMujocoWarnings();  // this thread's own, not the check's
      return;
    }
    std::vector<std::string> elements = elements_asked_.get();
    try {
      std::vector<std::string> thumbs;
      Image image;
      for (const std::string& name : elements) {
        if (!renderer) break;
        renderer->Highlight({name});
        renderer->Render(*initial, &image);
        thumbs.push_back(EncodePng(report::Half(image), PngEffort::kFast));
      }
      thumbnails_.set_value(std::move(thumbs));
    } catch (const UnavailableError&) {
      thumbnails_.set_value({});
    } catch (...) {
      thumbnails_.set_exception(std::current_exception());
    }
    TakeMujocoWarnings();
  }

  std::promise<report::ModelPictures> pictures_;
  std::shared_future<report::ModelPictures> pictures_done_;
  std::promise<std::vector<std::string>> elements_;
  std::future<std::vector<std::string>> elements_asked_;
  std::promise<std::vector<std::string>> thumbnails_;
  std::future<std::vector<std::string>> thumbnails_done_;
  bool asked_ = false;
  std::thread thread_;  // last: starts once the promises exist
};

std::shared_ptr<PicturesAhead> StartPictures(const Model& model,
                                             const std::vector<Assignment>& sets,
                                             const ReportInfo& info) {
  if (!info.pictures) return nullptr;
  ReportInfo copy = info;
  copy.ahead = nullptr;
  return std::make_shared<PicturesAhead>(model, sets, copy);
}

namespace report {

void AddModelPictures(Page* page, const Model& model, const std::vector<Assignment>& sets,
                      const ReportInfo& info) {
  if (!info.pictures) {
    page->Meta("renderer", "pictures not asked for");
    return;
  }
  std::shared_ptr<PicturesAhead> ahead = info.ahead ? info.ahead : StartPictures(model, sets, info);
  const ModelPictures& p = ahead->Pictures();
  page->Meta("renderer", p.renderer);
  if (!p.unavailable.empty()) {
    page->Paragraph("No pictures: " + p.unavailable, "note");
    return;
  }
  page->Pictures(p.stills);
  if (!p.frames.empty()) page->Flipbook(p.frames, p.interval_ms, p.animation);
}

std::vector<std::string> HighlightThumbnails(PicturesAhead& pictures,
                                             const std::vector<std::string>& elements,
                                             std::string* why) {
  return pictures.Thumbnails(elements, why);
}

void WritePage(const Page& page, const std::string& path) {
  std::string html = page.Render();
  AtomicFile file(path);
  if (std::fwrite(html.data(), 1, html.size(), file.stream()) != html.size()) {
    throw IoError("cannot write the report '" + path + "'");
  }
  file.Commit();
}

}  // namespace report
}  // namespace plumb
