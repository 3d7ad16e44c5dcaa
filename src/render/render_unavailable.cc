// The Renderer of a build without PLUMB_WITH_RENDER: every construction says so.

#include "plumb/error.h"
#include "plumb/render.h"

namespace plumb {

struct Renderer::Impl {};

Renderer::Renderer(const Model&, RenderOptions) {
  throw UnavailableError(
      "this plumb was built without the renderer (configured with PLUMB_WITH_RENDER=OFF, or "
      "no EGL or OSMesa headers and library were found). Install them (Debian: apt-get "
      "install libegl-dev libosmesa6-dev; scripts/install-deps.sh does) and rebuild with "
      "-DPLUMB_WITH_RENDER=ON.");
}

Renderer::~Renderer() = default;
void Renderer::Highlight(const std::vector<std::string>&) {}
void Renderer::Render(Data&, Image*) {}
Image Renderer::Render(Data&) { return {}; }
const std::string& Renderer::backend() const {
  static const std::string none = "none";
  return none;
}
const std::string& Renderer::camera() const { return backend(); }

bool RendererBuilt() { return false; }

}  // namespace plumb
