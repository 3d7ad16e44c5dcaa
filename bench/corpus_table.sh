#!/usr/bin/env bash
# The robot corpus table of bench/RESULTS.md: for every model of the corpus
# (scripts/fetch-robots.sh), whole-process seconds of plumb inspect, verify and audit and
# their verdict lines.
#
# Usage: bench/corpus_table.sh [BUILD_DIR]
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
plumb="${1:-$here/build}/plumb"
root=$("$here/scripts/fetch-robots.sh" --path)
echo "| model | inspect s | verify s | verify | audit s | audit |"
echo "|---|---|---|---|---|---|"
while read -r file; do
  row="| ${file#"$root"/} "
  for command in inspect verify audit; do
    start=$(date +%s.%N)
    set +e
    "$plumb" "$command" "$file" >"/tmp/corpus-$$.out" 2>/dev/null
    code=$?
    set -e
    seconds=$(python3 -c "print(f'{$(date +%s.%N) - $start:.2f}')")
    row+="| $seconds "
    if [[ $command != inspect ]]; then
      verdict=$(grep -E "passed, .* warned" "/tmp/corpus-$$.out" | tail -1 | sed 's/ (passed.*//')
      row+="| exit $code: ${verdict:-no verdict} "
    elif [[ $code -ne 0 ]]; then
      row+="(exit $code) "
    fi
  done
  echo "$row|"
done < <(find "$root" -name '*.xml' | sort)
rm -f "/tmp/corpus-$$.out"
