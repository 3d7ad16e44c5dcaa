#include "common.h"

namespace plumb::python {

void BindBatch(nb::module_& m) { (void)m; }

}  // namespace plumb::python
