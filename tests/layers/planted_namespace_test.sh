#!/usr/bin/env bash
# The namespace check in scripts/check-layers.py: no private header (src/**/*.h) declares into
# the public namespace plumb, and a copy fails, naming the file and the line, when one opens
# `namespace plumb {` again; a header in its folder's namespace (plumb::<folder>) passes.
set -euo pipefail
root="${1:?give the checkout}"
check="$root/scripts/check-layers.py"
python3 "$check" "$root" | grep -q "no private header declares into namespace plumb"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/tree"
cp -r "$root/src" "$root/include" "$work/tree/"
# a folder's own namespace is allowed
sed -i 's/^namespace plumb::internal {/namespace plumb::core {/; s|^}  // namespace plumb::internal|}  // namespace plumb::core|' \
  "$work/tree/src/core/strings.h"
python3 "$check" "$work/tree" >/dev/null
# the public namespace is not
sed -i 's/^namespace plumb::internal {/namespace plumb {/' "$work/tree/src/io/hash.h"
set +e
out=$(python3 "$check" "$work/tree" 2>&1)
rc=$?
set -e
line=$(grep -n -m1 '^namespace plumb {' "$work/tree/src/io/hash.h" | cut -d: -f1)
if [[ $rc -ne 1 || "$out" != *"src/io/hash.h:$line: a private header declares into the public namespace plumb"* ]]; then
  echo "FAIL: src/io/hash.h in namespace plumb: the check exited $rc and said:"
  echo "$out"
  exit 1
fi
echo "ok: src/io/hash.h:$line: caught"
