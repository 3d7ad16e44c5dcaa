#include "common.h"

namespace plumb::python {

void BindIdentify(nb::module_& m) { (void)m; }

}  // namespace plumb::python
