#!/usr/bin/env bash
# The include-guard check in scripts/check-layers.py: every header of the tree is guarded by its
# path, and a copy fails, naming the file, the line and the expected guard, when a guard is stale
# (the name a header had in a folder since renamed), when only the #endif comment is, and when a
# header moves to another folder without its guard following. The same check fails when
# docs/layout.md has no line for a public header.
set -euo pipefail
root="${1:?give the checkout}"
check="$root/scripts/check-layers.py"
python3 "$check" "$root" | grep -q "include guards match their paths; docs/layout.md names"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
fresh() {
  rm -rf "$work/tree"
  mkdir -p "$work/tree"
  cp -r "$root/src" "$root/include" "$work/tree/"
}
expect() {  # expect FILE LINE-PATTERN EXPECTED
  set +e
  out=$(python3 "$check" "$work/tree" 2>&1)
  rc=$?
  set -e
  if [[ $rc -ne 1 ]]; then
    echo "FAIL: $1 planted: the check exited $rc, not 1:"
    echo "$out"
    exit 1
  fi
  local line
  line=$(grep -n -m1 -e "$2" "$work/tree/$1" | cut -d: -f1)
  if [[ -z "$line" || "$out" != *"$1:$line: "*"$3"* ]]; then
    echo "FAIL: the check did not name $1:$line and '$3':"
    echo "$out"
    exit 1
  fi
  echo "ok: $1:$line: caught"
}
# a guard left from a renamed folder (src/check/ became src/core/, src/audit/, ...)
fresh
sed -i 's/PLUMB_SRC_CORE_STRINGS_H_/PLUMB_SRC_CHECK_STRINGS_H_/' "$work/tree/src/core/strings.h"
expect src/core/strings.h '^#ifndef' 'expected PLUMB_SRC_CORE_STRINGS_H_'
# only the comment of the closing #endif is stale
fresh
sed -i 's|^#endif  // PLUMB_SRC_IO_HASH_H_|#endif  // PLUMB_SRC_CHECK_HASH_H_|' "$work/tree/src/io/hash.h"
expect src/io/hash.h '^#endif  // PLUMB_SRC_CHECK_HASH_H_' '"#endif  // PLUMB_SRC_IO_HASH_H_"'
# a header moved to another folder, its guard unchanged
fresh
mv "$work/tree/src/io/hash.h" "$work/tree/src/core/hash.h"
expect src/core/hash.h '^#ifndef' 'expected PLUMB_SRC_CORE_HASH_H_'
# a public header's guard (include/plumb/NAME.h is guarded by PLUMB_INCLUDE_PLUMB_NAME_H_)
fresh
sed -i 's/PLUMB_INCLUDE_PLUMB_STOP_H_/PLUMB_STOP_H_/' "$work/tree/include/plumb/stop.h"
expect include/plumb/stop.h '^#ifndef' 'expected PLUMB_INCLUDE_PLUMB_STOP_H_'
# a public header docs/layout.md has no line for
fresh
mkdir -p "$work/tree/docs"
grep -v '^  sleep\.h ' "$root/docs/layout.md" >"$work/tree/docs/layout.md"
set +e
out=$(python3 "$check" "$work/tree" 2>&1)
rc=$?
set -e
if [[ $rc -ne 1 || "$out" != *"docs/layout.md: include/plumb/sleep.h has no line"* ]]; then
  echo "FAIL: docs/layout.md without sleep.h: the check exited $rc and said:"
  echo "$out"
  exit 1
fi
echo "ok: docs/layout.md without sleep.h: caught"
