#!/usr/bin/env bash
# engines/make-venv.sh stops at its first failure: a DIR under a file, under a place that cannot
# be made (/proc), or under a read-only folder is refused with exit 2 before anything is made or
# downloaded (issue 46: a failed `mkdir -p` inside `$(...)` left the path empty and the
# environment went to /). It runs a copy of the script beside a stand-in test-venv.sh that
# records being called and makes nothing, so no case can reach the network or write outside
# this test's temporary folder.
#
# Usage: make_venv_test.sh SOURCE_DIR      Exit 0 when every case passes, 1 otherwise.
set -euo pipefail
source_dir="${1:?give the source folder}"
work="$(mktemp -d "${TMPDIR:-/tmp}/plumb-make-venv-XXXXXX")" && [[ -n "$work" ]] || exit 1
trap 'chmod -R u+w "$work"; rm -rf "$work"' EXIT
mkdir -p "$work/engines" "$work/scripts"
cp "$source_dir/engines/make-venv.sh" "$source_dir/engines/requirements-warp.txt" "$work/engines/"
cat >"$work/scripts/test-venv.sh" <<EOF
#!/usr/bin/env bash
echo "\$1" >>"$work/called"
exit 1
EOF
echo x >"$work/file"
mkdir "$work/readonly"
chmod a-w "$work/readonly"

failures=0
expect_refused() {  # DIR: exit 2, the stand-in never called, nothing made at / or beside
  local dir="$1" status=0
  bash "$work/engines/make-venv.sh" warp "$dir" >"$work/out" 2>"$work/err" || status=$?
  if [[ $status -ne 2 || -e "$work/called" || -s "$work/out" ]]; then
    echo "FAIL: make-venv.sh warp $dir: exit $status (want 2), stand-in called:" \
      "$(cat "$work/called" 2>/dev/null || echo no); stderr: $(cat "$work/err")"
    failures=$((failures + 1))
  elif ! grep -q "make-venv.sh: cannot make the environment in $dir" "$work/err"; then
    echo "FAIL: make-venv.sh warp $dir: the message does not name DIR: $(cat "$work/err")"
    failures=$((failures + 1))
  fi
  rm -f "$work/called"
  if [[ -e /warp-x || -e /warp-x.lock ]]; then
    echo "FAIL: make-venv.sh warp $dir made /warp-x"
    failures=$((failures + 1))
  fi
}

expect_refused "$work/file/warp-x"
expect_refused "$work/file/deeper/warp-x"
expect_refused "/proc/nope/warp-x"
# root writes anywhere: the read-only folder is a case for other users only
if [[ $(id -u) -ne 0 ]]; then expect_refused "$work/readonly/sub/warp-x"; fi

# a writable DIR gets as far as the stand-in (the install), which is called with DIR itself
status=0
bash "$work/engines/make-venv.sh" warp "$work/venvs/warp-x" >/dev/null 2>&1 || status=$?
if [[ $status -ne 5 || "$(cat "$work/called" 2>/dev/null)" != "$work/venvs/warp-x" ]]; then
  echo "FAIL: make-venv.sh warp $work/venvs/warp-x: exit $status (want 5 from the stand-in)," \
    "stand-in called with: $(cat "$work/called" 2>/dev/null || echo nothing)"
  failures=$((failures + 1))
fi

if [[ $failures -ne 0 ]]; then exit 1; fi
echo "make_venv_test: every case passed"
