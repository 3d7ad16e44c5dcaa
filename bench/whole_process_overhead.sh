#!/usr/bin/env bash
# Whole-process instruction counts of `plumb run` against a bare C program that loads the same
# model with mj_loadXML and calls mj_step as many times (bench/bare_step.c), on the same
# libmujoco: everything both processes execute, from the dynamic loader to exit, counted
# with valgrind's callgrind (all threads). bench/callgrind_overhead.sh counts only inside
# the stepping loop.
#
# Three plumb commands are counted, each writing to stdout (no output file):
#   lean     plumb run MODEL --until T --every T --columns time,qpos[0] --format csv
#            (the least sampling: the start and the end)
#   csv      plumb run MODEL --until T --format csv
#            (default columns every ~0.1 s as CSV)
#   obvious  plumb run MODEL --until T
#            (what a user types: default columns every ~0.1 s as a table)
# T is STEPS timesteps. The last qpos[0] of the lean run must equal the bare program's,
# so both took the same steps.
#
# Usage: bench/whole_process_overhead.sh [PLUMB] [STEPS]     (default: build/plumb 20000)
#   MODEL=...  another model (default MuJoCo's humanoid)
#   CC=...     the C compiler for the bare program (default cc)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
plumb=${1:-build/plumb}
steps=${2:-20000}
model=${MODEL:-/usr/share/mujoco/model/humanoid/humanoid.xml}
command -v valgrind >/dev/null || { echo "valgrind is not installed" >&2; exit 2; }
[[ -x "$plumb" ]] || { echo "no plumb at $plumb" >&2; exit 2; }
[[ -f "$model" ]] || { echo "no model at $model (set MODEL)" >&2; exit 2; }

# the libmujoco plumb loads, and the headers next to it (a release folder) or the system's
lib=$(ldd "$plumb" | awk '/libmujoco/ {print $3; exit}')
[[ -f "$lib" ]] || { echo "$plumb loads no libmujoco (ldd)" >&2; exit 2; }
include=$(dirname "$(dirname "$lib")")/include
[[ -f "$include/mujoco/mujoco.h" ]] || include=/usr/include
[[ -f "$include/mujoco/mujoco.h" ]] || { echo "no mujoco/mujoco.h for $lib" >&2; exit 2; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"${CC:-cc}" -O2 "$here/bare_step.c" -I "$include" "$lib" -Wl,-rpath,"$(dirname "$lib")" \
  -o "$work/bare_step"

dt=$("$plumb" run "$model" --until 0 --columns opt.timestep --format csv | sed -n 2p)
until=$(awk -v n="$steps" -v dt="$dt" 'BEGIN { printf "%.17g", n * dt }')

count() {  # name command... -> instructions of the whole process; its stdout in $work/name.txt
  local name=$1
  shift
  valgrind --tool=callgrind --callgrind-out-file="$work/$name.out" "$@" \
    >"$work/$name.txt" 2>"$work/$name.log" || { cat "$work/$name.log" >&2; exit 1; }
  awk '/^(summary|totals):/ {print $2; exit}' "$work/$name.out"
}

bare=$(count bare "$work/bare_step" "$model" "$steps")
lean=$(count lean "$plumb" run "$model" --until "$until" --every "$until" \
  --columns 'time,qpos[0]' --format csv)
csv=$(count csv "$plumb" run "$model" --until "$until" --format csv)
obvious=$(count obvious "$plumb" run "$model" --until "$until")

bare_end=$(sed -n 's/^qpos\[0\] after [0-9]* steps: //p' "$work/bare.txt")
lean_end=$(tail -n 1 "$work/lean.txt" | cut -d, -f2)
if ! awk -v a="$bare_end" -v b="$lean_end" 'BEGIN { exit !(a != "" && a + 0 == b + 0) }'; then
  echo "the runs differ: qpos[0] at the end is $bare_end (bare) and $lean_end (plumb)" >&2
  exit 1
fi

echo "model $model, $steps steps of $dt s, $(basename "$lib")"
awk -v b="$bare" -v l="$lean" -v c="$csv" -v o="$obvious" 'BEGIN {
  printf "bare mj_step program   %15.0f instructions\n", b
  printf "plumb run, lean        %15.0f instructions   ratio %.4f\n", l, l / b
  printf "plumb run, csv         %15.0f instructions   ratio %.4f\n", c, c / b
  printf "plumb run, obvious     %15.0f instructions   ratio %.4f\n", o, o / b
}'
