// A headless OpenGL context for MuJoCo's renderer: EGL on Mesa's surfaceless platform, or
// OSMesa. The GL libraries are opened at run time (dlopen), so plumb runs, renderer or not,
// on a machine without them, and so only the backend in use is visible to MuJoCo's GL
// loader (it binds to the first one it finds in the process).

#ifndef PLUMB_SRC_RENDER_GL_CONTEXT_H_
#define PLUMB_SRC_RENDER_GL_CONTEXT_H_

#include <memory>
#include <string>

namespace plumb::render {

class GlContext {
 public:
  // Makes a context and makes it current on the calling thread. `backend` is "auto" (EGL,
  // else OSMesa), "egl" or "osmesa". The first context of a process fixes its backend: a
  // later request for the other one is refused.
  // @throws UnavailableError naming what failed at each backend tried; ValueError for an
  //         unknown backend name.
  static std::unique_ptr<GlContext> Create(const std::string& backend);
  virtual ~GlContext() = default;

  // Makes this context current on the calling thread again.
  virtual void MakeCurrent() = 0;
  // "EGL (surfaceless), <GL_RENDERER>" or "OSMesa, <GL_RENDERER>".
  const std::string& description() const { return description_; }

 protected:
  std::string description_;
};

}  // namespace plumb::render

#endif  // PLUMB_SRC_RENDER_GL_CONTEXT_H_
