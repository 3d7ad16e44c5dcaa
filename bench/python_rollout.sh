#!/usr/bin/env bash
# plumb.rollout from Python against (1) `plumb rollout` on the command line and (2) MuJoCo's
# own mujoco.rollout from Python, on the same worlds: the model as loaded, COUNT initial states
# (the reset state with every qvel drawn from U(-0.5, 0.5), plumb's draws handed to
# mujoco.rollout as full physics states), zero controls, NSTEP steps, the same threads.
#
#   1. Instructions (callgrind, whole processes, IR_COUNT x IR_NSTEP, 1 thread: valgrind runs
#      threads one at a time, so more threads only add scheduling noise): the Python process
#      minus a bare `import plumb` (the price of starting Python and importing numpy, mujoco
#      and plumb, paid once per process, not per batch) against the whole CLI process.
#   2. World-steps per second of plumb.rollout and mujoco.rollout, alternating in one Python
#      process (REPEAT times each; median and best), at 1 and 2 threads, with the final states
#      compared; and the instructions of one batch of each (callgrind, 1 thread, minus the same
#      import baseline: every mode of python_rollout.py imports mujoco, numpy and plumb).
#
# Usage: bench/python_rollout.sh [BUILD_DIR] [MODEL]
#   BUILD_DIR: a build with PLUMB_BUILD_PYTHON (default build/); MODEL default: the humanoid
#   env: COUNT (64), NSTEP (1000), REPEAT (5), IR_COUNT (8), IR_NSTEP (500), IR_REPEAT (3)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "${1:-$here/build}" && pwd)"
model="${2:-/usr/share/mujoco/model/humanoid/humanoid.xml}"
count=${COUNT:-64} nstep=${NSTEP:-1000} repeat=${REPEAT:-5}
ir_count=${IR_COUNT:-8} ir_nstep=${IR_NSTEP:-500} ir_repeat=${IR_REPEAT:-3}
plumb="$build/plumb"
python="$(grep '^PLUMB_PYTHON:' "$build/CMakeCache.txt" | cut -d= -f2)"
[[ -x "$plumb" && -x "$python" && -d "$build/python/plumb" ]] || {
  echo "python_rollout.sh: $build needs plumb and the Python module (PLUMB_BUILD_PYTHON=ON)" >&2
  exit 2
}
export PYTHONPATH="$build/python" PYTHONDONTWRITEBYTECODE=1
script="$here/bench/python_rollout.py"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"  # MuJoCo may write MUJOCO_LOG.TXT beside the process

# instructions the command executes, all threads, as callgrind counts them: the fewest of
# IR_REPEAT runs (a waiting thread's wakeups, plumb.rollout's 20 ms signal polls among them,
# add instructions in proportion to the time valgrind takes, which a loaded machine stretches;
# numpy's OpenBLAS threads, which spin as they wait, are held to one for the same reason)
instructions() {
  local best=
  for _ in $(seq "$ir_repeat"); do
    OPENBLAS_NUM_THREADS=1 valgrind --tool=callgrind --callgrind-out-file="$work/cg.out" "$@" \
      >/dev/null 2>"$work/cg.err" ||
      { cat "$work/cg.err" >&2; exit 1; }
    local n; n=$(awk '/^(summary|totals):/ {print $2; exit}' "$work/cg.out")
    if [[ -z "$best" || "$n" -lt "$best" ]]; then best=$n; fi
  done
  echo "$best"
}

until=$("$python" -c "import mujoco, sys; print(repr($ir_nstep * mujoco.MjModel.from_xml_path(sys.argv[1]).opt.timestep))" "$model")
echo "model $model; instructions: $ir_count rollouts x $ir_nstep steps (until $until s), 1 thread, fewest of $ir_repeat runs"
base=$(instructions "$python" "$script" import)
cli=$(instructions "$plumb" rollout "$model" --count "$ir_count" --until "$until" --threads 1 \
  --randomize 'qvel[*]=U(-0.5,0.5)' --metric "state@$until" --format csv)
py=$(instructions "$python" "$script" plumb "$model" "$ir_count" "$ir_nstep" 1)
"$python" "$script" draws "$model" "$ir_count" "$ir_nstep" "$work/states.npy"
peer=$(instructions "$python" "$script" mujoco "$model" "$ir_count" "$ir_nstep" 1 "$work/states.npy")
"$python" - "$base" "$cli" "$py" "$peer" <<'PY'
import sys
base, cli, py, peer = map(int, sys.argv[1:])
print(f"| process | instructions | minus import baseline |")
print(f"|---|---|---|")
print(f"| python: import plumb (baseline) | {base:,} | |")
print(f"| plumb rollout (CLI) | {cli:,} | |")
print(f"| python: plumb.rollout | {py:,} | {py - base:,} |")
print(f"| python: mujoco.rollout | {peer:,} | {peer - base:,} |")
print(f"plumb.rollout / plumb rollout: {(py - base) / cli:.4f} (whole process: {py / cli:.3f})")
print(f"mujoco.rollout / plumb.rollout: {(peer - base) / (py - base):.4f}")
PY

echo
echo "world-steps/s, $count rollouts x $nstep steps, median and best of $repeat, alternating:"
for threads in 1 2; do
  "$python" "$script" compare "$model" "$count" "$nstep" "$threads" "$repeat"
done
