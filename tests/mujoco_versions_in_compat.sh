#!/bin/sh
# Every MuJoCo version comparison lives in src/core/mujoco_compat.h (and its name tables,
# mujoco_compat_names.h): no other code of the library, the command or the bindings reads
# mjVERSION_HEADER or calls mj_version(); they ask compat::CompiledAtLeast,
# compat::LoadedMujocoIsCompiledOne, compat::kMujoco3, ... Comments may name them.
# Usage: mujoco_versions_in_compat.sh SOURCE_DIR
root="$1"
found=$(cd "$root" && for d in src include apps python/src; do [ -d "$d" ] && echo "$d"; done |
  xargs grep -rn --include='*.cc' --include='*.h' --include='*.h.in' \
    -e 'mjVERSION_HEADER' -e 'mj_version *(' |
  grep -v -e '^src/core/mujoco_compat\.h:' -e '^src/core/mujoco_compat_names\.h:' |
  sed 's|//.*||' | grep -e 'mjVERSION_HEADER' -e 'mj_version *(')
if [ -n "$found" ]; then
  echo "MuJoCo versions compared outside src/core/mujoco_compat.h (name the comparison there"
  echo "and call it):"
  echo "$found"
  exit 1
fi
echo "every MuJoCo version comparison is in src/core/mujoco_compat.h"
