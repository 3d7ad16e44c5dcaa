#!/usr/bin/env bash
# Runs every libFuzzer target of a fuzz build for SECONDS each, starting from the seed corpus
# in tests/fuzz/corpus/<target>/ (new inputs go to BUILD/fuzz-corpus/<target>/, never into the
# source tree), and prints the executions per target. A crash, leak, sanitizer report,
# timeout (10 s an input) or memory blow-up (2 GB) fails the run; the input that did it is
# kept in BUILD/fuzz-crashes/<target>/ and named in the output: make it a regression test.
#
# Usage: scripts/run-fuzzers.sh BUILD [SECONDS]   (default 60)
# Exit codes: 0 nothing found, 1 a finding, 2 no fuzz build at BUILD.
set -uo pipefail
build="${1:?run-fuzzers.sh: give the fuzz build folder (make test-fuzz makes build-fuzz)}"
seconds="${2:-60}"
root="$(cd "$(dirname "$0")/.." && pwd)"
targets=()
for t in "$build"/tests/fuzz/fuzz_*; do
  [[ -x "$t" && ! -d "$t" ]] && targets+=("$t")
done
if [[ ${#targets[@]} -eq 0 ]]; then
  echo "run-fuzzers.sh: no fuzz targets in $build/tests/fuzz (make test-fuzz builds them)" >&2
  exit 2
fi
status=0
printf '%-22s %12s %10s %s\n' target executions "exec/s" result
for t in "${targets[@]}"; do
  name="$(basename "$t")"
  work="$build/fuzz-corpus/$name" crashes="$build/fuzz-crashes/$name"
  mkdir -p "$work" "$crashes"
  log="$build/fuzz-$name.log"
  seeds=()
  [[ -d "$root/tests/fuzz/corpus/$name" ]] && seeds+=("$root/tests/fuzz/corpus/$name")
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    "$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$crashes/" "$work" "${seeds[@]}" >"$log" 2>&1
  rc=$?
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || true)
  rate=$(grep -o 'stat::average_exec_per_sec: *[0-9]*' "$log" | grep -o '[0-9]*$' || true)
  if [[ $rc -eq 0 ]]; then
    printf '%-22s %12s %10s %s\n' "$name" "${runs:-?}" "${rate:-?}" ok
  else
    status=1
    printf '%-22s %12s %10s %s\n' "$name" "${runs:-?}" "${rate:-?}" "FINDING (exit $rc): see $log"
    grep -m3 -E 'ERROR|SUMMARY|Test unit written' "$log" | sed 's/^/    /'
  fi
done
exit $status
