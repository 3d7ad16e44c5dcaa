#!/usr/bin/env python3
"""holosoma's own simulator (python -m holosoma.run_sim), unmodified, with an operator's hand on
its virtual gantry: RELEASE_S seconds of wall time after the gantry is made, it is switched off
through its own API (VirtualGantry.set_enable(False)), which is what its viewer's key 9 does;
headless, no one can press that key. The gantry's constructor is wrapped only to note the
instance (walking gc.get_objects() from a thread breaks CPython 3.11's tuple building).

Usage: vendor_sim.py RELEASE_S [run_sim's arguments ...]
"""
import runpy
import sys
import threading
import time

from holosoma.simulator.shared.virtual_gantry import VirtualGantry

made = []
made_at = []
_init = VirtualGantry.__init__


def _noting_init(self, *args, **kwargs):
    _init(self, *args, **kwargs)
    made.append(self)
    made_at.append(time.monotonic())


VirtualGantry.__init__ = _noting_init


def release_after(seconds):
    while not made:
        time.sleep(0.05)
    time.sleep(max(0.0, made_at[0] + seconds - time.monotonic()))
    for gantry in made:
        gantry.set_enable(False)
    print(f"vendor_sim.py: virtual gantry released {seconds} s after it was made", flush=True)


release = float(sys.argv[1])
threading.Thread(target=release_after, args=(release,), daemon=True).start()
sys.argv = ["run_sim"] + sys.argv[2:]
runpy.run_module("holosoma.run_sim", run_name="__main__", alter_sys=True)
