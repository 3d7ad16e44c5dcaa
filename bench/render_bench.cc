// Offscreen rendering throughput of plumb::Renderer, the plumb side of bench/render_peer.sh
// (the peer is MuJoCo's Python mujoco.Renderer, bench/render_peer.py, doing the same loop).
//
//   build/bench/render_bench MODEL FRAMES WIDTH HEIGHT [--camera NAME] [--msaa] [--dump FILE]
//
// Loads MODEL, then for each frame takes one mj_step (so the scene changes) and renders the
// new state into one reused Image. 5 frames are rendered first as warm-up (GL context,
// shader compilation, texture upload, first-touch of the buffers) and not timed. Prints one
// JSON line: {"model", "frames", "seconds", "ms_per_frame", "fps", "backend", ...}.
//
// Only Renderer::Render is timed: scene update (mjv_updateScene), draw (mjr_render) and
// readback (mjr_readPixels plus the top-down row flip). The mj_step between frames is not.
// Both the wall time and the process's CPU time (all threads: llvmpipe's rasteriser threads
// included) of those calls are summed; on a shared machine the CPU time is the steadier.
//
// --camera and --msaa are RenderOptions::camera and ::msaa (plumb's defaults: "auto", off);
// --camera fixed with --msaa draws what mujoco.Renderer draws by default (the model's free
// camera, the model's offsamples). --dump writes the last frame's raw RGB bytes, top row
// first, for comparing pictures with the peer's.

#include <time.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "plumb/error.h"
#include "plumb/image.h"
#include "plumb/model.h"
#include "plumb/render.h"

namespace {

constexpr int kWarmupFrames = 5;

// CPU time of the whole process, all threads (llvmpipe rasterises on worker threads).
double ProcessCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

std::string JsonString(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) continue;
    out += c;
  }
  return out + "\"";
}

int Usage() {
  std::fprintf(stderr,
               "usage: render_bench MODEL FRAMES WIDTH HEIGHT [--camera NAME] [--msaa] "
               "[--dump FILE]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) return Usage();
  const std::string path = argv[1];
  const int frames = std::atoi(argv[2]);
  plumb::RenderOptions options;
  options.width = std::atoi(argv[3]);
  options.height = std::atoi(argv[4]);
  std::string dump;
  for (int i = 5; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg == "--msaa") {
      options.msaa = true;
    } else if (arg == "--camera" && i + 1 < argc) {
      options.camera = argv[++i];
    } else if (arg == "--dump" && i + 1 < argc) {
      dump = argv[++i];
    } else {
      return Usage();
    }
  }
  if (frames < 1) return Usage();
  try {
    plumb::Model model = plumb::Model::Load(path);
    plumb::Data data(model);
    data.Forward();
    plumb::Renderer renderer(model, options);
    plumb::Image image;

    for (int i = 0; i < kWarmupFrames; ++i) {
      data.Step();
      renderer.Render(data, &image);
    }
    using Clock = std::chrono::steady_clock;
    Clock::duration rendering{};
    double cpu = 0;
    for (int i = 0; i < frames; ++i) {
      data.Step();  // not timed
      double cpu_start = ProcessCpuSeconds();
      Clock::time_point start = Clock::now();
      renderer.Render(data, &image);  // timed: scene update + draw + readback
      rendering += Clock::now() - start;
      cpu += ProcessCpuSeconds() - cpu_start;
    }
    double seconds = std::chrono::duration<double>(rendering).count();

    if (!dump.empty()) {
      std::ofstream out(dump, std::ios::binary);
      out.write(reinterpret_cast<const char*>(image.rgb.data()),
                static_cast<std::streamsize>(image.rgb.size()));
    }
    std::printf(
        "{\"model\": %s, \"frames\": %d, \"width\": %d, \"height\": %d, \"seconds\": %.6f, "
        "\"ms_per_frame\": %.4f, \"fps\": %.2f, \"cpu_ms_per_frame\": %.4f, \"backend\": %s, "
        "\"camera\": %s, \"msaa\": %s}\n",
        JsonString(path).c_str(), frames, options.width, options.height, seconds,
        1e3 * seconds / frames, frames / seconds, 1e3 * cpu / frames,
        JsonString(renderer.backend()).c_str(), JsonString(renderer.camera()).c_str(),
        options.msaa ? "true" : "false");
  } catch (const plumb::Error& e) {
    std::fprintf(stderr, "render_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
