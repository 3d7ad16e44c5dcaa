#!/usr/bin/env python3
"""The operator and the observer for a vendor's own simulator, so its run compares with the bridge's.

A vendor's simulator script (holosoma's run_sim.py) has no gamepad script and no flight log.
This plays the same gamepad file the bridge plays (plumb's format, the subset the rehearsals
use: `t = T: BUTTON`, `t = T: AXIS = V for D s`, items joined by commas, a button held 0.1 s
unless `for D s` says otherwise) on rt/wirelesscontroller (unitree_go WirelessController_) at
100 Hz, and records the base's pose that the simulator publishes (rt/odommodestate, unitree_go
SportModeState_: position, and the IMU quaternion, or rt/lowstate's when that is zero) into a
CSV that tests/rehearse/measure.py reads as it reads the bridge's flight log.

Time is the wall clock from the first state the simulator publishes: the vendor's simulator
paces simulated time to the wall clock, so it is simulated time too, to its pacing's error.

Usage (in the Unitree SDK2 Python environment, scripts/sdk2-venv.sh):
  sim_operator.py --gamepad gamepad.txt --until S --out flight.csv [--domain 0] [--interface lo]
                  [--family hg|go]
Exit codes: 0 done, 1 the simulator published nothing for 60 s, 2 bad use.
"""
import argparse
import csv
import re
import sys
import threading
import time

from unitree_sdk2py.core.channel import (ChannelFactoryInitialize, ChannelPublisher,
                                         ChannelSubscriber)
from unitree_sdk2py.idl.unitree_go.msg.dds_ import SportModeState_, WirelessController_

BUTTONS = ["R1", "L1", "start", "select", "R2", "L2", "F1", "F2", "A", "B", "X", "Y", "up",
           "right", "down", "left"]
AXES = ["lx", "ly", "rx", "ry"]
ITEM = re.compile(r"^\s*(\w+)\s*(?:=\s*(-?[\d.]+))?\s*(?:for\s+([\d.]+)\s*s)?\s*$")


def parse_gamepad(path):
    """Events (start, end or None, name, value) of plumb's gamepad file, the subset used here."""
    events = []
    for n, line in enumerate(open(path), 1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        m = re.match(r"^t\s*=\s*([\d.]+)\s*:(.*)$", line)
        if not m:
            raise ValueError(f"{path}:{n}: not 't = T: ...'")
        t = float(m.group(1))
        for item in m.group(2).split(","):
            im = ITEM.match(item)
            if not im or (im.group(1) not in BUTTONS and im.group(1) not in AXES):
                raise ValueError(f"{path}:{n}: '{item.strip()}' is not a button or an axis")
            name, value, dur = im.group(1), im.group(2), im.group(3)
            if name in BUTTONS:
                events.append((t, t + float(dur or 0.1), name, 1.0))
            else:
                events.append((t, t + float(dur) if dur else None, name, float(value)))
    return events


def pad_at(events, t):
    keys, axes = 0, dict.fromkeys(AXES, 0.0)
    for start, end, name, value in events:
        if start <= t and (end is None or t < end):
            if name in BUTTONS:
                keys |= 1 << BUTTONS.index(name)
            else:
                axes[name] = value
    return keys, axes


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--gamepad", required=True)
    p.add_argument("--until", type=float, required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--domain", type=int, default=0)
    p.add_argument("--interface", default="lo")
    p.add_argument("--family", choices=["hg", "go"], default="hg")
    a = p.parse_args()
    try:
        events = parse_gamepad(a.gamepad)
    except (OSError, ValueError) as e:
        print(f"sim_operator.py: {e}", file=sys.stderr)
        return 2
    if a.family == "hg":
        from unitree_sdk2py.idl.unitree_hg.msg.dds_ import LowState_
    else:
        from unitree_sdk2py.idl.unitree_go.msg.dds_ import LowState_
    ChannelFactoryInitialize(a.domain, a.interface)
    lock = threading.Lock()
    latest = {"odom": None, "quat": None}

    def on_odom(msg):
        with lock:
            latest["odom"] = msg

    def on_low(msg):
        with lock:
            latest["quat"] = list(msg.imu_state.quaternion)

    odom_sub = ChannelSubscriber("rt/odommodestate", SportModeState_)
    odom_sub.Init(on_odom, 10)
    sport_sub = ChannelSubscriber("rt/sportmodestate", SportModeState_)
    sport_sub.Init(on_odom, 10)
    low_sub = ChannelSubscriber("rt/lowstate", LowState_)
    low_sub.Init(on_low, 10)
    pad = ChannelPublisher("rt/wirelesscontroller", WirelessController_)
    pad.Init()
    waited = time.monotonic()
    while latest["odom"] is None:
        if time.monotonic() - waited > 60:
            print("sim_operator.py: nothing on rt/odommodestate or rt/sportmodestate for 60 s",
                  file=sys.stderr)
            return 1
        time.sleep(0.01)
    t0 = time.monotonic()
    root = "qpos[base]"
    header = ["time", "kind", "event"] + [f"{root}[{k}]" for k in range(7)]
    with open(a.out, "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(header)
        last_keys = None
        while True:
            t = time.monotonic() - t0
            if t > a.until:
                break
            keys, axes = pad_at(events, t)
            if keys != last_keys:
                out.writerow([f"{t:.3f}", "gamepad", f"keys {keys:#06x}"] + [""] * 7)
                last_keys = keys
            pad.Write(WirelessController_(lx=axes["lx"], ly=axes["ly"], rx=axes["rx"],
                                          ry=axes["ry"], keys=keys))
            with lock:
                odom, quat = latest["odom"], latest["quat"]
            q = list(odom.imu_state.quaternion)
            if not any(q) and quat is not None:
                q = quat
            out.writerow([f"{t:.3f}", "state", ""] + [f"{v:.6g}" for v in
                                                      list(odom.position) + q])
            time.sleep(0.01)
    return 0


if __name__ == "__main__":
    sys.exit(main())
