#!/usr/bin/env bash
# How long a stop takes: `plumb rollout MODEL --count N --threads 2 --db FILE` and the same
# plumb.rollout(..., db=) from Python get SIGINT (Ctrl-C) after WAIT seconds of running; the
# time from the signal to the end of the process (CLI) or to the KeyboardInterrupt reaching
# Python (Python; the child prints time.monotonic() as it catches it). REPEAT runs of each;
# the median and the largest. Each run also says how many rollouts the store kept.
#
# Usage: bench/stop_latency.sh [BUILD_DIR] [MODEL]
#   BUILD_DIR: a build with plumb and the Python module (default build/); MODEL default: the
#   corpus's largest robot, Unitree's G1 of mjlab (31 bodies, 35 dofs; scripts/fetch-robots.sh)
#   env: COUNT (100000), UNTIL (1), WAIT (3: the G1 takes about 1.2 s to load and start),
#   REPEAT (7), PYTHON (the build's venv Python)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "${1:-$here/build}" && pwd)"
corpus="${PLUMB_CORPUS:-$HOME/.cache/plumb/robots}"
model="${2:-$corpus/mjlab-1.6.0/unitree_g1/xmls/g1.xml}"
python="${PYTHON:-$(grep '^PLUMB_PYTHON:' "$build/CMakeCache.txt" 2>/dev/null | cut -d= -f2)}"
[[ -x "$build/plumb" && -f "$model" && -x "$python" ]] || {
  echo "stop_latency.sh: needs $build/plumb, the model $model (scripts/fetch-robots.sh) and a" \
    "Python (PYTHON=...)" >&2
  exit 2
}
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"  # MuJoCo may write MUJOCO_LOG.TXT beside the process
PLUMB="$build/plumb" MODEL="$model" PYTHONPATH="$build/python" PYTHONDONTWRITEBYTECODE=1 \
  COUNT="${COUNT:-100000}" UNTIL="${UNTIL:-1}" WAIT="${WAIT:-3}" REPEAT="${REPEAT:-7}" \
  "$python" - <<'EOF'
import os, signal, sqlite3, statistics, subprocess, sys, time

plumb, model = os.environ["PLUMB"], os.environ["MODEL"]
count, until = os.environ["COUNT"], os.environ["UNTIL"]
wait, repeat = float(os.environ["WAIT"]), int(os.environ["REPEAT"])
randomize, metric = "body_mass[*]=*U(0.9,1.1)", "xpos[pelvis][2]@" + until
CHILD = f"""
import sys, time, plumb
try:
    plumb.rollout({model!r}, {count}, randomize={randomize!r}, metrics={metric!r},
                  until={until}, threads=2, db=sys.argv[1])
except KeyboardInterrupt:
    print(time.monotonic(), flush=True)
"""


def stored(db):
    with sqlite3.connect(f"file:{db}?mode=ro", uri=True) as s:
        return s.execute("select count(*) from results").fetchone()[0]


def one(kind, k):
    db = f"{kind}{k}.sqlite"
    if kind == "cli":
        argv = [plumb, "rollout", model, "--count", count, "--threads", "2", "--until", until,
                "--randomize", randomize, "--metric", metric, "--format", "csv", "--db", db]
    else:
        argv = [sys.executable, "-c", CHILD, db]
    child = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    time.sleep(wait)
    sent = time.monotonic()
    child.send_signal(signal.SIGINT)
    out, _ = child.communicate(timeout=120)
    ended = time.monotonic()
    if kind == "python":
        ended = float(out.split()[-1])  # when KeyboardInterrupt reached Python
    return ended - sent, stored(db)


for kind in ("cli", "python"):
    runs = [one(kind, k) for k in range(repeat)]
    ms = [1000 * s for s, _ in runs]
    print(f"{kind:6}: stop latency median {statistics.median(ms):.0f} ms, largest {max(ms):.0f} ms"
          f" over {repeat} runs ({', '.join(f'{m:.0f}' for m in ms)}); stored "
          f"{', '.join(str(n) for _, n in runs)}")
EOF
