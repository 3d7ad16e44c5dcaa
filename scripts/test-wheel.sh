#!/usr/bin/env bash
# The wheel's CI leg (make test-wheel): builds and repairs plumb's wheel (build-wheel.sh),
# installs it into a fresh venv that holds only mujoco-core, numpy and pytest (hash-pinned,
# python/requirements-wheel-test.txt; the wheel itself with --no-index, so its requirements
# must be met by them), and runs tests/wheel there: the API, `plumb` on PATH, the bundled
# libraries and their licences, and the pytest plugin on examples/model_ci. It prints its
# seconds. Exit codes: 0 passed, 1 a test failed, 2 the wheel or the venv could not be made.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
start=$(date +%s)
wheel=$("$here/scripts/build-wheel.sh" | tail -1) || exit 2
built=$(date +%s)

venv="$here/build-wheel/venv"
rm -rf "$venv"
python3 -m venv "$venv" || exit 2
"$venv/bin/pip" install -q --disable-pip-version-check --require-hashes \
  -r "$here/python/requirements-wheel-test.txt" || exit 2
"$venv/bin/pip" install -q --disable-pip-version-check --no-index "$wheel" || exit 2
"$venv/bin/pip" check --disable-pip-version-check

# from a folder outside the checkout, with the venv's bin first on PATH, as a user has it
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
status=0
# the repaired wheel before its licences were added, and the build tools' python: for the
# test that an unreviewed bundled library stops the build
tools="$("$here/scripts/build-wheel.sh" --tools)"
(cd "$work" && PATH="$venv/bin:$PATH" PLUMB_SOURCE="$here" PLUMB_WHEEL_TOOLS_PYTHON="$tools" \
  PLUMB_REPAIRED_WHEEL="$(ls "$here"/build-wheel/raw/repaired/plumb_mujoco-*.whl)" \
  "$venv/bin/python" -m pytest -q \
  -p no:cacheprovider --rootdir "$work" "$here/tests/wheel") || status=$?
# MuJoCo Warp beside plumb, as docs/python.md ("Installing") says: mujoco-warp 4.0.0 requires
# the `mujoco` distribution, which pip satisfies with mujoco 3.17.0 (its `mujoco` package
# would overwrite mujoco-core 4.0.1's), so the wheel's own lock installs it without
# dependencies; then both import, on one MuJoCo
if [[ $status -eq 0 ]]; then
  engines="$("$venv/bin/python" -c 'import importlib.util, os; print(os.path.join(
    importlib.util.find_spec("plumb").submodule_search_locations[0], "share/plumb/engines"))')"
  "$venv/bin/pip" install -q --disable-pip-version-check --no-deps --require-hashes \
    -r "$engines/requirements-warp.txt" || exit 2
  (cd "$work" && "$venv/bin/python" -c '
import mujoco, mujoco_warp, plumb
assert mujoco.__version__ == "4.0.1", mujoco.__version__
assert plumb.verify(mujoco.MjModel.from_xml_path("'"$here"'/models/pendulum.xml")).ok
print("== mujoco-warp", mujoco_warp.__name__, "beside plumb: one MuJoCo,", mujoco.__version__)
') || status=$?
fi
echo "== the wheel: $(basename "$wheel") ($(du -m "$wheel" | cut -f1) MB): built and" \
  "repaired in $((built - start)) s, installed and tested in $(( $(date +%s) - built )) s"
exit $status
