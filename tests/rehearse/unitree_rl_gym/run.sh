#!/usr/bin/env bash
# Rehearsal: Unitree's G1 or H1 locomotion policy (unitree_rl_gym deploy/pre_train/ROBOT/
# motion.pt, TorchScript) driven by Unitree's own deploy script, unmodified (deploy/deploy_real/
# deploy_real.py lo ROBOT.yaml: unitree_sdk2py over CycloneDDS on loopback), against plumb
# bridge running the repository's own model of the robot (the 12-DoF G1's
# resources/robots/g1_description/scene.xml, unitree_hg; the 10-DoF H1's
# resources/robots/h1/scene.xml, unitree_go), through plumb bridge --client (ROBOT.toml).
# unitree_rl_gym (BSD-3-Clause) is published on GitHub only, which CI does not reach, and none
# of it is committed here: give a checkout.
#
# Usage: run.sh --rl-gym DIR --python PY [--robot g1|h1] [--mode lockstep|realtime] [--until S]
#                [--out DIR] [--plumb EXE]
#   --rl-gym  a checkout of unitreerobotics/unitree_rl_gym (the script's LEGGED_GYM_ROOT_DIR)
#   --python  a python with unitree_sdk2py (scripts/sdk2-venv.sh), torch, numpy and pyyaml
#   --until   simulated seconds (default 24: start at 5 s, A at 8 s, band let go at 10 s,
#             stick 12-20 s)
# Exit codes: 0 it stood and walked, 1 it did not, 2 bad use or set-up.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/../../.." && pwd)"
robot=g1 mode=lockstep until=24 out="" gym="" python="" plumb="$repo/build/plumb"
while [[ $# -gt 0 ]]; do
  case "$1" in
    --robot) robot="$2"; shift 2 ;;
    --mode) mode="$2"; shift 2 ;;
    --until) until="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --rl-gym) gym="$2"; shift 2 ;;
    --python) python="$2"; shift 2 ;;
    --plumb) plumb="$2"; shift 2 ;;
    *) echo "run.sh: unknown argument '$1' (see the header of $0)" >&2; exit 2 ;;
  esac
done
[[ -n "$gym" && -f "$gym/deploy/deploy_real/deploy_real.py" ]] ||
  { echo "run.sh: --rl-gym must name a checkout of unitree_rl_gym" >&2; exit 2; }
[[ -n "$python" && -x "$python" ]] || { echo "run.sh: --python must name a python" >&2; exit 2; }
case "$robot" in
  g1) scene=resources/robots/g1_description/scene.xml ;;
  h1) scene=resources/robots/h1/scene.xml ;;
  *) echo "run.sh: --robot must be g1 or h1" >&2; exit 2 ;;
esac
[[ -n "$out" ]] || out="$(mktemp -d "${TMPDIR:-/tmp}/rehearse-rl-gym-$robot.XXXXXX")"
mkdir -p "$out"
gym="$(cd "$gym" && pwd)"
# realtime: a state every 2 ms as the robot's, the latest command in force (lockstep: one
# command, one 20 ms period)
config="$here/$robot.toml"
if [[ "$mode" == realtime ]]; then
  sed 's/^control_period = 0.02$/control_period = 0.002/' "$config" >"$out/bridge.toml"
  config="$out/bridge.toml"
fi
status=0
"$plumb" bridge "$gym/$scene" --config "$config" \
  --gamepad "$here/gamepad.txt" --mode "$mode" --until "$until" --log "$out/flight.csv" \
  --client "$python deploy_real.py lo $robot.yaml" --client-cwd "$gym/deploy/deploy_real" \
  --client-env "PYTHONPATH=$gym" --client-output "$out/policy.txt" --first-command-timeout 60 \
  --assert "min(qpos[floating_base_joint][2]) > 0.5 during [10, $until]" \
  --assert "mean(qvel[floating_base_joint][0]) > 0.15 during [14, 20]" \
  >"$out/bridge.txt" 2>&1 || status=$?
if [[ $status -ne 0 && $status -ne 1 ]]; then
  echo "run.sh: plumb bridge --client exited $status (see $out/bridge.txt)" >&2
  exit 2
fi
grep -E '^rehearsal|^plumb bridge:' "$out/bridge.txt" || true
python3 "$here/../measure.py" "$out/flight.csv" --after 10 --walk 14 20 --json \
  | tee "$out/verdict.json"
python3 "$here/../measure.py" "$out/flight.csv" --after 10 --walk 14 20 >/dev/null
