#!/usr/bin/env bash
# Makes (once) the throw-away virtual environment with Unitree's Python SDK for the
# wire-compatibility test (tests/bridge/requirements-sdk2*.txt) and prints its python.
# CycloneDDS's Python binding is built from source against Debian's cyclonedds-dev, which
# keeps libddsc in the multiarch folder: a small CYCLONEDDS_HOME of links shows it where.
#
# Usage: scripts/sdk2-venv.sh DIR   (as scripts/test-venv.sh)
# Exit codes: 0 ready, 2 no DIR given, cyclonedds-dev or python3-venv missing, pip failed.
set -euo pipefail
dir="${1:?sdk2-venv.sh: give the folder for the virtual environment}"
here="$(cd "$(dirname "$0")/.." && pwd)"
multiarch="$(gcc -print-multiarch 2>/dev/null || dpkg-architecture -qDEB_HOST_MULTIARCH)"
if [[ ! -e /usr/lib/$multiarch/libddsc.so || ! -e /usr/include/dds/dds.h ]]; then
  echo "sdk2-venv.sh: CycloneDDS's C library is missing (Debian: apt-get install cyclonedds-dev)" >&2
  exit 2
fi
home="$dir-cyclonedds-home"
mkdir -p "$home"
ln -sfn /usr/include "$home/include"
ln -sfn /usr/bin "$home/bin"
ln -sfn "/usr/lib/$multiarch" "$home/lib"
# opencv-python, which the SDK lists, is not needed to talk DDS: no dependencies are taken
# that the files do not pin
CYCLONEDDS_HOME="$home" PLUMB_PIP_OPTIONS="--no-deps --no-build-isolation" \
  exec "$here/scripts/test-venv.sh" "$dir" "$here/tests/bridge/requirements-sdk2-build.txt" \
  "$here/tests/bridge/requirements-sdk2.txt"
