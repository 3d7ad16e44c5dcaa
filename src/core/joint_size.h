// The qpos and dof block sizes of MuJoCo's joint types, and the base body a free joint moves.
// Private to the library.

#ifndef PLUMB_SRC_CORE_JOINT_SIZE_H_
#define PLUMB_SRC_CORE_JOINT_SIZE_H_

#include <mujoco/mujoco.h>

namespace plumb::internal {

// 7 and 6 for a free joint, 4 and 3 for a ball joint, 1 and 1 for a hinge or slide.
inline int JointQposSize(int type) { return type == mjJNT_FREE ? 7 : type == mjJNT_BALL ? 4 : 1; }
inline int JointDofSize(int type) { return type == mjJNT_FREE ? 6 : type == mjJNT_BALL ? 3 : 1; }

// The first body moved by a free joint (a floating robot's base), or -1.
inline int FirstFreeBody(const mjModel* m) {
  for (int j = 0; j < m->njnt; ++j) {
    if (m->jnt_type[j] == mjJNT_FREE) return m->jnt_bodyid[j];
  }
  return -1;
}

}  // namespace plumb::internal

#endif  // PLUMB_SRC_CORE_JOINT_SIZE_H_
