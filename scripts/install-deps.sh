#!/usr/bin/env bash
# Installs the Debian packages plumb needs to build, test and benchmark.
#
# Idempotent: checks each package with dpkg-query first, prints nothing and
# touches nothing when all are present, runs `apt-get update` only when
# something is missing, and uses sudo when not run as root.
#
# Usage: scripts/install-deps.sh [--print]   (--print lists missing packages only)
set -euo pipefail

packages=(
  build-essential cmake pkg-config git
  libmujoco-dev libmujoco-samples
  libcli11-dev nlohmann-json3-dev libfmt-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libsqlite3-dev libtbb-dev libcpptoml-dev
  libopenmpi-dev openmpi-bin
  valgrind sqlite3
)

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done

if [[ "${1:-}" == "--print" ]]; then
  if [[ ${#missing[@]} -gt 0 ]]; then printf '%s\n' "${missing[@]}"; fi
  exit 0
fi
[[ ${#missing[@]} -eq 0 ]] && exit 0

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
