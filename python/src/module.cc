// plumb._plumb: the compiled half of the `plumb` Python package (python/plumb/__init__.py
// imports mujoco first, checks its version, then this).

#include "common.h"
#include "plumb/version.h"

NB_MODULE(_plumb, m) {
  using namespace plumb::python;
  // beside the `mujoco` package: plumb's handlers only around plumb's own calls, and no
  // plugin library loaded twice
  plumb::SetMujocoHandlerMode(plumb::MujocoHandlerMode::kAroundCalls);
  plumb::InstallMujocoHandlers();  // refuses a library that is not the one plumb was built with
  m.attr("__version__") = PLUMB_VERSION;
  BindErrors(m);
  BindCore(m);
  BindChecks(m);
  BindRun(m);
  BindRender(m);
  BindBatch(m);
  BindIdentify(m);
  BindRehearse(m);
}
