#include "common.h"

namespace plumb::python {

void BindRun(nb::module_& m) { (void)m; }

}  // namespace plumb::python
