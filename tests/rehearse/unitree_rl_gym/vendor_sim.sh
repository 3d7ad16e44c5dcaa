#!/usr/bin/env bash
# The same policy on Unitree's own sim-to-sim script, unmodified, for the numbers side by side:
# unitree_rl_gym's deploy/deploy_mujoco/deploy_mujoco.py ROBOT.yaml (MuJoCo from PyPI, its
# passive viewer under xvfb-run: Debian's xvfb), which starts the G1 or H1 standing at the model's pose and
# walks it at cmd_init = 0.5 m/s from the start; tests/rehearse/observe_mujoco.py records the
# base every 10 physics steps (simulated time) for measure.py.
#
# Usage: vendor_sim.sh --rl-gym DIR --python PY [--robot g1|h1] [--out DIR]
#   (PY: torch, mujoco, pyyaml)
# Exit codes: 0 it stood and walked, 1 it did not, 2 bad use or set-up.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
robot=g1 out="" gym="" python=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --robot) robot="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --rl-gym) gym="$2"; shift 2 ;;
    --python) python="$2"; shift 2 ;;
    *) echo "vendor_sim.sh: unknown argument '$1' (see the header of $0)" >&2; exit 2 ;;
  esac
done
[[ -n "$gym" && -f "$gym/deploy/deploy_mujoco/deploy_mujoco.py" ]] ||
  { echo "vendor_sim.sh: --rl-gym must name a checkout of unitree_rl_gym" >&2; exit 2; }
command -v xvfb-run >/dev/null || { echo "vendor_sim.sh: no xvfb-run (Debian: apt-get install xvfb)" >&2; exit 2; }
[[ -n "$out" ]] || out="$(mktemp -d "${TMPDIR:-/tmp}/rehearse-rl-gym-$robot-vendor.XXXXXX")"
mkdir -p "$out"
gym="$(cd "$gym" && pwd)"
# the script runs simulation_duration = 60 s of wall time; its viewer may crash under xvfb
# before (it did at 8 s once): what it simulated until then is measured
(cd "$gym/deploy/deploy_mujoco" && PYTHONPATH="$gym" LIBGL_ALWAYS_SOFTWARE=1 timeout 90 \
  xvfb-run -a -s "-screen 0 640x480x24" "$python" "$here/../observe_mujoco.py" \
  "$out/flight.csv" deploy_mujoco.py "$robot.yaml") >"$out/sim.txt" 2>&1 || true
python3 "$here/../measure.py" "$out/flight.csv" --after 0 --walk 2 8 --json | tee "$out/verdict.json"
python3 "$here/../measure.py" "$out/flight.csv" --after 0 --walk 2 8 >/dev/null
