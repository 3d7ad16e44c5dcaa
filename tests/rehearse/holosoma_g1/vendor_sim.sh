#!/usr/bin/env bash
# The same rehearsal on holosoma's own simulator instead of plumb bridge, for the numbers side
# by side: holosoma 0.0.3's run_sim.py (MuJoCo, headless, realtime, its own DDS bridge through
# far-unitree-sdk 0.1.8), the same policy and deploy script (run_policy.py, as run.sh runs it),
# and tests/rehearse/sim_operator.py playing the same gamepad file and recording the base from
# rt/odommodestate into a log measure.py reads. Its virtual gantry is set as the bridge's band
# (anchored 1 m above the pelvis, k 1000 N/m, c 200 N s/m, rest length carrying the robot) and
# let go at 6 s (vendor_sim.py).
#
# The simulator's environment is heavy and is not pinned: holosoma's run_sim imports torch,
# tensordict, warp, opencv, wandb, boto3, pygame ... (about 6 GB with PyPI's torch). Make it by
# hand (bench only, see bench/rehearse_policies.sh):
#   python3 -m venv SIMVENV && SIMVENV/bin/pip install holosoma==0.0.3 far-unitree-sdk==0.1.8 \
#     mujoco torch tensordict warp-lang opencv-python-headless wandb pygame boto3 ...
#
# Usage: vendor_sim.sh --sim-venv DIR [--venv DIR] [--sdk2-venv DIR] [--until S] [--out DIR]
# Exit codes: 0 it stood and walked, 1 it did not, 2 bad use or set-up.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/../../.." && pwd)"
until=20 out="" venv="$repo/build/rehearse-venv" simvenv="" sdk2="$repo/build/tests/sdk2-venv"
while [[ $# -gt 0 ]]; do
  case "$1" in
    --until) until="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --venv) venv="$2"; shift 2 ;;
    --sim-venv) simvenv="$2"; shift 2 ;;
    --sdk2-venv) sdk2="$2"; shift 2 ;;
    *) echo "vendor_sim.sh: unknown argument '$1' (see the header of $0)" >&2; exit 2 ;;
  esac
done
for v in "$venv" "$simvenv" "$sdk2"; do
  [[ -n "$v" && -x "$v/bin/python" ]] || { echo "vendor_sim.sh: no environment at '$v' (see the header of $0)" >&2; exit 2; }
done
[[ -n "$out" ]] || out="$(mktemp -d "${TMPDIR:-/tmp}/rehearse-holosoma-g1-vendor.XXXXXX")"
mkdir -p "$out"

# (tyro: a subcommand's options follow it). Physics at 500 Hz with the PD law every step (the
# model file's 2 ms timestep, as plumb bridge runs it): holosoma's default, 2000 Hz with the PD
# law every 4th step, runs at 0.26x real time here (2 cores), and the policy, paced by the wall
# clock, would then act 4 times as often in simulated time as it was trained to.
OMP_NUM_THREADS=1 "$simvenv/bin/python" "$here/vendor_sim.py" 6.0 --training.headless True \
  simulator:mujoco --simulator.config.sim.fps 500 --simulator.config.sim.control-decimation 1 \
  --simulator.config.bridge.interface lo \
  --simulator.config.virtual-gantry.height 1.8 \
  --simulator.config.virtual-gantry.stiffness 1000 \
  --simulator.config.virtual-gantry.damping 200 \
  --simulator.config.virtual-gantry.length 0.677 \
  robot:g1-29dof terrain:terrain-locomotion-plane >"$out/sim.txt" 2>&1 &
sim=$!
"$sdk2/bin/python" "$here/../sim_operator.py" --gamepad "$here/gamepad.txt" --until "$until" \
  --out "$out/flight.csv" >"$out/operator.txt" 2>&1 &
operator=$!
# --secondary none: the preset's second policy (X switches to it) is the same FastSAC model as
# its first; with it, beside this simulator (which takes most of the 2 cores), the script took
# A but missed the start press in 2 runs of 3; without it, it took it (1 of 1). Under the bridge
# it took every press with the preset as it is (6 of 6).
LOGURU_LEVEL=INFO "$venv/bin/python" -m holosoma_inference.run_policy inference:g1-29dof-loco \
  --task.use-joystick --task.interface lo --secondary none >"$out/policy.txt" 2>&1 &
policy=$!
status=0
wait "$operator" || status=$?
for p in "$policy" "$sim"; do
  kill -INT "$p" 2>/dev/null || true
  for _ in 1 2 3 4 5 6 7 8 9 10; do kill -0 "$p" 2>/dev/null || break; sleep 0.5; done
  kill -KILL "$p" 2>/dev/null || true
  wait "$p" 2>/dev/null || true
done
if [[ $status -ne 0 ]]; then
  echo "vendor_sim.sh: the operator exited $status (see $out/operator.txt, $out/sim.txt)" >&2
  exit 2
fi
python3 "$here/../measure.py" "$out/flight.csv" --after 6 --walk 10 17 --json \
  | tee "$out/verdict.json"
python3 "$here/../measure.py" "$out/flight.csv" --after 6 --walk 10 17 >/dev/null
