#!/usr/bin/env bash
# Peak RSS of long runs, to show it stays flat as the work grows 10x and 100x:
# plumb run of 10^5, 10^6 and 10^7 steps writing every step as CSV, and plumb rollout of
# 10^4, 10^5 and 10^6 rollouts (to stdout as CSV, and into a results store with --db).
# Prints a Markdown table (peak RSS from /usr/bin/time -v, wall time).
# Usage: bench/rss.sh [PLUMB]   (default build/plumb)
set -euo pipefail
plumb="${1:-build/plumb}"
model="$(cd "$(dirname "$0")/.." && pwd)/models/pendulum.xml"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
measure() {  # label, command...
  local label=$1; shift
  /usr/bin/time -v "$@" >"$work/out" 2>"$work/time" || { cat "$work/time" >&2; exit 1; }
  local rss wall
  rss=$(grep 'Maximum resident' "$work/time" | grep -o '[0-9]*$')
  wall=$(grep 'Elapsed (wall' "$work/time" | awk '{print $NF}')
  awk -v l="$label" -v r="$rss" -v w="$wall" 'BEGIN { printf "| %s | %.1f MB | %s |\n", l, r / 1024, w }'
}
echo "| command | peak RSS | wall (m:ss) |"
echo "|---|---|---|"
for steps in 100000 1000000 10000000; do
  measure "run, $steps steps, CSV of every step to -o" "$plumb" run "$model" \
    --set 'qpos[hinge]=0.7' --until $((steps / 500)) --every 0.002 --format csv -o "$work/run.csv"
  rm -f "$work/run.csv"
done
rollout=(rollout "$model" --until 0.01 --set 'qpos[hinge]=0.7'
         --randomize 'dof_damping[hinge]=U(0,0.1)' --metric 'qpos[hinge]@0.01' --format csv)
for n in 10000 100000 1000000; do
  measure "rollout, $n rollouts, CSV to stdout" "$plumb" "${rollout[@]}" --count $n
  measure "rollout, $n rollouts, --db" "$plumb" "${rollout[@]}" --count $n --db "$work/r.sqlite"
  rm -f "$work"/r.sqlite*
done
