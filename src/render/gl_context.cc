// Headless GL contexts: EGL surfaceless (default) and OSMesa (fallback), both opened with
// dlopen. See gl_context.h.

#include "render/gl_context.h"

#include <dlfcn.h>

#include <cstdlib>
#include <mutex>
#include <vector>

#include "plumb/error.h"

#ifdef PLUMB_HAVE_EGL
#include <EGL/egl.h>
#include <EGL/eglext.h>
#endif
#ifdef PLUMB_HAVE_OSMESA
#include <GL/osmesa.h>
#endif

namespace plumb::render {
namespace {

constexpr unsigned kGlRenderer = 0x1F01;  // GL_RENDERER
using GetStringFn = const unsigned char* (*)(unsigned);

// The process's backend once a context was made ("egl", "osmesa"), "" before.
std::mutex backend_mutex;
std::string process_backend;

std::string RendererString(void* get_string) {
  if (get_string == nullptr) return "unknown GL renderer";
  const unsigned char* text = reinterpret_cast<GetStringFn>(get_string)(kGlRenderer);
  return text != nullptr ? reinterpret_cast<const char*>(text) : "unknown GL renderer";
}

template <typename Fn>
Fn Symbol(void* lib, const char* name) {
  return reinterpret_cast<Fn>(dlsym(lib, name));
}

#ifdef PLUMB_HAVE_EGL
class EglContext : public GlContext {
 public:
  // Fills `why` and returns null when any step fails.
  static std::unique_ptr<GlContext> Make(std::string* why) {
    // opened locally first: MuJoCo's loader must not see EGL unless EGL works
    void* lib = dlopen("libEGL.so.1", RTLD_NOW | RTLD_LOCAL);
    if (lib == nullptr) {
      *why = std::string("EGL: cannot open libEGL.so.1 (") + dlerror() + ")";
      return nullptr;
    }
    auto context = std::unique_ptr<EglContext>(new EglContext(lib));
    if (!context->Start(why)) return nullptr;
    dlopen("libEGL.so.1", RTLD_NOW | RTLD_NOLOAD | RTLD_GLOBAL);
    return context;
  }

  ~EglContext() override {
    if (context_ != EGL_NO_CONTEXT) {
      make_current_(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      destroy_context_(display_, context_);
    }
  }

  void MakeCurrent() override {
    if (!make_current_(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
      throw UnavailableError("EGL: cannot make the context current again");
    }
  }

 private:
  explicit EglContext(void* lib) : lib_(lib) {
    get_proc_ = Symbol<PFNEGLGETPROCADDRESSPROC>(lib, "eglGetProcAddress");
    make_current_ = Symbol<PFNEGLMAKECURRENTPROC>(lib, "eglMakeCurrent");
    destroy_context_ = Symbol<PFNEGLDESTROYCONTEXTPROC>(lib, "eglDestroyContext");
  }

  bool Start(std::string* why) {
    auto initialize = Symbol<PFNEGLINITIALIZEPROC>(lib_, "eglInitialize");
    auto choose_config = Symbol<PFNEGLCHOOSECONFIGPROC>(lib_, "eglChooseConfig");
    auto bind_api = Symbol<PFNEGLBINDAPIPROC>(lib_, "eglBindAPI");
    auto create_context = Symbol<PFNEGLCREATECONTEXTPROC>(lib_, "eglCreateContext");
    auto get_error = Symbol<PFNEGLGETERRORPROC>(lib_, "eglGetError");
    if (get_proc_ == nullptr || make_current_ == nullptr || initialize == nullptr ||
        choose_config == nullptr || bind_api == nullptr || create_context == nullptr ||
        get_error == nullptr || destroy_context_ == nullptr) {
      *why = "EGL: libEGL.so.1 lacks a core EGL 1.4 function";
      return false;
    }
    auto get_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(get_proc_("eglGetPlatformDisplayEXT"));
    if (get_display == nullptr) {
      *why = "EGL: no eglGetPlatformDisplayEXT (EGL_EXT_platform_base)";
      return false;
    }
    display_ = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    EGLint major = 0, minor = 0;
    if (display_ == EGL_NO_DISPLAY || !initialize(display_, &major, &minor)) {
      *why = Failed("no surfaceless display (Mesa's libegl-mesa0 is needed)", get_error());
      return false;
    }
    const EGLint attributes[] = {EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8,
                                 EGL_ALPHA_SIZE, 8, EGL_DEPTH_SIZE, 24, EGL_STENCIL_SIZE, 8,
                                 EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                                 // the surfaceless platform offers pbuffer configs only
                                 EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint count = 0;
    if (!choose_config(display_, attributes, &config, 1, &count) || count < 1) {
      *why = Failed("no config with desktop OpenGL, 8-bit colour and a depth buffer", get_error());
      return false;
    }
    if (!bind_api(EGL_OPENGL_API)) {
      *why = Failed("desktop OpenGL cannot be bound", get_error());
      return false;
    }
    // a compatibility context: MuJoCo's renderer uses fixed-function OpenGL
    context_ = create_context(display_, config, EGL_NO_CONTEXT, nullptr);
    if (context_ == EGL_NO_CONTEXT) {
      *why = Failed("cannot create a context", get_error());
      return false;
    }
    if (!make_current_(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
      *why = Failed("cannot make a surfaceless context current", get_error());
      return false;
    }
    description_ =
        "EGL (surfaceless), " + RendererString(reinterpret_cast<void*>(get_proc_("glGetString")));
    return true;
  }

  static std::string Failed(const char* what, EGLint code) {
    char hex[16];
    std::snprintf(hex, sizeof hex, "0x%04x", unsigned(code));
    return std::string("EGL: ") + what + " (error " + hex + ")";
  }

  void* lib_;
  PFNEGLGETPROCADDRESSPROC get_proc_ = nullptr;
  PFNEGLMAKECURRENTPROC make_current_ = nullptr;
  PFNEGLDESTROYCONTEXTPROC destroy_context_ = nullptr;
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
};
#endif  // PLUMB_HAVE_EGL

#ifdef PLUMB_HAVE_OSMESA
class OsmesaContext : public GlContext {
 public:
  static std::unique_ptr<GlContext> Make(std::string* why) {
    void* lib = dlopen("libOSMesa.so.8", RTLD_NOW | RTLD_LOCAL);
    if (lib == nullptr) lib = dlopen("libOSMesa.so.6", RTLD_NOW | RTLD_LOCAL);
    if (lib == nullptr) {
      *why = std::string("OSMesa: cannot open libOSMesa.so.8 (") + dlerror() +
             "; Debian: apt-get install libosmesa6)";
      return nullptr;
    }
    auto create = Symbol<OSMesaContext (*)(GLenum, GLint, GLint, GLint, OSMesaContext)>(
        lib, "OSMesaCreateContextExt");
    auto context = std::unique_ptr<OsmesaContext>(new OsmesaContext(lib));
    if (create == nullptr || context->make_current_ == nullptr || context->destroy_ == nullptr ||
        context->get_proc_ == nullptr) {
      *why = "OSMesa: the library lacks OSMesaCreateContextExt or OSMesaMakeCurrent";
      return nullptr;
    }
    context->context_ = create(OSMESA_RGBA, 24, 8, 0, nullptr);
    if (context->context_ == nullptr) {
      *why = "OSMesa: cannot create a context";
      return nullptr;
    }
    context->MakeCurrent();
    dlopen("libOSMesa.so.8", RTLD_NOW | RTLD_NOLOAD | RTLD_GLOBAL);
    dlopen("libOSMesa.so.6", RTLD_NOW | RTLD_NOLOAD | RTLD_GLOBAL);
    context->description_ =
        "OSMesa, " + RendererString(reinterpret_cast<void*>(context->get_proc_("glGetString")));
    return context;
  }

  ~OsmesaContext() override {
    if (context_ != nullptr) destroy_(context_);
  }

  // MuJoCo draws into its own offscreen framebuffer; the context's buffer is a token one
  void MakeCurrent() override {
    if (!make_current_(context_, buffer_.data(), GL_UNSIGNED_BYTE, kSide, kSide)) {
      throw UnavailableError("OSMesa: cannot make the context current");
    }
  }

 private:
  static constexpr int kSide = 16;
  explicit OsmesaContext(void* lib) : buffer_(kSide * kSide * 4) {
    make_current_ = Symbol<GLboolean (*)(OSMesaContext, void*, GLenum, GLsizei, GLsizei)>(
        lib, "OSMesaMakeCurrent");
    destroy_ = Symbol<void (*)(OSMesaContext)>(lib, "OSMesaDestroyContext");
    get_proc_ = Symbol<OSMESAproc (*)(const char*)>(lib, "OSMesaGetProcAddress");
  }

  GLboolean (*make_current_)(OSMesaContext, void*, GLenum, GLsizei, GLsizei) = nullptr;
  void (*destroy_)(OSMesaContext) = nullptr;
  OSMESAproc (*get_proc_)(const char*) = nullptr;
  OSMesaContext context_ = nullptr;
  std::vector<unsigned char> buffer_;
};
#endif  // PLUMB_HAVE_OSMESA

std::unique_ptr<GlContext> MakeBackend(const std::string& name, std::string* why) {
#ifdef PLUMB_HAVE_EGL
  if (name == "egl") return EglContext::Make(why);
#endif
#ifdef PLUMB_HAVE_OSMESA
  if (name == "osmesa") return OsmesaContext::Make(why);
#endif
  *why = name + ": not built in (its headers were missing when plumb was configured)";
  return nullptr;
}

}  // namespace

std::unique_ptr<GlContext> GlContext::Create(const std::string& backend) {
  if (backend != "auto" && backend != "egl" && backend != "osmesa") {
    throw ValueError("unknown GL backend '" + backend + "': use auto, egl or osmesa");
  }
  std::lock_guard<std::mutex> lock(backend_mutex);
  std::vector<std::string> order;
  if (!process_backend.empty()) {
    if (backend != "auto" && backend != process_backend) {
      throw UnavailableError("this process already renders through " + process_backend +
                             "; MuJoCo's GL loader cannot switch to " + backend +
                             " (use one backend per process)");
    }
    order = {process_backend};
  } else if (backend == "auto") {
    order = {"egl", "osmesa"};
  } else {
    order = {backend};
  }
  std::string reasons;
  for (const std::string& name : order) {
    std::string why;
    std::unique_ptr<GlContext> context = MakeBackend(name, &why);
    if (context != nullptr) {
      // MuJoCo 3.x and later read MUJOCO_GL to pick the GL loader (older ones look for
      // whichever library is loaded)
      setenv("MUJOCO_GL", name.c_str(), 1);
      process_backend = name;
      return context;
    }
    reasons += (reasons.empty() ? "" : "; ") + why;
  }
  throw UnavailableError("no headless OpenGL context could be made: " + reasons +
                         ". Install Mesa (Debian: apt-get install libegl1 libegl-mesa0 "
                         "libgl1-mesa-dri, or libosmesa6).");
}

}  // namespace plumb::render
