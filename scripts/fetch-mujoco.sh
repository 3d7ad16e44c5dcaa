#!/usr/bin/env bash
# Puts one MuJoCo release into plumb's cache, laid out like an official release folder:
#   $CACHE/mujoco/<version>/{lib/libmujoco.so.<version>, lib/libmujoco.so,
#                            include/mujoco/*.h, bin/mujoco_plugin/*.so}
# from the release's PyPI wheel, pinned by sha256 in cmake/mujoco-wheels.lock. The wheel
# is downloaded with pip (never installed, never imported) and only the C library, its
# headers and its plugin libraries are unpacked, into a temporary folder that is renamed
# into place when complete: a killed run leaves no half cache.
#
# Usage: scripts/fetch-mujoco.sh VERSION      prints nothing when the cache has it
#        scripts/fetch-mujoco.sh --path VERSION   prints the folder (fetching if needed)
# Cache: $PLUMB_CACHE, else ${XDG_CACHE_HOME:-$HOME/.cache}/plumb.
# Exit codes: 0 ready, 2 version not pinned, download impossible or checksum mismatch.
set -euo pipefail

print_path=0
if [[ "${1:-}" == "--path" ]]; then print_path=1; shift; fi
version="${1:?usage: fetch-mujoco.sh [--path] VERSION}"
here="$(cd "$(dirname "$0")/.." && pwd)"
lock="$here/cmake/mujoco-wheels.lock"
cache="${PLUMB_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/plumb}"
dest="$cache/mujoco/$version"

done_() { [[ $print_path -eq 1 ]] && echo "$dest"; exit 0; }
[[ -f "$dest/.complete" ]] && done_

read -r _ dist wheel sha < <(awk -v v="$version" '$1 == v {print; exit}' "$lock") || true
if [[ -z "${sha:-}" ]]; then
  pinned=$(awk '!/^#/ && NF {printf "%s ", $1}' "$lock")
  echo "fetch-mujoco.sh: MuJoCo $version is not pinned in cmake/mujoco-wheels.lock (pinned: ${pinned}debian)." >&2
  echo "fetch-mujoco.sh: add a line (version, distribution, wheel file, sha256) to use another release." >&2
  exit 2
fi

if ! python3 -m pip --version >/dev/null 2>&1; then
  echo "fetch-mujoco.sh: pip is missing; scripts/install-deps.sh installs python3-pip." >&2
  exit 2
fi

mkdir -p "$cache/mujoco"
work=$(mktemp -d "$cache/mujoco/.fetch-$version.XXXXXX")
trap 'rm -rf "$work"' EXIT
# the wheel's tags name CPython 3.11, but the C library inside does not use Python: ask
# for exactly that file whatever Python runs pip, so the pinned checksum always applies
ver_name="${wheel#*-}"; ver_name="${ver_name%%-*}"
if ! python3 -m pip download --quiet --no-deps --only-binary=:all: \
      --platform manylinux_2_28_x86_64 --python-version 3.11 --implementation cp --abi cp311 \
      --dest "$work/wheel" "$dist==$ver_name" >"$work/pip.log" 2>&1 || [[ ! -f "$work/wheel/$wheel" ]]; then
  echo "fetch-mujoco.sh: could not download MuJoCo $version ($wheel) from PyPI, and the cache" >&2
  echo "  $dest" >&2
  echo "does not hold it. Connect to PyPI and rerun, or build against Debian's MuJoCo 2.2.2:" >&2
  echo "  make test MUJOCO=debian   (or cmake -DPLUMB_MUJOCO=debian)" >&2
  sed 's/^/  pip: /' "$work/pip.log" | tail -3 >&2
  exit 2
fi
actual=$(sha256sum "$work/wheel/$wheel" | cut -d' ' -f1)
if [[ "$actual" != "$sha" ]]; then
  echo "fetch-mujoco.sh: checksum mismatch for $wheel: expected $sha, got $actual; nothing unpacked." >&2
  exit 2
fi

stage="$work/mujoco-$version"
mkdir -p "$stage/lib" "$stage/include" "$stage/bin/mujoco_plugin"
python3 - "$work/wheel/$wheel" "$stage" <<'PY'
import os, shutil, sys, zipfile
wheel, stage = sys.argv[1], sys.argv[2]
with zipfile.ZipFile(wheel) as z:
    for name in z.namelist():
        if name.endswith("/"):
            continue
        if name.startswith("mujoco/libmujoco.so"):
            target = os.path.join(stage, "lib", os.path.basename(name))
        elif name.startswith("mujoco/include/mujoco/"):
            target = os.path.join(stage, "include", name[len("mujoco/include/"):])
        elif name.startswith("mujoco/plugin/") and name.endswith(".so"):
            target = os.path.join(stage, "bin", "mujoco_plugin", os.path.basename(name))
        else:
            continue
        os.makedirs(os.path.dirname(target), exist_ok=True)
        with z.open(name) as src, open(target, "wb") as dst:
            shutil.copyfileobj(src, dst)
        if target.endswith(".so") or ".so." in target:
            os.chmod(target, 0o755)
PY
real=$(cd "$stage/lib" && ls libmujoco.so.* | head -1)
[[ -n "$real" ]] || { echo "fetch-mujoco.sh: $wheel holds no libmujoco; nothing unpacked." >&2; exit 2; }
ln -s "$real" "$stage/lib/libmujoco.so"
echo "$version $dist $wheel $sha" > "$stage/.complete"
rm -rf "$dest"
mv "$stage" "$dest"
done_
