#!/usr/bin/env bash
# Installs what plumb needs to build, test and benchmark: Debian packages, and the MuJoCo
# release to build against.
#
# Idempotent: checks each package with dpkg-query first, prints nothing and touches
# nothing when all are present, runs `apt-get update` only when something is missing,
# and uses sudo when not run as root. MuJoCo comes from its PyPI wheel into plumb's cache
# (scripts/fetch-mujoco.sh; a second run fetches nothing), or from Debian with `debian`.
#
# Usage: scripts/install-deps.sh [--mujoco VERSION|debian] [--print]
#   --mujoco   4.0.1 (default), 3.11.0 or another version pinned in
#              cmake/mujoco-wheels.lock; `debian` is Debian's libmujoco-dev 2.2.2
#   --print    lists missing Debian packages only
# Exit codes: 0 ready, 2 bad option, no root, or MuJoCo cannot be fetched.
set -euo pipefail

mujoco=4.0.1
print=0
while [[ $# -gt 0 ]]; do
  case "$1" in
    --print) print=1 ;;
    --mujoco) mujoco="${2:-}"; shift ;;
    --mujoco=*) mujoco="${1#--mujoco=}" ;;
    *) echo "install-deps.sh: unknown option '$1' (use --mujoco VERSION|debian, --print)" >&2; exit 2 ;;
  esac
  shift
done
if [[ -z "$mujoco" ]]; then
  echo "install-deps.sh: --mujoco needs a version (4.0.1, 3.11.0) or debian" >&2
  exit 2
fi

packages=(
  build-essential cmake pkg-config git ccache
  libmujoco-dev libmujoco-samples
  libcli11-dev nlohmann-json3-dev libfmt-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libsqlite3-dev libtbb-dev libtomlplusplus-dev
  libopenmpi-dev openmpi-bin
  valgrind sqlite3 python3-pip python3-venv python3-dev clang libclang-rt-14-dev
  libceres-dev libpng-dev libegl-dev libegl-mesa0 libgl1-mesa-dri libosmesa6-dev ffmpeg libjs-chart.js
  chromium cyclonedds-dev cyclonedds-tools strace
)

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done

if [[ $print -eq 1 ]]; then
  if [[ ${#missing[@]} -gt 0 ]]; then printf '%s\n' "${missing[@]}"; fi
  exit 0
fi

fetch_mujoco() {
  [[ "$mujoco" == debian ]] || "$(dirname "$0")/fetch-mujoco.sh" "$mujoco"
}
if [[ ${#missing[@]} -eq 0 ]]; then
  fetch_mujoco
  exit 0
fi

if [[ $(id -u) -eq 0 ]]; then
  sudo=()
elif command -v sudo >/dev/null 2>&1; then
  sudo=(sudo)
else
  echo "install-deps.sh: missing packages: ${missing[*]}" >&2
  echo "install-deps.sh: not root and no sudo; install them as root, then rerun." >&2
  exit 2
fi

echo "install-deps.sh: installing ${missing[*]}" >&2
# sudo resets the environment, so the front-end setting goes on the command itself
apt=("${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get)
"${apt[@]}" update -qq
"${apt[@]}" install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fetch_mujoco
