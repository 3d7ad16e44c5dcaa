"""Peak memory of plumb.run returning a long trajectory, against the array it returns.

plumb.run writes every sample straight into one buffer sized from the schedule, which the
numpy array then owns without a copy: the run's peak memory growth should be the array's size
and little more (target: within 1.2x its nbytes).

Two measurements, for 10^6 samples of the pendulum (time, qpos, qvel every step, 2000 s):
  in-process  the peak RSS (VmHWM, reset through /proc/self/clear_refs just before the call)
              minus the RSS before it;
  two runs    /usr/bin/time -v's maximum resident set of a process doing the long run minus
              that of one doing a 10-sample run (everything else equal).

Usage (from the checkout, after building with PLUMB_BUILD_PYTHON):
  PYTHONPATH=build/python $(grep PLUMB_PYTHON: build/CMakeCache.txt | cut -d= -f2) \\
      bench/python_run_memory.py [SAMPLES]
Prints a Markdown table; exits 1 when a ratio is above 1.2.
"""

import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODEL = os.path.join(ROOT, "models", "pendulum.xml")
DT = 0.002  # the pendulum's timestep
TARGET = 1.2


def status_kb(field):
    with open("/proc/self/status") as f:
        return int(re.search(rf"^{field}:\s+(\d+) kB", f.read(), re.M).group(1))


def run(samples):
    import plumb  # noqa: PLC0415  (the child imports it; the parent only starts children)

    plumb.run(MODEL, until=10 * DT, every=DT)  # warm up: libraries, MuJoCo, numpy
    before = status_kb("VmRSS")
    with open("/proc/self/clear_refs", "w") as f:
        f.write("5")  # resets VmHWM to the current RSS
    t = plumb.run(MODEL, until=(samples - 1) * DT, every=DT, set={"qpos[hinge]": 0.7})
    peak = status_kb("VmHWM")
    assert t.array.shape[0] == samples, t.array.shape
    print(f"{t.array.nbytes} {(peak - before) * 1024}")


def child(samples):
    """(array bytes, in-process growth, max RSS bytes of the whole process)"""
    done = subprocess.run(["/usr/bin/time", "-v", sys.executable, __file__, "--child",
                           str(samples)], capture_output=True, text=True, check=True)
    nbytes, growth = map(int, done.stdout.split())
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", done.stderr).group(1))
    return nbytes, growth, rss * 1024


def main():
    if sys.argv[1:2] == ["--child"]:
        run(int(sys.argv[2]))
        return 0
    samples = int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000
    nbytes, growth, rss = child(samples)
    _, _, small_rss = child(10)
    in_process = growth / nbytes
    two_runs = (rss - small_rss) / nbytes
    mb = 1 / 2**20
    print(f"plumb.run of {samples} samples x 3 columns of the pendulum\n")
    print("| measure | bytes | x array |")
    print("|---|---|---|")
    print(f"| the array (nbytes) | {nbytes * mb:.1f} MiB | 1.00 |")
    print(f"| in-process peak RSS growth (VmHWM) | {growth * mb:.1f} MiB | {in_process:.3f} |")
    print(f"| max RSS, long run - 10-sample run (/usr/bin/time -v) | "
          f"{(rss - small_rss) * mb:.1f} MiB | {two_runs:.3f} |")
    return 0 if max(in_process, two_runs) <= TARGET else 1


if __name__ == "__main__":
    sys.exit(main())
