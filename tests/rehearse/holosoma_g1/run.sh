#!/usr/bin/env bash
# Rehearsal: Amazon FAR's holosoma G1 locomotion policy, driven by holosoma_inference's own
# deploy script (python -m holosoma_inference.run_policy inference:g1-29dof-loco
# --task.use-joystick, unmodified, from PyPI), against `plumb bridge` running holosoma's own G1
# model (PyPI's holosoma 0.0.3) as the robot. The policy talks Unitree SDK2 over CycloneDDS on
# the loopback interface (far-unitree-sdk: Unitree's C++ SDK2 bound with pybind11); the
# gamepad script presses A (start the policy), then start (walk) and pushes the left stick.
#
# Usage: run.sh [--mode lockstep|realtime] [--until S] [--out DIR] [--venv DIR] [--plumb EXE]
#   --until   simulated seconds (default 20: A at 4 s, band let go at 6 s, walk from 8 s, stick 9-17 s)
#   --out     folder for flight.csv, bridge.txt, policy.txt, verdict.json (default: a new one
#             under ${TMPDIR:-/tmp})
#   --venv    the environment scripts/rehearse-venv.sh makes (default build/rehearse-venv)
# Exit codes: 0 it stood and walked, 1 it did not, 2 bad use or set-up (no venv, no plumb).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/../../.." && pwd)"
mode=lockstep until=20 out="" venv="$repo/build/rehearse-venv" plumb="$repo/build/plumb"
while [[ $# -gt 0 ]]; do
  case "$1" in
    --mode) mode="$2"; shift 2 ;;
    --until) until="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --venv) venv="$2"; shift 2 ;;
    --plumb) plumb="$2"; shift 2 ;;
    *) echo "run.sh: unknown argument '$1' (see the header of $0)" >&2; exit 2 ;;
  esac
done
python="$venv/bin/python"
[[ -x "$python" ]] || { echo "run.sh: no environment at $venv: make it with scripts/rehearse-venv.sh $venv" >&2; exit 2; }
[[ -x "$plumb" ]] || { echo "run.sh: no plumb at $plumb: build the plumb_cli target" >&2; exit 2; }
site="$("$python" -c 'import holosoma, os; print(os.path.dirname(holosoma.__file__))' 2>/dev/null)" ||
  { echo "run.sh: holosoma (the model's package) is not in $venv" >&2; exit 2; }
model="$site/data/robots/g1/scenes/scene_g1_29dof_wbt_plane.xml"
[[ -n "$out" ]] || out="$(mktemp -d "${TMPDIR:-/tmp}/rehearse-holosoma-g1.XXXXXX")"
mkdir -p "$out"
# the walk is judged from 10 s until the stick lets go (17 s) or the rehearsal ends
walk_end=$(python3 -c 'import sys; print(min(17.0, float(sys.argv[1])))' "$until")

client="$python -m holosoma_inference.run_policy inference:g1-29dof-loco --task.use-joystick --task.interface lo"
bridge=("$plumb" bridge "$model" --config "$here/bridge.toml" --pose "$here/pose.txt"
  --gamepad "$here/gamepad.txt" --mode "$mode" --until "$until" --log "$out/flight.csv")
# plumb starts the vendor's deploy script once the bridge is up, stops it (SIGINT, as its README
# stops it) at --until and judges: the band lets go at 6 s, A started the policy at 4 s, the
# stick asks for 0.5 m/s from 9 s
verdict=0
# (onnxruntime keeps a device id below XDG_CACHE_HOME: the run's folder, not the user's cache)
"${bridge[@]}" --client "$client" --client-env LOGURU_LEVEL=INFO \
  --client-env "XDG_CACHE_HOME=$out/cache" \
  --client-output "$out/policy.txt" --first-command-timeout 60 \
  --assert "min(qpos[floating_base_joint][2]) > 0.5 during [6, $until]" \
  --assert "mean(qvel[floating_base_joint][0]) > 0.15 during [10, $walk_end]" \
  --format json >"$out/rehearsal.json" 2>"$out/bridge.txt" || verdict=$?
if [[ $verdict -ne 0 && $verdict -ne 1 ]]; then
  echo "run.sh: plumb bridge --client exited $verdict (see $out/bridge.txt)" >&2
  exit 2
fi
# the verdict in a line, and every row that did not pass
python3 - "$out/rehearsal.json" <<'PY' || true
import json, sys
r = json.load(open(sys.argv[1]))
print("rehearsal", "PASS" if r["passed"] else "FAIL", r["summary"])
for row in r["rows"]:
    if row["status"] != "PASS":
        print(" ", row["status"], row["id"], row["element"], row["measured_text"])
PY
python3 "$here/../measure.py" "$out/flight.csv" --after 6 --walk 10 "$walk_end" --json \
  | tee "$out/verdict.json"
python3 "$here/../measure.py" "$out/flight.csv" --after 6 --walk 10 "$walk_end" >/dev/null
exit "$verdict"
