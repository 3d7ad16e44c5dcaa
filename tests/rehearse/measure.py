#!/usr/bin/env python3
"""Reads a plumb bridge flight log (--log flight.csv) and says whether the robot stood and walked.

The base is the first free joint of the log (its qpos[...][0..6] columns: x y z, w x y z).
From the state rows it reports the base height at a few times, its lowest height after
--after (the moment the robot stands on its own: the band's release), the largest tilt
from upright, and the forward distance and mean forward speed (world x) inside the window
--walk FROM TO. Verdict: stood when the base never dropped below --min-height after
--after; walked when it also covered at least --min-distance in the walk window.

Usage: measure.py flight.csv [--after S] [--walk FROM TO] [--min-height M]
       [--min-distance M] [--json]
Exit codes: 0 the verdict holds (stood, and walked when --walk is given), 1 it does not,
2 the log cannot be read or has no free joint.
Only the standard library is used: it runs under any python3.
"""
import argparse
import csv
import json
import math
import sys


def base_columns(header):
    for i, name in enumerate(header):
        if name.startswith("qpos[") and name.endswith("][0]"):
            root = name[: -len("[0]")]
            names = [f"{root}[{k}]" for k in range(7)]
            if all(n in header for n in names):
                return root, [header.index(n) for n in names]
    return None, None


def read_states(path):
    with open(path, newline="") as f:
        rows = csv.reader(f)
        header = next(rows)
        root, cols = base_columns(header)
        if root is None:
            raise ValueError(f"{path}: no free joint's qpos columns (qpos[NAME][0..6])")
        t_col, kind_col = header.index("time"), header.index("kind")
        states = []
        for row in rows:
            if len(row) <= max(cols) or row[kind_col] != "state" or not row[cols[2]]:
                continue
            states.append((float(row[t_col]), [float(row[c]) for c in cols]))
    return root, states


def tilt_deg(q):
    # angle between the base's z axis and the world's: R[2][2] = 1 - 2 (x^2 + y^2)
    w, x, y, z = q
    n = w * w + x * x + y * y + z * z
    c = 1 - 2 * (x * x + y * y) / n if n > 0 else 1
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))


def at(states, t):
    best = min(states, key=lambda s: abs(s[0] - t))
    return best[1]


def measure(path, after, walk, min_height, min_distance):
    root, states = read_states(path)
    if not states:
        raise ValueError(f"{path}: no state rows")
    end = states[-1][0]
    later = [s for s in states if s[0] >= after] or states[-1:]
    lowest = min(s[1][2] for s in later)
    result = {
        "log": path,
        "base": root,
        "simulated_s": round(end, 3),
        "height_m": {f"{t:g}": round(at(states, t)[2], 4)
                     for t in sorted({0.0, after, end / 2, end}) if t <= end},
        "lowest_after_m": round(lowest, 4),
        "max_tilt_after_deg": round(max(tilt_deg(s[1][3:7]) for s in later), 2),
        "stood": lowest >= min_height,
    }
    ok = result["stood"]
    if walk:
        t0, t1 = walk[0], min(walk[1], end)
        a, b = at(states, t0), at(states, t1)
        dist = b[0] - a[0]
        result["walk_window_s"] = [t0, round(t1, 3)]
        result["forward_m"] = round(dist, 4)
        result["lateral_m"] = round(b[1] - a[1], 4)
        result["mean_forward_speed_mps"] = round(dist / (t1 - t0), 4) if t1 > t0 else 0.0
        result["walked"] = ok and dist >= min_distance
        ok = result["walked"]
    return result, ok


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("log")
    p.add_argument("--after", type=float, default=0.0)
    p.add_argument("--walk", type=float, nargs=2, metavar=("FROM", "TO"))
    p.add_argument("--min-height", type=float, default=0.5)
    p.add_argument("--min-distance", type=float, default=0.5)
    p.add_argument("--json", action="store_true")
    a = p.parse_args()
    try:
        result, ok = measure(a.log, a.after, a.walk, a.min_height, a.min_distance)
    except (OSError, ValueError, StopIteration) as e:
        print(f"measure.py: {e}", file=sys.stderr)
        return 2
    if a.json:
        print(json.dumps(result))
    else:
        for k, v in result.items():
            print(f"{k}: {v}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
