#!/usr/bin/env bash
# plumb identify against MuJoCo's own system-identification toolbox, mujoco.sysid
# (mujoco-core 4.0.1 from PyPI), on logs simulated from a known truth with noise: the
# two-joint arm of tests/models/arm2.xml (damping, armature and friction loss of both joints,
# chirps on both motors) and the chapter's pendulum (its damping, from a free decay). Both
# fit the same parameters from the same wrong guess and bounds; the table gives each
# estimate with its standard error, the rms of the residuals of both fitted parameter sets
# replayed the same way, and the wall and CPU time of each, all from one run
# (bench/identify_peer.py says how each is measured).
#
# The peer is installed into a virtual environment, for this benchmark only, from
# bench/requirements-sysid.txt (hash-pinned, CPython 3.11 on x86_64); the build never uses
# Python.
#
# Usage: bench/identify_peer.sh [VENV_DIR] [PLUMB] [-- identify_peer.py options]
#   VENV_DIR  where the virtual environment is made (default build/sysid-venv; reused)
#   PLUMB     the plumb binary (default build/plumb)
#   env: REPEAT (3 timed runs of each tool per case), COVERAGE (10 further noise seeds,
#        untimed, for the standard errors' honesty), SEED (1), PYTHON (python3, a CPython 3.11)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
venv=$here/build/sysid-venv plumb=$here/build/plumb
if [[ $# -gt 0 && $1 != -- ]]; then venv=$1; shift; fi
if [[ $# -gt 0 && $1 != -- ]]; then plumb=$1; shift; fi
[[ $# -gt 0 && $1 == -- ]] && shift
[[ -x "$plumb" ]] || { echo "no $plumb: run make build first, or give the binary" >&2; exit 2; }
python=${PYTHON:-python3}
version=$("$python" -c 'import sys; print("%d.%d" % sys.version_info[:2])')
[[ "$version" == 3.11 ]] ||
  echo "warning: $python is Python $version; bench/requirements-sysid.txt pins wheels for 3.11" >&2

if [[ ! -x "$venv/bin/python" ]]; then
  "$python" -m venv "$venv"
fi
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check --require-hashes \
  -r "$here/bench/requirements-sysid.txt"

"$venv/bin/python" "$here/bench/identify_peer.py" "$plumb" --repeat "${REPEAT:-3}" \
  --coverage "${COVERAGE:-10}" --seed "${SEED:-1}" "$@"
