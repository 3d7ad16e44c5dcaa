#!/usr/bin/env bash
# Instruction counts of plumb run's loop against a bare mj_step loop (humanoid, 20 000
# steps, sampling every 0.1 s to CSV), with valgrind's callgrind. Counts are repeatable
# whatever else the machine is doing, unlike wall time on a small shared machine.
# Only the loop is counted; bench/whole_process_overhead.sh counts whole processes of plumb run
# against a bare C program.
#
# Usage: bench/callgrind_overhead.sh [BUILD_DIR]      (default: build)
set -euo pipefail
build=${1:-build}
bench="$build/bench/run_overhead_bench"
[[ -x "$bench" ]] || { echo "no $bench: build with PLUMB_BUILD_BENCHMARKS=ON" >&2; exit 2; }
command -v valgrind >/dev/null || { echo "valgrind is not installed" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

count() {  # variant function -> instructions collected inside that function
  valgrind --tool=callgrind --callgrind-out-file="$work/$1.out" \
    --toggle-collect="$2" "$bench" --count="$1" >/dev/null 2>"$work/$1.log"
  awk '/^(summary|totals):/ {print $2; exit}' "$work/$1.out"
}

bare=$(count bare '*RunBareLoop*')
plumb=$(count plumb '*RunPlumb*')
awk -v b="$bare" -v p="$plumb" 'BEGIN {
  printf "bare mj_step loop   %15.0f instructions\n", b
  printf "plumb run           %15.0f instructions\n", p
  printf "overhead            %15.3f %%\n", 100 * (p - b) / b
}'
