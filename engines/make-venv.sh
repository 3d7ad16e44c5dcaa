#!/usr/bin/env bash
# Makes (once) the virtual environment in which engines/adapter.py runs MuJoCo Warp or MJX for
# `plumb crosscheck`, and prints its python on standard output.
#
# Usage: make-venv.sh ENGINE DIR    (ENGINE: warp or mjx; DIR is made if missing and reused
#        while complete for the same lock file).
# The lock (requirements-ENGINE.txt beside this script) is complete and hash-pinned; it is
# installed with --no-deps so that pip cannot replace mujoco-core 4.0.1 by the `mujoco`
# distribution (see the lock's header). The work is done by test-venv.sh: scripts/ in a
# source checkout, beside this script where CMake installs it.
# Exit codes: 0 ready, 2 bad usage, 5 the packages could not be downloaded or do not import.
# It stops at its first failure, command substitutions included: `set -e` does not reach into
# `$(...)` (inherit_errexit does), and an assignment takes the status of its last
# substitution only, so each one is checked where it is made.
set -euo pipefail
shopt -s inherit_errexit
engine="${1:-}"
dir="${2:-}"
here="$(cd "$(dirname "$0")" && pwd)" && [[ -n "$here" ]] || exit 2
case "$engine" in
  warp) module=mujoco_warp; what="MuJoCo Warp"; size="about 170 MB to download, 540 MB installed" ;;
  mjx) module=mujoco.mjx; what="MJX (JAX on CPU)"; size="about 150 MB to download, 690 MB installed" ;;
  *) echo "make-venv.sh: usage: make-venv.sh warp|mjx DIR" >&2; exit 2 ;;
esac
if [[ -z "$dir" ]]; then
  echo "make-venv.sh: usage: make-venv.sh warp|mjx DIR (give the folder for the environment)" >&2
  exit 2
fi
lock="$here/requirements-$engine.txt"
script="$here/../scripts/test-venv.sh"
[[ -f "$script" ]] || script="$here/test-venv.sh"
if [[ ! -f "$lock" || ! -f "$script" ]]; then
  echo "make-venv.sh: $lock or test-venv.sh is missing beside $0 (a broken install)" >&2
  exit 2
fi
# the folder that holds DIR: made, and writable, before anything is downloaded
parent="$(dirname -- "$dir")" && [[ -n "$parent" ]] || exit 2
if ! mkdir -p -- "$parent" || ! parent="$(cd -- "$parent" && pwd)" || [[ -z "$parent" ]] ||
    [[ ! -w "$parent" ]]; then
  echo "make-venv.sh: cannot make the environment in $dir: $parent is not a folder that can" \
    "be made and written; give a DIR in a writable folder" >&2
  exit 2
fi
dir="$parent/$(basename -- "$dir")"
if ! ls "$dir"/.complete-* >/dev/null 2>&1; then
  echo "make-venv.sh: downloading $what and its dependencies, $size, into $dir" >&2
fi
if ! python="$(PLUMB_PIP_OPTIONS="--no-deps" bash "$script" "$dir" "$lock")" ||
    [[ -z "$python" ]]; then
  echo "make-venv.sh: could not install $what into $dir: pip could not download the packages" \
    "of $lock (is PyPI reachable? behind a proxy set HTTPS_PROXY, or point PIP_INDEX_URL at" \
    "a mirror), then run it again" >&2
  exit 5
fi
core="$(sed -n 's/^mujoco-core==\([^ ]*\).*/\1/p' "$lock")" && [[ -n "$core" ]] || {
  echo "make-venv.sh: $lock pins no mujoco-core (a broken install)" >&2
  exit 2
}
check="import mujoco, $module, sys
if mujoco.__version__ != '$core':
    sys.exit(f'mujoco is {mujoco.__version__}, not $core (another mujoco over mujoco-core?)')
v = getattr(sys.modules['$module'], '__version__', None)
if v is None:
    from importlib.metadata import version
    v = version('mujoco-warp' if '$engine' == 'warp' else 'mujoco-mjx')
print('mujoco', mujoco.__version__, '$module', v, file=sys.stderr)"
if ! "$python" -c "$check" >&2; then
  echo "make-venv.sh: $python cannot import mujoco $core and $module; remove $dir and run" \
    "make-venv.sh again (a partial or foreign environment)" >&2
  exit 5
fi
echo "$python"
