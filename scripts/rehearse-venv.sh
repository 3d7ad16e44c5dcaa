#!/usr/bin/env bash
# Makes (once) the throw-away virtual environment for the policy rehearsals (tests/rehearse/):
# vendors' deploy scripts, their trained policies and the SDK they talk through, from PyPI,
# pinned with hashes (tests/rehearse/requirements-rehearse.txt), and prints its python.
# Nothing is installed that the files do not pin (no dependencies are taken); evdev and
# netifaces are built from source with the venv's own setuptools and the pinned wheel.
#
# Usage: scripts/rehearse-venv.sh DIR   (as scripts/test-venv.sh; about 250 MB of downloads)
# Exit codes: 0 ready, 2 no DIR given, python3-venv missing, pip failed.
set -euo pipefail
dir="${1:?rehearse-venv.sh: give the folder for the virtual environment}"
here="$(cd "$(dirname "$0")/.." && pwd)"
PLUMB_PIP_OPTIONS="--no-deps --no-build-isolation" \
  exec "$here/scripts/test-venv.sh" "$dir" "$here/tests/bridge/requirements-sdk2-build.txt" \
  "$here/tests/rehearse/requirements-rehearse.txt"
