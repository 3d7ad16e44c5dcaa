#!/usr/bin/env bash
# scripts/list-created-files.sh, the CI check that a test run writes nothing outside its
# temporary folders and plumb's cache, against planted writes in a folder of its own (--root) and
# a checkout of its own (--checkout): an allowed write passes, a file planted elsewhere, a
# folder planted elsewhere and a repro folder left in the checkout each fail naming the path, and
# a failing command's exit status is kept.
#
# Usage: created_files_test.sh SOURCE_DIR      Exit 0 when every case passes, 1 otherwise.
set -euo pipefail
shopt -s inherit_errexit
script="${1:?give the source folder}/scripts/list-created-files.sh"
work="$(mktemp -d "${TMPDIR:-/tmp}/plumb-created-files-test-XXXXXX")" && [[ -n "$work" ]] || exit 1
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/root/allowed" "$work/root/elsewhere" "$work/checkout"
git -C "$work/checkout" init -q
echo tracked >"$work/checkout/tracked"
git -C "$work/checkout" add tracked
git -C "$work/checkout" -c user.name=t -c user.email=t@t commit -q -m tracked

failures=0
# case STATUS PATTERN COMMAND...: list-created-files.sh exits STATUS, its stderr matching PATTERN
case_() {
  local want="$1" pattern="$2" status=0
  shift 2
  bash "$script" --root "$work/root" --allow "$work/root/allowed" --checkout "$work/checkout" \
    -- "$@" 2>"$work/err" || status=$?
  if [[ $status -ne $want ]] || ! grep -q -- "$pattern" "$work/err"; then
    echo "FAIL: $*: exit $status (want $want), stderr (want /$pattern/):"
    sed 's/^/  /' "$work/err"
    failures=$((failures + 1))
  fi
}

case_ 0 "wrote nothing outside" touch "$work/root/allowed/cache-file"
case_ 1 "  $work/root/elsewhere/planted$" touch "$work/root/elsewhere/planted"
case_ 1 "  $work/root/warp-99f1b8621d3c/$" mkdir "$work/root/warp-99f1b8621d3c"
case_ 1 "?? plumb-repro-1/" sh -c "mkdir '$work/checkout/plumb-repro-1' && touch '$work/checkout/plumb-repro-1/model.xml'"
case_ 1 " M tracked" sh -c "echo changed >'$work/checkout/tracked'"
case_ 3 "wrote nothing outside" sh -c "exit 3"
case_ 2 "give the COMMAND" 

if [[ $failures -ne 0 ]]; then exit 1; fi
echo "created_files_test: every case passed"
