#!/usr/bin/env bash
# Makes (once) a test-only virtual environment from a hash-pinned requirements file and
# prints its python: Playwright for the browser test (tests/report/requirements-browser.txt,
# the default), fastcrc for the Unitree CRC cross-check (tests/bridge/requirements-crc.txt).
#
# Usage: scripts/test-venv.sh DIR [REQUIREMENTS]   (DIR is made if missing; reused while
#        complete for the same requirements)
# Exit codes: 0 ready, 2 no DIR given, python3 -m venv missing, or pip failed.
# PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD is set: the tests launch Debian's /usr/bin/chromium.
set -euo pipefail
dir="${1:-}"
if [[ -z "$dir" ]]; then
  echo "test-venv.sh: give the folder for the virtual environment" >&2
  exit 2
fi
here="$(cd "$(dirname "$0")/.." && pwd)"
requirements="${2:-$here/tests/report/requirements-browser.txt}"
stamp="$dir/.complete-$(sha256sum "$requirements" | cut -c1-16)"
if [[ -f "$stamp" ]]; then
  echo "$dir/bin/python"
  exit 0
fi
rm -rf "$dir"
if ! python3 -m venv "$dir" >/dev/null 2>&1; then
  echo "test-venv.sh: python3 -m venv failed (Debian: apt-get install python3-venv)" >&2
  exit 2
fi
export PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1
if ! "$dir/bin/pip" install -q --disable-pip-version-check --require-hashes \
    -r "$requirements" >&2; then
  echo "test-venv.sh: pip could not install $requirements from PyPI" >&2
  exit 2
fi
touch "$stamp"
echo "$dir/bin/python"
