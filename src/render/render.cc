// Renderer: MuJoCo's classic renderer (mjv_updateScene, mjr_render, mjr_readPixels) on a
// headless GL context, with the camera chosen for the model and highlighted elements.

#include "plumb/render.h"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <cstring>
#include <set>

#include "core/joint_size.h"
#include "core/mujoco_compat.h"
#include "plumb/error.h"
#include "render/gl_context.h"

namespace plumb {
using internal::FirstFreeBody;

namespace {

constexpr int kMaxSide = 8192;
// the scene's geom budget, as MuJoCo's Python Renderer has it
constexpr int kMaxSceneGeoms = 10000;
constexpr float kHighlight[4] = {1.0f, 0.15f, 0.6f, 1.0f};
constexpr float kFade = 0.25f;  // alpha of everything else while something is highlighted

std::string Names(const Model& model, int type, int count) {
  std::string list;
  for (int i = 0; i < count; ++i) {
    std::string name = model.Name(type, i);
    if (!name.empty()) list += (list.empty() ? "" : ", ") + name;
  }
  return list.empty() ? "(none has a name)" : list;
}

// The geoms that colouring `name` (a body, geom or joint) makes stand out.
void AddHighlight(const Model& model, const std::string& name, std::set<int>* geoms, bool* joint) {
  const mjModel* m = model.get();
  int geom = mj_name2id(m, mjOBJ_GEOM, name.c_str());
  if (geom >= 0) {
    geoms->insert(geom);
    return;
  }
  int body = mj_name2id(m, mjOBJ_BODY, name.c_str());
  int jnt = mj_name2id(m, mjOBJ_JOINT, name.c_str());
  if (body < 0 && jnt >= 0) {
    body = m->jnt_bodyid[jnt];
    *joint = true;
  }
  if (body < 0) {
    throw ArgumentError(
        "highlight", Quoted(name),
        "names no body, geom or joint of the model. Bodies: " + Names(model, mjOBJ_BODY, m->nbody) +
            ". Joints: " + Names(model, mjOBJ_JOINT, m->njnt) + ".");
  }
  for (int g = 0; g < m->ngeom; ++g) {
    if (m->geom_bodyid[g] == body) geoms->insert(g);
  }
}

}  // namespace

struct Renderer::Impl {
  const Model& model;
  Model offscreen;  // a copy whose offscreen buffer fits the picture
  RenderOptions options;
  std::unique_ptr<render::GlContext> gl;
  mjvScene scene;
  mjvCamera camera;
  mjvOption option;
  mjrContext context;
  std::set<int> highlighted;
  std::string camera_text;
  std::vector<unsigned char> bottom_up;

  Impl(const Model& m, RenderOptions o) : model(m), offscreen(m.Clone()), options(std::move(o)) {
    // defaults first: a constructor that throws later frees these as they are
    mjv_defaultScene(&scene);
    mjr_defaultContext(&context);
    mjv_defaultOption(&option);
  }
  ~Impl() {
    // GL objects belong to this renderer's context, which another renderer may have
    // displaced as the current one
    if (gl != nullptr) {
      try {
        gl->MakeCurrent();
      } catch (const Error&) {
        // the context is gone; freeing MuJoCo's side is all that is left to do
      }
      mjr_freeContext(&context);
    }
    mjv_freeScene(&scene);
  }
  void ChooseCamera();
};

void Renderer::Impl::ChooseCamera() {
  const mjModel* m = model.get();
  mjv_defaultCamera(&camera);
  CameraChoice choice = ChooseRenderCamera(model, options.camera);
  int free_body = FirstFreeBody(m);
  if (choice.id >= 0) {
    camera.type = mjCAMERA_FIXED;
    camera.fixedcamid = choice.id;
    camera_text = "model camera " + CameraLabel(model, choice.id);
    return;
  }
  std::string name = choice.builtin;
  if (name == "auto") name = free_body >= 0 ? "track" : "fixed";
  if (name == "fixed") {
    mjv_defaultFreeCamera(m, &camera);
    camera_text = "fixed: whole model";
    return;
  }
  if (free_body < 0) {
    throw ArgumentError("camera", Quoted(options.camera),
                        "follows a free-floating body, and '" + model.file() +
                            "' has none: use the fixed camera or a camera of the model (" +
                            (m->ncam > 0 ? Names(model, mjOBJ_CAMERA, m->ncam) : "none") + ")");
  }
  mjv_defaultFreeCamera(m, &camera);
  camera.type = mjCAMERA_TRACKING;
  camera.trackbodyid = free_body;
  camera_text = "tracking body '" + model.Name(mjOBJ_BODY, free_body) + "'";
}

Renderer::Renderer(const Model& model, RenderOptions options) {
  if (options.shadow_size < 0 || options.shadow_size > kMaxSide) {
    throw ValueError("a shadow map must be 1 to 8192 texels a side (0: the model's)");
  }
  if (options.width < 1 || options.height < 1 || options.width > kMaxSide ||
      options.height > kMaxSide) {
    throw ValueError("a picture must be 1 to 8192 pixels a side, not " +
                     std::to_string(options.width) + "x" + std::to_string(options.height));
  }
  impl_ = std::make_unique<Impl>(model, std::move(options));
  Impl& r = *impl_;
  r.ChooseCamera();
  Highlight(r.options.highlight);
  r.gl = render::GlContext::Create(r.options.backend);

  mjModel* m = r.offscreen.get_mutable();
  m->vis.global.offwidth = std::max(m->vis.global.offwidth, r.options.width);
  m->vis.global.offheight = std::max(m->vis.global.offheight, r.options.height);
  if (r.options.shadow_size > 0) m->vis.quality.shadowsize = r.options.shadow_size;
  if (!r.options.msaa) {
    m->vis.quality.offsamples = 0;
  } else if (m->vis.quality.offsamples <= 0) {
    m->vis.quality.offsamples = 4;
  }
  mjv_makeScene(m, &r.scene, kMaxSceneGeoms);
  mjr_makeContext(m, &r.context, mjFONTSCALE_100);
  mjr_setBuffer(mjFB_OFFSCREEN, &r.context);
  if (r.context.currentBuffer != mjFB_OFFSCREEN) {
    throw UnavailableError("MuJoCo could not make its offscreen framebuffer on " +
                           r.gl->description());
  }
  r.bottom_up.resize(std::size_t(r.options.width) * r.options.height * 3);
  if (compat::kRendererFirstFrameDiffers) {
    Data warm_up(model);
    mj_forward(model.get(), warm_up.get());
    Image discarded;
    Render(warm_up, &discarded);
  }
}

Renderer::~Renderer() = default;

void Renderer::Highlight(const std::vector<std::string>& names) {
  std::set<int> geoms;
  bool joint = false;
  for (const std::string& name : names) AddHighlight(impl_->model, name, &geoms, &joint);
  impl_->highlighted = std::move(geoms);
  impl_->option.flags[mjVIS_JOINT] = joint ? 1 : 0;
}

void Renderer::Render(Data& data, Image* image) {
  Impl& r = *impl_;
  r.gl->MakeCurrent();
  mjv_updateScene(r.model.get(), data.get(), &r.option, nullptr, &r.camera, mjCAT_ALL, &r.scene);
  if (!r.highlighted.empty()) {
    for (int i = 0; i < r.scene.ngeom; ++i) {
      mjvGeom& g = r.scene.geoms[i];
      if (g.objtype == mjOBJ_GEOM && r.highlighted.count(g.objid) > 0) {
        std::copy(kHighlight, kHighlight + 4, g.rgba);
        g.emission = 0.4f;
      } else if (g.objtype == mjOBJ_GEOM && g.type != mjGEOM_PLANE) {
        g.rgba[3] *= kFade;
        g.transparent = 1;
      }
    }
  }
  mjrRect viewport = {0, 0, r.options.width, r.options.height};
  mjr_render(viewport, &r.scene, &r.context);
  mjr_readPixels(r.bottom_up.data(), nullptr, viewport, &r.context);
  // OpenGL's rows start at the bottom; an Image's at the top
  image->width = r.options.width;
  image->height = r.options.height;
  std::size_t row = std::size_t(r.options.width) * 3;
  image->rgb.resize(row * r.options.height);
  for (int y = 0; y < r.options.height; ++y) {
    std::memcpy(&image->rgb[row * y], &r.bottom_up[row * (r.options.height - 1 - y)], row);
  }
}

Image Renderer::Render(Data& data) {
  Image image;
  Render(data, &image);
  return image;
}

const std::string& Renderer::backend() const { return impl_->gl->description(); }
const std::string& Renderer::camera() const { return impl_->camera_text; }

bool RendererBuilt() { return true; }

}  // namespace plumb
