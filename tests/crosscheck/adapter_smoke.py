"""Smoke test of engines/adapter.py: speaks docs/engine-protocol.md to it and checks the
answers against CPU MuJoCo on the pendulum of models/pendulum.xml and a box on a plane.

    <venv>/bin/python tests/crosscheck/adapter_smoke.py --engine warp|mjx [--device cpu]

Run it with the engine's venv (engines/make-venv.sh). Standard library and numpy, plus the
venv's mujoco for the CPU reference. Exit 0 when every check passes, 1 otherwise.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
ADAPTER = os.path.join(ROOT, "engines", "adapter.py")
PENDULUM = os.path.join(ROOT, "models", "pendulum.xml")

PGS = """<mujoco><option solver="PGS"/><worldbody>
  <body><freejoint/><geom type="box" size=".1 .1 .1"/></body></worldbody></mujoco>"""
BOX = """<mujoco><option timestep="0.002"/><worldbody>
  <geom name="floor" type="plane" size="2 2 .1"/>
  <body name="box" pos="0 0 0.1"><freejoint/><geom name="box" type="box" size=".1 .1 .1"
    mass="1"/></body></worldbody></mujoco>"""

failures = []


def check(condition, what):
    print(("ok   " if condition else "FAIL ") + what, flush=True)
    if not condition:
        failures.append(what)


class Adapter:
    """The adapter as a subprocess, spoken to in the protocol's framing."""

    def __init__(self, engine, device):
        self.process = subprocess.Popen(
            [sys.executable, ADAPTER, "--engine", engine, "--device", device],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE)

    def send_raw(self, data):
        self.process.stdin.write(data)
        self.process.stdin.flush()

    def request(self, header, arrays=()):
        arrays = [(n, np.ascontiguousarray(v, dtype="<f8")) for n, v in arrays]
        if arrays:
            header = dict(header, arrays=[{"name": n, "shape": list(v.shape)} for n, v in arrays])
        payload = b"".join(v.tobytes() for _, v in arrays)
        self.send_raw(json.dumps(header).encode() + b"\n" + payload)
        return self.reply()

    def reply(self):
        line = self.process.stdout.readline()
        if not line:
            raise RuntimeError("the adapter closed its output")
        header = json.loads(line)
        out = {}
        for spec in header.get("arrays", []):
            count = int(np.prod(spec["shape"]))
            data = self.process.stdout.read(8 * count)
            out[spec["name"]] = np.frombuffer(data, dtype="<f8").reshape(spec["shape"])
        return header, out

    def close(self):
        self.process.stdin.close()
        return self.process.wait(timeout=120)


def cpu_states(mjm, qpos_rows):
    """CPU MuJoCo's xpos, qacc and next qpos from each qpos row."""
    import mujoco
    out = []
    for qpos in qpos_rows:
        mjd = mujoco.MjData(mjm)
        mjd.qpos[:] = qpos
        mujoco.mj_forward(mjm, mjd)
        xpos, qacc = mjd.xpos.reshape(-1).copy(), mjd.qacc.copy()
        mujoco.mj_step(mjm, mjd)
        out.append((xpos, qacc, mjd.qpos.copy()))
    return out


def close_to(a, b, rel, floor):
    return np.all(np.abs(a - b) <= rel * np.abs(b) + floor)


def test_hello_and_load(adapter, engine):
    import mujoco
    header, _ = adapter.request({"op": "hello", "protocol": 1})
    check(header.get("ok") and header["protocol"] == 1 and header["engine"] == engine,
          f"hello: {header}")
    check(header.get("mujoco_version") == "4.0.1" == mujoco.__version__, "hello: MuJoCo 4.0.1")
    check(header.get("precision") == "float32", "hello: float32")
    header, _ = adapter.request({"op": "load", "model": PENDULUM, "edits": []})
    sizes = header.get("sizes", {})
    check(header.get("ok") and sizes.get("nq") == 1 and sizes.get("nv") == 1
          and sizes.get("nbody") == 2 and sizes.get("ngeom") == 1, f"load: {header}")


def test_stages(adapter):
    import mujoco
    mjm = mujoco.MjModel.from_xml_path(PENDULUM)
    qpos = np.array([[0.7], [-0.3], [1.9]])
    header, out = adapter.request({"op": "stages"}, [("qpos", qpos), ("qvel", np.zeros((3, 1)))])
    check(header.get("ok"), f"stages: {header.get('message', 'ok')}")
    if not header.get("ok"):
        return
    want = cpu_states(mjm, qpos)
    xpos = np.array([w[0] for w in want])
    qacc = np.array([w[1] for w in want])
    nxt = np.array([w[2] for w in want])
    print(f"     stages: xpos diff {np.abs(out['xpos'] - xpos).max():.3g}, "
          f"qacc diff {np.abs(out['qacc'] - qacc).max():.3g}, "
          f"next_qpos diff {np.abs(out['next_qpos'] - nxt).max():.3g}")
    check(close_to(out["xpos"], xpos, 1e-4, 1e-6), "stages: xpos close to CPU")
    check(close_to(out["qacc"], qacc, 1e-4, 1e-5), "stages: qacc close to CPU")
    check(close_to(out["next_qpos"], nxt, 1e-4, 1e-6), "stages: next_qpos close to CPU")
    check(out["qM"].shape == (3, 1) and close_to(out["qM"][:, 0], 1 / 3 + 0.0, 1e-2, 0.05),
          f"stages: qM {out['qM'].reshape(-1)}")
    check(out["contact_geom"].shape == (0, 2) and out["efc_type"].shape == (0, 1),
          "stages: no contacts, no constraint rows")


def test_rollout(adapter):
    import mujoco
    mjm = mujoco.MjModel.from_xml_path(PENDULUM)
    mjd = mujoco.MjData(mjm)
    mjd.qpos[0] = 0.7
    for _ in range(250):
        mujoco.mj_step(mjm, mjd)
    began = time.perf_counter()
    header, out = adapter.request({"op": "rollout", "steps": 250, "every": 50},
                                  [("qpos", np.array([[0.7]])), ("qvel", np.zeros((1, 1))),
                                   ("ctrl_sequence", np.zeros((250, 0)))])
    check(header.get("ok"), f"rollout: {header.get('message', 'ok')}")
    if not header.get("ok"):
        return
    diff = out["qpos"][-1, 0] - mjd.qpos[0]
    print(f"     rollout: final qpos {out['qpos'][-1, 0]:.9f}, CPU {mjd.qpos[0]:.9f}, "
          f"diff {diff:.3g} ({time.perf_counter() - began:.1f} s)")
    check(out["qpos"].shape == (6, 1), "rollout: 250/50 + 1 rows")
    check(out["qpos"][0, 0] == 0.7 or abs(out["qpos"][0, 0] - 0.7) < 1e-7, "rollout: start row")
    check(abs(diff) < 1e-5, "rollout: final qpos within 1e-5 of CPU")
    check(out["ncon_max"].shape == (1, 1), "rollout: ncon_max")


def test_model_fields(adapter):
    """Worlds that differ in a model field: the damping slows the second pendulum."""
    qpos = np.array([[0.7], [0.7]])
    header, out = adapter.request({"op": "rollout", "steps": 250, "every": 250},
                                  [("qpos", qpos),
                                   ("model:dof_damping", np.array([[0.05], [5.0]]))])
    check(header.get("ok") and header.get("unvaried") == {},
          f"model:dof_damping varied per world ({header.get('unvaried', header)})")
    if header.get("ok"):
        first, second = out["qpos"][-1]
        print(f"     damping 0.05 -> qpos {first:.6f}, damping 5 -> {second:.6f}")
        check(abs(first - second) > 1e-3, "the damped world moves otherwise")


def test_no_device(engine):
    """--device cuda: the engine on a GPU, or no_device on a machine without one."""
    adapter = Adapter(engine, "cuda")
    header, _ = adapter.request({"op": "hello", "protocol": 1})
    print(f"     --device cuda: {header}")
    check(header.get("error") == "no_device" or header.get("device") == "cuda",
          "--device cuda: no_device without a GPU")
    adapter.request({"op": "quit"})
    check(adapter.close() == 0, "--device cuda: exit 0")


def test_refused_and_bad_request(adapter, folder):
    path = os.path.join(folder, "pgs.xml")
    with open(path, "w") as f:
        f.write(PGS)
    header, _ = adapter.request({"op": "stages"}, [("qpos", np.zeros((2, 5)))])
    check(header.get("error") == "bad_request", f"wrong qpos shape: {header}")
    header, _ = adapter.request({"op": "load", "model": path})
    print(f"     PGS: {header}")
    check(header.get("error") in ("refused",) or header.get("ok"), "PGS model: refused (or run)")
    header, _ = adapter.request({"op": "frobnicate"})
    check(header.get("error") == "bad_request", "unknown op: bad_request")
    adapter.send_raw(b"this is not json\n")
    header, _ = adapter.reply()
    check(header.get("error") == "bad_request", "garbage line: bad_request")
    header, _ = adapter.request({"op": "hello", "protocol": 1})
    check(header.get("ok"), "keeps serving after errors")


def test_box(adapter, folder):
    import mujoco
    path = os.path.join(folder, "box.xml")
    with open(path, "w") as f:
        f.write(BOX)
    mjm = mujoco.MjModel.from_xml_path(path)
    mjd = mujoco.MjData(mjm)
    for _ in range(300):  # let it settle: resting, the corners sink a little into the floor
        mujoco.mj_step(mjm, mjd)
    mujoco.mj_forward(mjm, mjd)
    header, _ = adapter.request({"op": "load", "model": path})
    check(header.get("ok"), "box: load")
    qpos = mjd.qpos.reshape(1, -1).copy()
    header, out = adapter.request({"op": "stages"}, [("qpos", qpos),
                                                      ("qacc_warmstart", mjd.qacc_warmstart[None])])
    check(header.get("ok"), f"box: stages {header.get('message', '')}")
    if not header.get("ok"):
        return
    ncon = out["contact_geom"].shape[0]
    print(f"     box: {ncon} contacts (CPU {mjd.ncon}), {out['efc_type'].shape[0]} rows "
          f"(CPU {mjd.nefc}), capacity {header['capacity']}, overflow {header['overflow']}")
    check(ncon == mjd.ncon == 4, "box: the 4 corner contacts, like CPU")
    cpu = sorted(tuple(np.round(c.pos, 4)) for c in mjd.contact)
    got = sorted(tuple(np.round(p, 4)) for p in out["contact_pos"])
    check(np.allclose(np.array(cpu), np.array(got), atol=1e-4), "box: contact positions")
    check(np.all(out["contact_force"][:, 0] > 0), "box: normal forces from the engine > 0")
    total = out["contact_force"][:, 0].sum()
    check(abs(total - 9.81) < 0.5, f"box: normal forces carry the weight ({total:.3f} N)")
    header, out = adapter.request({"op": "rollout", "steps": 100, "every": 100},
                                  [("qpos", np.repeat(qpos, 2, axis=0)),
                                   ("model:body_mass", np.array([[0, 1.0], [0, 2.0]]))])
    most = out["ncon_max"].reshape(-1).tolist() if header.get("ok") else header
    check(most == [4, 4], f"box: rollout of 2 worlds, ncon_max {most}, {header.get('unvaried')}")
    header, _ = adapter.request({"op": "throughput", "worlds": 8, "steps": 50},
                                [("qpos", qpos)])
    print(f"     throughput: {header}")
    check(header.get("ok") and header["seconds"] > 0, "throughput")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--engine", choices=("warp", "mjx"), required=True)
    parser.add_argument("--device", default="cpu")
    options = parser.parse_args()
    adapter = Adapter(options.engine, options.device)
    with tempfile.TemporaryDirectory() as folder:
        try:
            test_hello_and_load(adapter, options.engine)
            test_stages(adapter)
            test_rollout(adapter)
            test_model_fields(adapter)
            test_refused_and_bad_request(adapter, folder)
            test_box(adapter, folder)
            header, _ = adapter.request({"op": "quit"})
            check(header.get("ok"), "quit")
        except Exception as error:  # a dead adapter: report it as a failure
            check(False, f"the conversation broke: {type(error).__name__}: {error}")
        check(adapter.close() == 0, "exit 0")
    test_no_device(options.engine)
    broken = Adapter(options.engine, options.device)
    header = b'{"op": "stages", "arrays": [{"name": "qpos", "shape": [4, 1]}]}\n'
    broken.send_raw(header + b"\0" * 9)  # 9 of the 32 bytes the header announces
    check(broken.close() == 3, "input broken inside a message: exit 3")
    print(f"{len(failures)} failure(s)" if failures else "all passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
