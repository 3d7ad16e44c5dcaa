#!/usr/bin/env bash
# The robot corpus table of bench/RESULTS.md: for every model of the corpus
# (scripts/fetch-robots.sh), whole-process seconds of plumb inspect, verify and audit and
# their verdict lines.
#
# Usage: bench/corpus_table.sh [BUILD_DIR]
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
plumb="$(realpath "${1:-$here/build}/plumb")"
root=$("$here/scripts/fetch-robots.sh" --path)
# plumb runs in a folder of its own: a diverging verify writes its plumb-repro-* folder there,
# not into the current folder
work=$(mktemp -d) && [[ -n "$work" ]] || exit 1
trap 'rm -rf "$work"' EXIT
echo "| model | inspect s | verify s | verify | audit s | audit |"
echo "|---|---|---|---|---|---|"
while read -r file; do
  row="| ${file#"$root"/} "
  for command in inspect verify audit; do
    start=$(date +%s.%N)
    set +e
    (cd "$work" && "$plumb" "$command" "$file") >"$work/out" 2>/dev/null
    code=$?
    set -e
    seconds=$(python3 -c "print(f'{$(date +%s.%N) - $start:.2f}')")
    row+="| $seconds "
    if [[ $command != inspect ]]; then
      verdict=$(grep -E "passed, .* warned" "$work/out" | tail -1 | sed 's/ (passed.*//')
      row+="| exit $code: ${verdict:-no verdict} "
    elif [[ $code -ne 0 ]]; then
      row+="(exit $code) "
    fi
  done
  echo "$row|"
done < <(find "$root" -name '*.xml' | sort)
rm -f "/tmp/corpus-$$.out"
