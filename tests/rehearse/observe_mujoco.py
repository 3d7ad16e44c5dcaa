#!/usr/bin/env python3
"""Runs a vendor's MuJoCo script unmodified and records its robot's base for measure.py.

The script is run with runpy as its own __main__; mujoco.mj_step is wrapped only to note the
free base's qpos (x y z, w x y z: the first seven qpos) and d.time every 10 physics steps into
a CSV with the columns measure.py reads (time, kind = state, qpos[base][0..6]). Nothing the
script computes is changed.

Usage: observe_mujoco.py OUT.csv SCRIPT.py [the script's arguments ...]
"""
import csv
import runpy
import sys

import mujoco

out = open(sys.argv[1], "w", newline="")
writer = csv.writer(out)
writer.writerow(["time", "kind", "event"] + [f"qpos[base][{k}]" for k in range(7)])
_step = mujoco.mj_step
steps = [0]


def noting_step(m, d, *args, **kwargs):
    _step(m, d, *args, **kwargs)
    steps[0] += 1
    if steps[0] % 10 == 0:
        writer.writerow([f"{d.time:.4f}", "state", ""] + [f"{v:.6g}" for v in d.qpos[:7]])
        out.flush()


mujoco.mj_step = noting_step
script = sys.argv[2]
sys.argv = [script] + sys.argv[3:]
runpy.run_path(script, run_name="__main__")
