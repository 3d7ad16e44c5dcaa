#!/usr/bin/env bash
# The WARN and FAIL rows of plumb audit and plumb verify on every model of the robot corpus
# (scripts/fetch-robots.sh) and of dm_control's suite (tests/models/dm_control/suite), one line
# per model and command: "path<TAB>command<TAB>count<TAB>STATUS check xN, ...". Two runs of it
# (before and after a change, each with its own plumb) give bench/RESULTS.md's before/after
# table: diff before.tsv after.tsv
#
# Usage: bench/audit_findings.sh [PLUMB] > findings.tsv
#        COMMANDS=audit bench/audit_findings.sh [PLUMB]   (one command only)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
plumb="$(realpath "${1:-$here/build/plumb}")"
root=$("$here/scripts/fetch-robots.sh" --path)
out=$(mktemp) && [[ -n "$out" ]] || exit 1
# plumb runs in a folder of its own: a diverging run writes its plumb-repro-* folder there, not
# into the current folder (it left them in the checkout)
work=$(mktemp -d) && [[ -n "$work" ]] || exit 1
trap 'rm -f "$out"; rm -rf "$work"' EXIT
{
  find "$root" -name '*.xml' | sort
  find "$here/tests/models/dm_control/suite" -maxdepth 1 -name '*.xml' | sort
} | while read -r file; do
  for command in ${COMMANDS:-audit verify}; do
    set +e
    (cd "$work" && timeout 600 "$plumb" "$command" "$file" --format json) >"$out" 2>/dev/null
    code=$?
    set -e
    name=${file#"$root"/}
    name=${name#"$here"/tests/models/}
    python3 - "$out" "$name" "$command" "$code" <<'PY'
import collections, json, sys
path, name, command, code = sys.argv[1:5]
try:
    doc = json.load(open(path))
except Exception:
    print(f"{name}\t{command}\t-\tno JSON (exit {code})")
    sys.exit(0)
rows = []
def walk(x):
    if isinstance(x, dict):
        if "status" in x and "id" in x:
            rows.append(x)
        else:
            for v in x.values():
                walk(v)
    elif isinstance(x, list):
        for v in x:
            walk(v)
walk(doc.get("layers", doc.get("checks", doc)))
count = collections.Counter(f"{r['status']} {r['id']}" for r in rows
                            if r["status"] in ("WARN", "FAIL"))
text = ", ".join(f"{k} x{v}" if v > 1 else k for k, v in sorted(count.items()))
print(f"{name}\t{command}\t{sum(count.values())}\t{text or '-'}")
PY
  done
done
