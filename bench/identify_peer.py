#!/usr/bin/env python3
"""plumb identify against MuJoCo's own mujoco.sysid, on logs made from a known truth.

For each case (the two-joint arm of tests/models/arm2.xml driven by chirps, and the chapter's
pendulum in free decay):

1. a log is simulated with the Python bindings from the truth (the model file's own values),
   with Gaussian noise on the measured qpos and qvel, and written in plumb's log format
   (inputs logged at the row where they are set and held until the next row);
2. `plumb identify` fits the free parameters from a wrong guess (set with --set), timed as a
   whole process;
3. mujoco.sysid fits the same parameters from the same guess and bounds (its default
   optimizer, MuJoCo's own least squares in mujoco.minimize), timed from reading the CSV to
   its confidence intervals;
4. both fitted parameter sets (and the truth and the guess, for reference) are replayed here
   in the same way from the logged start state, and the rms of the residuals per signal is
   the comparable final cost.

Usage: identify_peer.py PLUMB [--repeat N] [--seed S] [--work DIR] [--json FILE]
Prints one markdown table per case. Needs mujoco-core[sysid] (bench/requirements-sysid.txt).
"""

import argparse
import csv
import io
import json
import math
import os
import pathlib
import platform
import resource
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

_t_import = time.perf_counter()
import mujoco  # noqa: E402
from mujoco import sysid  # noqa: E402
import scipy.optimize  # noqa: E402
import scipy.special  # noqa: E402
from absl import logging as absl_logging  # noqa: E402

IMPORT_SECONDS = time.perf_counter() - _t_import

ROOT = pathlib.Path(__file__).resolve().parent.parent
# what each plumb array path is on a joint of an MjSpec
SPEC_ATTRIBUTE = {"dof_damping": "damping", "dof_armature": "armature",
                  "dof_frictionloss": "frictionloss"}


def chirp(amplitude, f0, f1, seconds, phase=0.0):
  """A sine whose frequency rises linearly from f0 to f1 Hz over `seconds`."""
  def u(t):
    return amplitude * math.sin(
        2 * math.pi * (f0 * t + (f1 - f0) * t * t / (2 * seconds)) + phase)
  return u


CASES = [
    {
        "name": "arm",
        "model": "tests/models/arm2.xml",
        "joints": ["shoulder", "elbow"],
        "inputs": [("ctrl[shoulder]", chirp(6.0, 0.2, 3.0, 6.0)),
                   ("ctrl[elbow]", chirp(2.5, 0.3, 4.0, 6.0, phase=0.5))],
        "start": {},  # qpos0, at rest
        "seconds": 6.0,
        "every": 2,
        # path, truth, guess, lower, upper
        "params": [("dof_damping[shoulder]", 0.8, 1.2, 0.0, 5.0),
                   ("dof_damping[elbow]", 0.4, 0.2, 0.0, 5.0),
                   ("dof_armature[shoulder]", 0.05, 0.1, 0.0, 1.0),
                   ("dof_armature[elbow]", 0.02, 0.05, 0.0, 1.0),
                   ("dof_frictionloss[shoulder]", 0.3, 0.1, 0.0, 2.0),
                   ("dof_frictionloss[elbow]", 0.1, 0.2, 0.0, 2.0)],
    },
    {
        "name": "pendulum",
        "model": "models/pendulum.xml",
        "joints": ["hinge"],
        "inputs": [],
        "start": {"hinge": 0.7},
        "seconds": 6.0,
        "every": 2,
        "params": [("dof_damping[hinge]", 0.05, 0.2, 0.0, 2.0)],
    },
]
NOISE = {"qpos": 0.001, "qvel": 0.01}  # sigma: rad, rad/s


def split_path(path):
  array, rest = path.split("[", 1)
  return array, rest.rstrip("]")


def set_values(model, values):
  """Writes {plumb path: value} of dof arrays into a compiled model."""
  for path, value in values.items():
    array, joint = split_path(path)
    dof = model.jnt_dofadr[model.joint(joint).id]
    getattr(model, array)[dof] = value


def columns(case):
  return ([p for p, _ in case["inputs"]] + [f"qpos[{j}]" for j in case["joints"]] +
          [f"qvel[{j}]" for j in case["joints"]])


def make_log(case, path, seed):
  """Simulates the truth and writes its log; returns the rows as a float array."""
  model = mujoco.MjModel.from_xml_path(str(ROOT / case["model"]))
  for p, truth, *_ in case["params"]:
    array, joint = split_path(p)
    actual = getattr(model, array)[model.jnt_dofadr[model.joint(joint).id]]
    if actual != truth:
      sys.exit(f"{case['model']}: {p} is {actual}, the benchmark's truth is {truth}")
  data = mujoco.MjData(model)
  for joint, q in case["start"].items():
    data.qpos[model.jnt_qposadr[model.joint(joint).id]] = q
  qadr = [model.jnt_qposadr[model.joint(j).id] for j in case["joints"]]
  vadr = [model.jnt_dofadr[model.joint(j).id] for j in case["joints"]]
  actuators = [model.actuator(split_path(p)[1]).id for p, _ in case["inputs"]]
  rng = np.random.default_rng(seed)
  dt = model.opt.timestep
  steps = round(case["seconds"] / dt)
  rows = []
  for k in range(0, steps + 1):
    if k % case["every"] == 0:
      t = k * dt
      u = [f(t) for _, f in case["inputs"]]
      q = [data.qpos[a] + NOISE["qpos"] * rng.standard_normal() for a in qadr]
      v = [data.qvel[a] + NOISE["qvel"] * rng.standard_normal() for a in vadr]
      rows.append([t] + u + q + v)
      for a, value in zip(actuators, u):
        data.ctrl[a] = value  # set at this row, held until the next
    if k < steps:
      mujoco.mj_step(model, data)
  with open(path, "w", newline="") as f:
    f.write(",".join(["time"] + columns(case)) + "\n")
    for row in rows:
      f.write(",".join(repr(float(x)) for x in row) + "\n")
  return np.array(rows)


def read_log(path):
  with open(path, newline="") as f:
    reader = csv.reader(f)
    header = next(reader)
    rows = np.array([[float(x) for x in r] for r in reader])
  return header, rows


class Replayer:
  """Replays a log with the model at given parameter values, inputs held from row to row."""

  def __init__(self, case, values, rows):
    self.model = mujoco.MjModel.from_xml_path(str(ROOT / case["model"]))
    set_values(self.model, values)
    self.data = mujoco.MjData(self.model)
    self.rows = rows
    self.n_in, self.nj = len(case["inputs"]), len(case["joints"])
    m = self.model
    self.qadr = [m.jnt_qposadr[m.joint(j).id] for j in case["joints"]]
    self.vadr = [m.jnt_dofadr[m.joint(j).id] for j in case["joints"]]
    self.actuators = [m.actuator(split_path(p)[1]).id for p, _ in case["inputs"]]
    dt = m.opt.timestep
    self.steps = [round((rows[i + 1, 0] - rows[i, 0]) / dt) for i in range(len(rows) - 1)]
    self.logged_start = rows[0, 1 + self.n_in:]

  def errors(self, start):
    """measured - simulated at every row, from the start state (qpos..., qvel...)."""
    m, d, rows = self.model, self.data, self.rows
    mujoco.mj_resetData(m, d)
    d.qpos[self.qadr] = start[:self.nj]
    d.qvel[self.vadr] = start[self.nj:]
    err = np.empty((len(rows), 2 * self.nj))
    for i in range(len(rows)):
      err[i] = rows[i, 1 + self.n_in:] - np.concatenate([d.qpos[self.qadr], d.qvel[self.vadr]])
      if i + 1 == len(rows):
        break
      d.ctrl[self.actuators] = rows[i, 1:1 + self.n_in]
      for _ in range(self.steps[i]):
        mujoco.mj_step(m, d)
    return err


def replay_rms(case, values, rows):
  """rms of (measured - simulated) per measured column over every row but the first, (a)
  from the logged start state, (b) from the start state that fits the log best for these
  parameters (least squares over the start, residuals in units of the noise: what a fit
  that also estimates the start, as plumb's, would see)."""
  r = Replayer(case, values, rows)
  logged = np.sqrt(np.mean(r.errors(r.logged_start)[1:] ** 2, axis=0))
  sigma = np.array([NOISE["qpos"]] * r.nj + [NOISE["qvel"]] * r.nj)
  best = scipy.optimize.least_squares(lambda s: (r.errors(s) / sigma).ravel(), r.logged_start,
                                      x_scale=sigma, diff_step=1e-7)
  refitted = np.sqrt(np.mean(r.errors(best.x)[1:] ** 2, axis=0))
  return logged, refitted


def run_plumb(plumb, case, log):
  cmd = [plumb, "identify", str(ROOT / case["model"]), "--log", str(log)]
  for p, _, guess, lo, hi in case["params"]:
    cmd += ["--fit", p, "--set", f"{p}={guess!r}", "--bounds", f"{p}={lo!r}:{hi!r}"]
  cmd += ["--format", "json"]
  cpu0 = resource.getrusage(resource.RUSAGE_CHILDREN)
  start = time.perf_counter()
  proc = subprocess.run(cmd, capture_output=True, text=True)
  seconds = time.perf_counter() - start
  cpu1 = resource.getrusage(resource.RUSAGE_CHILDREN)
  cpu = (cpu1.ru_utime - cpu0.ru_utime) + (cpu1.ru_stime - cpu0.ru_stime)
  if proc.returncode != 0:
    sys.exit(f"plumb identify failed ({proc.returncode}): {' '.join(cmd)}\n{proc.stderr}")
  out = json.loads(proc.stdout)
  est = {e["path"]: (e["value"], e["std_error"]) for e in out["estimates"]}
  return {"seconds": seconds, "cpu": cpu, "estimates": est, "iterations": out["iterations"],
          "converged": out["converged"], "termination": out["termination"],
          "warnings": out["warnings"], "stderr": proc.stderr.strip(), "command": cmd}


def run_peer(case, log, inputs="held", start_from="logged"):
  """mujoco.sysid on the same log: its documented path (ParameterDict, ModelSequences,
  build_residual_fn, optimize, calculate_intervals)."""
  start, cpu0 = time.perf_counter(), time.process_time()
  header, rows = read_log(log)
  spec = mujoco.MjSpec.from_file(str(ROOT / case["model"]))
  model = spec.compile()
  dt = model.opt.timestep
  n_in, nj = len(case["inputs"]), len(case["joints"])

  params = sysid.ParameterDict()
  for p, _, guess, lo, hi in case["params"]:
    array, joint = split_path(p)

    def modifier(s, par, joint=joint, attr=SPEC_ATTRIBUTE[array]):
      if attr == "damping":  # MuJoCo 4: damping is a polynomial, [0] the linear term
        d = s.joint(joint).damping.copy()
        d[0] = par.value[0]
        s.joint(joint).damping = d
      else:
        setattr(s.joint(joint), attr, par.value[0])

    params.add(sysid.Parameter(p, nominal=guess, min_value=lo, max_value=hi,
                               modifier=modifier))

  # Inputs: sysid resamples the control series to the timestep by linear interpolation;
  # the log's inputs are held from row to row, so they are handed over held, one value per
  # timestep (a linear interpolation of the rows would be a different input).
  t_rows = rows[:, 0]
  steps = round((t_rows[-1] - t_rows[0]) / dt)
  t_steps = t_rows[0] + dt * np.arange(steps + 1)
  held = np.clip(np.searchsorted(t_rows, t_steps + 0.5 * dt, side="right") - 1, 0,
                 len(rows) - 1)
  if inputs == "rows":  # as logged: sysid interpolates linearly between the rows
    t_steps, held = t_rows, np.arange(len(rows))
  names = [split_path(p)[1] for p, _ in case["inputs"]]
  if names:
    control = sysid.TimeSeries.from_control_names(t_steps, rows[held, 1:1 + n_in], model,
                                                  names)
  else:
    control = sysid.TimeSeries(t_steps, np.zeros((len(t_steps), 0)))
  measured_names = [f"{j}_qpos" for j in case["joints"]] + [f"{j}_qvel" for j in case["joints"]]
  sensordata = sysid.TimeSeries.from_names(t_rows, rows[:, 1 + n_in:], model, measured_names)
  # the start state is not a parameter in sysid: the logged first row, noise included (or,
  # as a diagnostic, the true start the log was simulated from)
  qpos0, qvel0 = rows[0, 1 + n_in:1 + n_in + nj], rows[0, 1 + n_in + nj:1 + n_in + 2 * nj]
  if start_from == "true":
    qpos0 = np.array([case["start"].get(j, model.qpos0[model.jnt_qposadr[model.joint(j).id]])
                      for j in case["joints"]])
    qvel0 = np.zeros(nj)
  initial_state = sysid.create_initial_state(
      model, qpos0, qvel0,
      qpos_names=[f"{j}_qpos" for j in case["joints"]],
      qvel_names=[f"{j}_qvel" for j in case["joints"]])
  sequences = sysid.ModelSequences(case["name"], spec, "log", initial_state, control,
                                   sensordata, allow_missing_sensors=True)
  residual_fn = sysid.build_residual_fn(models_sequences=[sequences])
  trace = io.StringIO()
  opt_params, result = sysid.optimize(initial_params=params, residual_fn=residual_fn,
                                      optimizer="mujoco", verbose=False, output=trace)
  residuals, _, _ = residual_fn(result.x, opt_params)
  _, half_width = sysid.calculate_intervals(residuals, result.jac)  # 95 %, Student t
  seconds, cpu = time.perf_counter() - start, time.process_time() - cpu0
  dof = sum(r.size for r in residuals) - len(result.x)
  se = np.asarray(half_width) / scipy.special.stdtrit(dof, 0.975)
  est = {p: (float(x), float(s)) for (p, *_), x, s in zip(case["params"], result.x, se)}
  objective = result.extras.get("objective", [])
  lines = trace.getvalue().strip().splitlines()
  return {"seconds": seconds, "cpu": cpu, "estimates": est,
          "iterations": max(len(objective) - 1, 0),
          "termination": next((l for l in lines if l.startswith("Terminated")), ""),
          "objective": objective[-1] if objective else None}


def fmt_value(x, se=None):
  if se is None:
    return f"{x:.4g}"
  if not math.isfinite(se):
    return f"{x:.4g} ± inf"
  return f"{x:.4g} ± {se:.2g}"


def z_score(x, se, truth):
  return (x - truth) / se if math.isfinite(se) and se > 0 else math.nan


def cell(text):
  return str(text).replace("|", "\\|")  # markdown table cell


def print_case(case, rows, seed, plumb_runs, peer_runs, rms):
  mine, peer = plumb_runs[0], peer_runs[0]
  print()
  print(f"### {case['name']}: {case['model']}, {len(rows)} rows, "
        f"{case['seconds']:g} s every {case['every']} steps, noise seed {seed}")
  print()
  print("| parameter | truth | guess | plumb identify ± std error | (est - truth) / se | "
        "mujoco.sysid ± std error (its 95 % half-width / t) | (est - truth) / se |")
  print("|---|---|---|---|---|---|---|")
  for p, t, g, *_ in case["params"]:
    mv, ms = mine["estimates"][p]
    pv, ps = peer["estimates"][p]
    print(f"| {p} | {t:g} | {g:g} | {fmt_value(mv, ms)} | {z_score(mv, ms, t):+.1f} | "
          f"{fmt_value(pv, ps)} | {z_score(pv, ps, t):+.1f} |")
  sig = columns(case)[len(case["inputs"]):]
  for k, title in ((0, "from the logged start (noisy)"),
                   (1, "from the best start for those parameters")):
    print()
    print(f"| rms of the residuals, replayed {title} | " +
          " | ".join(sig) + " |")
    print("|---|" + "---|" * len(sig))
    for name in ("truth", "guess", "plumb", "peer"):
      label = {"plumb": "plumb's estimates", "peer": "mujoco.sysid's estimates"}.get(name, name)
      print(f"| {label} | " + " | ".join(f"{x:.5f}" for x in rms[name][k]) + " |")
  print()
  print("| tool | wall s, median (each run) | CPU s, median (each run) | iterations | "
        "termination |")
  print("|---|---|---|---|---|")
  for name, runs in (("plumb identify (whole process)", plumb_runs),
                     ("mujoco.sysid (CSV read to intervals, in process)", peer_runs)):
    wall = [r["seconds"] for r in runs]
    cpu = [r["cpu"] for r in runs]
    print(f"| {name} | {statistics.median(wall):.2f} ({' / '.join(f'{t:.2f}' for t in wall)}) | "
          f"{statistics.median(cpu):.2f} ({' / '.join(f'{t:.2f}' for t in cpu)}) | "
          f"{runs[0]['iterations']} | {cell(runs[0]['termination'])} |")
  for w in mine["warnings"]:
    print(f"\nplumb warning: {w}")
  print()
  print("```sh")
  print(" ".join(a if "[" not in a and "=" not in a else f"'{a}'"
                 for a in mine["command"]).replace(str(ROOT) + "/", ""))
  print("```")


def coverage(plumb, case, work, seeds, peer_inputs, peer_start):
  """Both fits over several noise seeds: is the truth within 2 standard errors about 95 %
  of the time (honest standard errors), and how far off are the estimates on average?"""
  z = {"plumb": {p[0]: [] for p in case["params"]}, "peer": {p[0]: [] for p in case["params"]}}
  for seed in seeds:
    log = work / f"{case['name']}-seed{seed}.csv"
    make_log(case, log, seed)
    runs = (("plumb", run_plumb(plumb, case, log)),
            ("peer", run_peer(case, log, peer_inputs, peer_start)))
    for name, run in runs:
      for p, t, *_ in case["params"]:
        v, se = run["estimates"][p]
        z[name][p].append(z_score(v, se, t))
  print()
  print(f"{case['name']}, noise seeds {seeds[0]}-{seeds[-1]}: (estimate - truth) / std error")
  print()
  print("| parameter | plumb: within 2 se | plumb: rms of z | mujoco.sysid: within 2 se | "
        "mujoco.sysid: rms of z |")
  print("|---|---|---|---|---|")
  for p, *_ in case["params"]:
    row = [p]
    for name in ("plumb", "peer"):
      zs = np.array(z[name][p])
      row += [f"{int(np.sum(np.abs(zs) <= 2))}/{len(zs)}", f"{np.sqrt(np.mean(zs ** 2)):.1f}"]
    print("| " + " | ".join(row) + " |")
  return z


def main():
  ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
  ap.add_argument("plumb", help="the plumb binary")
  ap.add_argument("--repeat", type=int, default=3, help="timed runs of each tool per case")
  ap.add_argument("--seed", type=int, default=1, help="noise seed of the timed logs")
  ap.add_argument("--coverage", type=int, default=0,
                  help="also fit logs with this many further noise seeds (untimed)")
  ap.add_argument("--work", help="folder for the logs, kept (default: a temporary one)")
  ap.add_argument("--json", help="also write every number here")
  ap.add_argument("--cases", default="arm,pendulum")
  ap.add_argument("--peer-inputs", choices=["held", "rows"], default="held",
                  help="held: the log's inputs handed to sysid held, one value per timestep "
                  "(what the log means); rows: the rows as they are (sysid then interpolates "
                  "linearly between them)")
  ap.add_argument("--peer-start", choices=["logged", "true"], default="logged",
                  help="sysid's start state: the logged first row (noise included), or, as "
                  "a diagnostic, the true start the log was simulated from")
  args = ap.parse_args()
  absl_logging.set_verbosity(absl_logging.ERROR)  # sysid's per-call "missing sensors" note

  plumb = os.path.abspath(args.plumb)
  version = subprocess.run([plumb, "--version"], capture_output=True, text=True).stdout
  temporary = None if args.work else tempfile.TemporaryDirectory(prefix="identify-peer-")
  work = pathlib.Path(args.work or temporary.name)  # a temporary one is removed at the end
  work.mkdir(parents=True, exist_ok=True)
  print(f"plumb: {version.splitlines()[0]}; mujoco (python): {mujoco.__version__}; "
        f"python {platform.python_version()}; import mujoco+sysid {IMPORT_SECONDS:.2f} s; "
        f"sysid's inputs: {args.peer_inputs}, start: {args.peer_start}; logs in {work}")
  report = {"plumb_version": version, "mujoco": mujoco.__version__, "cases": {}}
  for case in CASES:
    if case["name"] not in args.cases.split(","):
      continue
    log = work / f"{case['name']}.csv"
    rows = make_log(case, log, args.seed)
    plumb_runs, peer_runs = [], []
    for _ in range(args.repeat):  # alternating, so drifts in the machine's load hit both
      plumb_runs.append(run_plumb(plumb, case, log))
      peer_runs.append(run_peer(case, log, args.peer_inputs, args.peer_start))
    for name, runs in (("plumb", plumb_runs), ("peer", peer_runs)):
      if any(r["estimates"] != runs[0]["estimates"] for r in runs):
        print(f"note: {name}'s estimates differ between repetitions on {case['name']}")
    truth = {p: t for p, t, *_ in case["params"]}
    guess = {p: g for p, _, g, *_ in case["params"]}
    rms = {
        "truth": replay_rms(case, truth, rows),
        "guess": replay_rms(case, guess, rows),
        "plumb": replay_rms(case, {p: v for p, (v, _) in plumb_runs[0]["estimates"].items()},
                            rows),
        "peer": replay_rms(case, {p: v for p, (v, _) in peer_runs[0]["estimates"].items()},
                           rows),
    }
    print_case(case, rows, args.seed, plumb_runs, peer_runs, rms)
    report["cases"][case["name"]] = {
        "rows": len(rows), "plumb": plumb_runs, "peer": peer_runs,
        "rms": {k: [v.tolist() for v in vs] for k, vs in rms.items()}}
  if args.coverage > 0:
    seeds = list(range(args.seed + 1, args.seed + 1 + args.coverage))
    for case in CASES:
      if case["name"] in args.cases.split(","):
        report["cases"][case["name"]]["coverage"] = coverage(
            plumb, case, work, seeds, args.peer_inputs, args.peer_start)
  if args.json:
    with open(args.json, "w") as f:
      json.dump(report, f, indent=1, default=str)


if __name__ == "__main__":
  main()
