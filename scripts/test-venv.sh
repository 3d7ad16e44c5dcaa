#!/usr/bin/env bash
# Makes (once) a test-only virtual environment from hash-pinned requirements files and
# prints its python: Playwright for the browser test (tests/report/requirements-browser.txt,
# the default), fastcrc for the Unitree CRC cross-check (tests/bridge/requirements-crc.txt),
# Unitree's Python SDK (through scripts/sdk2-venv.sh).
#
# Usage: scripts/test-venv.sh DIR [REQUIREMENTS ...]   (DIR is made if missing; reused while
#        complete for the same requirements). Several files are installed one after the
#        other, each by its own pip run; PLUMB_PIP_OPTIONS adds options to every run.
# Exit codes: 0 ready, 2 no DIR given, python3 -m venv missing, or pip failed.
# PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD is set: the tests launch Debian's /usr/bin/chromium.
# It stops at its first failure, inside command substitutions too (inherit_errexit).
set -euo pipefail
shopt -s inherit_errexit
dir="${1:-}"
if [[ -z "$dir" ]]; then
  echo "test-venv.sh: give the folder for the virtual environment" >&2
  exit 2
fi
shift
here="$(cd "$(dirname "$0")/.." && pwd)" && [[ -n "$here" ]] || exit 2
requirements=("$@")
[[ ${#requirements[@]} -gt 0 ]] || requirements=("$here/tests/report/requirements-browser.txt")
options="${PLUMB_PIP_OPTIONS:-}"
# two tests may ask at once: one makes it, the other waits
if ! mkdir -p -- "$(dirname -- "$dir")" || ! exec 9>"$dir.lock"; then
  echo "test-venv.sh: cannot make the environment $dir: its folder cannot be made or written" >&2
  exit 2
fi
flock 9
stamp="$dir/.complete-$( (cat "${requirements[@]}"; echo "$options") | sha256sum | cut -c1-16)"
if [[ -f "$stamp" ]]; then
  echo "$dir/bin/python"
  exit 0
fi
# what is there is replaced only when it is an environment (or an empty folder): a DIR given by
# mistake (a file, a folder of the user's) is not removed
if [[ -e "$dir" || -L "$dir" ]] && ! [[ -d "$dir" && ! -L "$dir" &&
    ( -f "$dir/pyvenv.cfg" || -z "$(ls -A -- "$dir")" ) ]]; then
  echo "test-venv.sh: $dir exists and is not a virtual environment: give another folder, or" \
    "remove it yourself" >&2
  exit 2
fi
rm -rf "$dir"
if ! python3 -m venv "$dir" >/dev/null 2>&1; then
  echo "test-venv.sh: python3 -m venv failed (Debian: apt-get install python3-venv)" >&2
  exit 2
fi
export PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1
for file in "${requirements[@]}"; do
  # shellcheck disable=SC2086  # the options are words
  if ! "$dir/bin/pip" install -q --disable-pip-version-check --require-hashes $options \
      -r "$file" >&2; then
    echo "test-venv.sh: pip could not install $file from PyPI" >&2
    exit 2
  fi
done
touch "$stamp"
echo "$dir/bin/python"
