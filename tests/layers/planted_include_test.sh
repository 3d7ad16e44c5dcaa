#!/usr/bin/env bash
# The layer check (scripts/check-layers.py) passes on the tree, and fails, naming the file, the
# line and the rule, on a copy with an upward include planted (core reading the report) and on
# one with a sideways include (verify reading audit's internals).
set -euo pipefail
root="${1:?give the checkout}"
check="$root/scripts/check-layers.py"
python3 "$check" "$root"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
plant() {  # plant FOLDER-FILE INCLUDE EXPECTED
  rm -rf "$work/tree"
  mkdir -p "$work/tree"
  cp -r "$root/src" "$root/include" "$work/tree/"
  echo "#include \"$2\"" >>"$work/tree/src/$1"
  local line
  line=$(wc -l <"$work/tree/src/$1")
  set +e
  out=$(python3 "$check" "$work/tree" 2>&1)
  rc=$?
  set -e
  if [[ $rc -ne 1 ]]; then
    echo "FAIL: '#include \"$2\"' planted in src/$1: the check exited $rc, not 1:"
    echo "$out"
    exit 1
  fi
  if [[ "$out" != *"src/$1:$line: $3"* ]]; then
    echo "FAIL: the check did not name src/$1:$line and '$3':"
    echo "$out"
    exit 1
  fi
  echo "ok: src/$1:$line: caught"
}
plant core/error.cc report/html.h 'src/core/ includes "report/html.h" from src/report/, a layer above'
plant core/model.cc plumb/verify.h 'src/core/ includes "plumb/verify.h" from src/verify/, a layer above'
plant verify/verify.cc audit/audit_layers.h 'src/verify/ includes "audit/audit_layers.h" from src/audit/, a sibling'
