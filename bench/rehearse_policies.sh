#!/usr/bin/env bash
# The long policy rehearsals (issue 48): each vendor's trained policy, driven by its own deploy
# script, on plumb bridge in lockstep and in realtime, and (when its environment is given) on
# the vendor's own simulator, the numbers side by side. See tests/rehearse/README.md.
#
# Pairs: holosoma_g1 (Amazon FAR holosoma's G1 29-DoF locomotion policy, run_policy.py,
# far-unitree-sdk, holosoma's G1 model, all from PyPI); unitree_rl_gym_g1 (Unitree's G1 12-DoF
# policy, deploy_real.py, unitree_sdk2py, the repository's G1; GitHub only: with --rl-gym).
#
# Usage: bench/rehearse_policies.sh [--until S] [--runs N] [--sim-venv DIR] [--out DIR]
#   --until     simulated seconds a run (default 30; the gamepad script walks 9-17 s)
#   --runs      runs of each kind (default 2)
#   --sim-venv  holosoma's simulator environment (tests/rehearse/holosoma_g1/vendor_sim.sh's
#               header says how to make it; about 6 GB): adds the vendor-simulator runs
#   --out       folder for every run's logs (default: a new one under ${TMPDIR:-/tmp})
#   --rl-gym DIR --rl-gym-python PY   a checkout of unitree_rl_gym and a python with
#               unitree_sdk2py, torch, mujoco, pyyaml (and xvfb-run): adds its runs
# Needs build/plumb (target plumb_cli), the rehearsal environment (scripts/rehearse-venv.sh
# build/rehearse-venv, made here when missing) and, for the vendor simulator, the SDK2 one
# (scripts/sdk2-venv.sh build/tests/sdk2-venv).
# Prints one line a run: kind, stood, lowest base height after the release, largest tilt,
# forward metres and mean speed in the walk window, the bridge's realtime factor.
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
until=30 runs=2 simvenv="" out="" gym="" gympy=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --until) until="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --sim-venv) simvenv="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --rl-gym) gym="$2"; shift 2 ;;
    --rl-gym-python) gympy="$2"; shift 2 ;;
    *) echo "rehearse_policies.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
[[ -n "$out" ]] || out="$(mktemp -d "${TMPDIR:-/tmp}/rehearse-policies.XXXXXX")"
venv="$repo/build/rehearse-venv"
"$repo/scripts/rehearse-venv.sh" "$venv" >/dev/null

row() {  # KIND DIR
  python3 - "$1" "$2" <<'EOF'
import json, re, sys
kind, d = sys.argv[1], sys.argv[2]
try:
    v = json.load(open(f"{d}/verdict.json"))
except (OSError, ValueError):
    print(f"{kind:22} no verdict (see {d})"); sys.exit()
rtf = ""
try:
    m = re.search(r"realtime factor ([0-9.]+), (\d+) late periods", open(f"{d}/bridge.txt").read())
    rtf = f"rtf {m.group(1)}, {m.group(2)} late" if m else ""
except OSError:
    pass
print(f"{kind:22} stood {str(v['stood']):5} lowest {v['lowest_after_m']:.3f} m  tilt "
      f"{v['max_tilt_after_deg']:5.2f} deg  forward {v.get('forward_m', 0):6.3f} m  "
      f"{v.get('mean_forward_speed_mps', 0):.3f} m/s  {rtf}")
EOF
}

for n in $(seq 1 "$runs"); do
  for mode in lockstep realtime; do
    d="$out/holosoma_g1-$mode-$n"
    "$repo/tests/rehearse/holosoma_g1/run.sh" --mode "$mode" --until "$until" --out "$d" \
      --venv "$venv" >/dev/null 2>&1 || true
    row "holosoma_g1 $mode" "$d"
  done
  if [[ -n "$simvenv" ]]; then
    d="$out/holosoma_g1-vendor-$n"
    "$repo/tests/rehearse/holosoma_g1/vendor_sim.sh" --sim-venv "$simvenv" --until "$until" \
      --out "$d" --venv "$venv" >/dev/null 2>&1 || true
    row "holosoma_g1 vendor sim" "$d"
  fi
  if [[ -n "$gym" ]]; then
    for robot in g1 h1; do
      for mode in lockstep realtime; do
        d="$out/rl_gym_$robot-$mode-$n"
        "$repo/tests/rehearse/unitree_rl_gym/run.sh" --rl-gym "$gym" --python "$gympy" \
          --robot "$robot" --mode "$mode" --until "$until" --out "$d" >/dev/null 2>&1 || true
        row "rl_gym_$robot $mode" "$d"
      done
    done
    for robot in g1 h1; do
      d="$out/rl_gym_$robot-vendor-$n"
      "$repo/tests/rehearse/unitree_rl_gym/vendor_sim.sh" --rl-gym "$gym" --python "$gympy" \
        --robot "$robot" --out "$d" >/dev/null 2>&1 || true
      row "rl_gym_$robot vendor sim" "$d"
    done
  fi
done
echo "logs: $out"
