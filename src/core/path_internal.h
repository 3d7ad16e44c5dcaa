// What path.cc (resolving names) tells path_values.cc (writing values). Private to core.

#ifndef PLUMB_SRC_CORE_PATH_INTERNAL_H_
#define PLUMB_SRC_CORE_PATH_INTERNAL_H_

#include <mujoco/mujoco.h>

#include <string>

namespace plumb {

// Whether model field `field` is a constant the compiler derives (mj_setConst recomputes
// it: body_subtreemass, dof_invweight0, ...), so that writing it would be undone.
bool IsCompilerConstant(const std::string& field);

// The qpos and dof block sizes of a joint of `type`: 7 and 6 for a free joint, 4 and 3 for a
// ball joint, 1 and 1 for a hinge or slide.
inline int JointQposSize(int type) { return type == mjJNT_FREE ? 7 : type == mjJNT_BALL ? 4 : 1; }
inline int JointDofSize(int type) { return type == mjJNT_FREE ? 6 : type == mjJNT_BALL ? 3 : 1; }

}  // namespace plumb

#endif  // PLUMB_SRC_CORE_PATH_INTERNAL_H_
