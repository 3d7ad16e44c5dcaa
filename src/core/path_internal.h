// What path.cc (resolving names) tells path_values.cc (writing values). Private to core.

#ifndef PLUMB_SRC_CORE_PATH_INTERNAL_H_
#define PLUMB_SRC_CORE_PATH_INTERNAL_H_

#include <mujoco/mujoco.h>

#include <string>

#include "core/joint_size.h"

namespace plumb::internal {

// Whether model field `field` is a constant the compiler derives (mj_setConst recomputes
// it: body_subtreemass, dof_invweight0, ...), so that writing it would be undone.
bool IsCompilerConstant(const std::string& field);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_CORE_PATH_INTERNAL_H_
