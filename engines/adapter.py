"""The engine adapter through which plumb (C++) drives MuJoCo Warp or MJX.

    python adapter.py --engine warp|mjx --device cpu|cuda

It speaks the protocol of docs/engine-protocol.md on its standard input and output: one JSON
line, then the float64 arrays the line lists. It only runs the engine and ships arrays; plumb
makes every comparison. Standard error is its log. This file is the engine-neutral core; the
engine itself lives in _warp.py and _mjx.py beside it, behind the same small interface:

    name, version, backend, precision          what runs (for hello)
    load(mjm)                                  prepares the model (raises to refuse it)
    start(states, fields, capacity)            a batch of worlds; returns (batch, unvaried)
    forward(batch), step(batch), sync(batch)
    set_ctrl(batch, ctrl)                      ctrl [W, nu]
    read(batch, names)                         {name: [W, n]} of qpos, qvel, act
    world_into(batch, world, mjd)              one world's results into a CPU MjData
    tally(batch, tally)                        adds the present contact counts to a running
                                               tally (None to begin; kept on the device
                                               where the engine can)
    tally_result(batch, tally)                 (most contacts a world held [W], overflow
                                               dict: the worst step's contacts and rows)
    capacity(batch)                            {"nconmax": n, "njmax": n}
"""

import argparse
import json
import os
import sys
import time
import traceback

PROTOCOL = 1
STATE_FIELDS = ("time", "qpos", "qvel", "act", "ctrl", "qacc_warmstart", "qfrc_applied",
                "xfrc_applied", "mocap_pos", "mocap_quat")
MIN_CONTACTS = 32  # contacts a world has room for at the least
DENSE_QM_LIMIT = 400


class Failure(Exception):
    """An error reply: kind is refused, bad_request, no_device or engine_error."""

    def __init__(self, kind, message):
        super().__init__(message)
        self.kind = kind
        self.message = message


class BrokenInput(Exception):
    """The input ended inside a message."""


def verbatim(error):
    """An exception as the engine said it: "TypeName: message"."""
    return f"{type(error).__name__}: {error}"


# ---------------------------------------------------------------------------------------------
# Framing

def read_exact(stream, count):
    data = stream.read(count)
    if len(data) != count:
        raise BrokenInput(f"input ended after {len(data)} of {count} payload bytes")
    return data


def read_message(stream):
    """The next request as (header, {name: array}); None at the end of the input."""
    line = stream.readline()
    if not line:
        return None
    if not line.endswith(b"\n"):
        raise BrokenInput("input ended inside a header line")
    try:
        header = json.loads(line.decode("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as error:
        raise Failure("bad_request", f"the header is not JSON: {error}") from None
    if not isinstance(header, dict):
        raise Failure("bad_request", "the header is not a JSON object")
    arrays = {}
    specs = header.get("arrays", [])
    if not isinstance(specs, list):
        raise Failure("bad_request", '"arrays" is not a list')
    problem = None
    for spec in specs:
        name, shape = spec_of(spec)
        if shape is None:
            problem = problem or f"array {spec!r} has no valid name and shape"
            continue  # its size is unknown: the rest of the stream cannot be framed
        count = int(np.prod(shape)) if shape else 1
        arrays[name] = np.frombuffer(read_exact(stream, 8 * count), dtype="<f8").reshape(shape)
    if problem:
        raise Failure("bad_request", problem)
    return header, arrays


def spec_of(spec):
    """(name, shape) of one entry of "arrays"; shape None when it is malformed."""
    if not isinstance(spec, dict) or not isinstance(spec.get("name"), str):
        return None, None
    shape = spec.get("shape")
    if not isinstance(shape, list) or not all(isinstance(n, int) and n >= 0 for n in shape):
        return spec["name"], None
    return spec["name"], tuple(shape)


def write_message(stream, header, arrays=()):
    """One reply: the header line (listing the arrays), then their float64 payload."""
    packed = [(name, np.ascontiguousarray(value, dtype="<f8")) for name, value in arrays]
    if packed:
        header = dict(header, arrays=[{"name": n, "shape": list(v.shape)} for n, v in packed])
    stream.write(json.dumps(header, separators=(",", ":")).encode("utf-8") + b"\n")
    for _, value in packed:
        stream.write(value.tobytes())
    stream.flush()


# ---------------------------------------------------------------------------------------------
# States and models

def world_count(arrays):
    """W: the rows of the state arrays (they must agree)."""
    rows = {value.shape[0] for name, value in arrays.items()
            if (name in STATE_FIELDS or name.startswith("model:")) and value.ndim == 2}
    if len(rows) > 1:
        raise Failure("bad_request", f"state arrays disagree on the number of worlds: {rows}")
    return rows.pop() if rows else 1


def state_datas(mjm, arrays, worlds):
    """One CPU MjData a world, holding its state (defaults where an array is missing)."""
    datas = []
    for world in range(worlds):
        mjd = mujoco.MjData(mjm)
        for name in STATE_FIELDS:
            if name not in arrays:
                continue
            value = arrays[name]
            target = getattr(mjd, name)
            size = 1 if name == "time" else target.size
            if value.ndim != 2 or value.shape[1] != size:
                raise Failure("bad_request", f"{name} has shape {list(value.shape)}, "
                              f"want [{worlds}, {size}]")
            if name == "time":
                mjd.time = float(value[world, 0])
            else:
                target.flat[:] = value[world]
        datas.append(mjd)
    return datas


def model_fields(mjm, arrays, worlds):
    """{FIELD: [W, size]} from the model:FIELD arrays, checked against the MjModel."""
    fields = {}
    for name, value in arrays.items():
        if not name.startswith("model:"):
            continue
        field = name[len("model:"):]
        target = getattr(mjm, field, None)
        if not isinstance(target, np.ndarray):
            raise Failure("bad_request", f"{name}: MjModel has no array {field}")
        if value.shape != (worlds, target.size):
            raise Failure("bad_request", f"{name} has shape {list(value.shape)}, "
                          f"want [{worlds}, {target.size}]")
        fields[field] = value
    return fields


def capacity_for(mjm, datas):
    """Room per world for contacts and constraint rows: twice what CPU MuJoCo finds at the
    given states, and at least MIN_CONTACTS or 4 a geom, since a rollout may gather more
    than its start; rows for that many contacts of the model's largest condim, plus its
    equality, limit and friction-loss rows."""
    ncon = nefc = 0
    for mjd in datas:
        probe = mujoco.MjData(mjm)
        probe.qpos[:], probe.qvel[:], probe.act[:] = mjd.qpos, mjd.qvel, mjd.act
        probe.mocap_pos[:], probe.mocap_quat[:] = mjd.mocap_pos, mjd.mocap_quat
        mujoco.mj_forward(mjm, probe)
        ncon, nefc = max(ncon, probe.ncon), max(nefc, probe.nefc)
    nconmax = max(2 * ncon, MIN_CONTACTS, 4 * mjm.ngeom)
    condim = int(max([3, *mjm.geom_condim, *mjm.pair_dim]))
    elliptic = mjm.opt.cone == mujoco.mjtCone.mjCONE_ELLIPTIC
    rows_per_contact = condim if elliptic else 2 * (condim - 1)
    other_rows = 6 * mjm.neq + mjm.njnt + mjm.nv + mjm.ntendon
    njmax = max(2 * nefc, nconmax * rows_per_contact + other_rows)
    return {"nconmax": nconmax, "njmax": njmax}


def compile_model(path, edits):
    """The MjModel of an MJCF or .mjb file, with plumb's edits applied."""
    if not isinstance(path, str) or not os.path.isfile(path):
        raise Failure("bad_request", f"no model file {path!r}")
    try:
        if path.endswith(".mjb"):
            mjm = mujoco.MjModel.from_binary_path(path)
        else:
            mjm = mujoco.MjModel.from_xml_path(path)
    except Exception as error:  # the file itself is wrong: plumb compiled it, so a bug
        raise Failure("bad_request", verbatim(error)) from None
    for edit in edits or []:
        if not (isinstance(edit, list) and len(edit) == 3 and isinstance(edit[0], str)):
            raise Failure("bad_request", f"edit {edit!r} is not [field, index, value]")
        field, index, value = edit
        if field.startswith("opt."):  # an option: a scalar, or an array such as opt.gravity
            set_option(mjm.opt, field[4:], int(index), value, edit)
            continue
        target = getattr(mjm, field, None)
        if not isinstance(target, np.ndarray) or not 0 <= int(index) < target.size:
            raise Failure("bad_request", f"edit {edit!r}: no such MjModel element")
        target.flat[int(index)] = value
    return mjm


def set_option(opt, name, index, value, edit):
    """Writes element `index` of option `name` (mjOption's field)."""
    current = getattr(opt, name, None)
    if isinstance(current, np.ndarray):
        if not 0 <= index < current.size:
            raise Failure("bad_request", f"edit {edit!r}: no such option element")
        current.flat[index] = value
    elif current is not None and index == 0:
        setattr(opt, name, type(current)(value))
    else:
        raise Failure("bad_request", f"edit {edit!r}: no such option")


# ---------------------------------------------------------------------------------------------
# Requests

class Session:
    """The adapter's state between requests: the engine and the loaded model."""

    def __init__(self, engine):
        self.engine = engine
        self.mjm = None

    def hello(self, header, arrays):
        if header.get("protocol") != PROTOCOL:
            log(f"plumb speaks protocol {header.get('protocol')}, this adapter {PROTOCOL}")
        e = self.engine
        return {"protocol": PROTOCOL, "engine": e.name, "engine_version": e.version,
                "backend": e.backend, "mujoco_version": mujoco.__version__,
                "mujoco_library": mujoco_library(), "device": e.device,
                "precision": e.precision}, []

    def load(self, header, arrays):
        mjm = compile_model(header.get("model"), header.get("edits"))
        self.mjm = None
        try:
            self.engine.load(mjm)
        except Exception as error:
            raise Failure("refused", verbatim(error)) from None
        self.mjm = mjm
        sizes = {k: int(getattr(mjm, k)) for k in
                 ("nq", "nv", "na", "nu", "nbody", "ngeom", "nmocap", "nsensordata")}
        return {"sizes": sizes}, []

    def start(self, arrays, worlds=None):
        """The engine's batch of worlds for a request's state and model:FIELD arrays."""
        if self.mjm is None:
            raise Failure("bad_request", "no model loaded")
        worlds = worlds or world_count(arrays)
        if worlds < 1:
            raise Failure("bad_request", "no worlds")
        datas = state_datas(self.mjm, arrays, worlds)
        fields = model_fields(self.mjm, arrays, worlds)
        capacity = capacity_for(self.mjm, datas)
        batch, unvaried = self.engine.start(datas, fields, capacity)
        return batch, unvaried, worlds

    def stages(self, header, arrays):
        batch, unvaried, worlds = self.start(arrays)
        self.engine.forward(batch)
        self.engine.sync(batch)
        _, overflow = self.engine.tally_result(batch, self.engine.tally(batch, None))
        out = record_stages(self.mjm, self.engine, batch, worlds)
        # the step starts from the given state again, warm start included, as plumb's does:
        # an engine's forward may keep its solution as the next warm start
        batch, _, _ = self.start(arrays)
        self.engine.step(batch)
        self.engine.sync(batch)
        after = self.engine.read(batch, ("qpos", "qvel", "act"))
        out += [("next_" + k, after[k]) for k in ("qpos", "qvel", "act")]
        return {"capacity": self.engine.capacity(batch), "overflow": overflow,
                "unvaried": unvaried}, out

    def rollout(self, header, arrays):
        steps, every = header.get("steps"), header.get("every", 1)
        if not (isinstance(steps, int) and steps >= 0 and isinstance(every, int) and every >= 1):
            raise Failure("bad_request", '"steps" and "every" must be integers, >= 0 and >= 1')
        batch, unvaried, worlds = self.start(arrays)
        controls = arrays.get("ctrl_sequence")
        nu = self.mjm.nu
        if controls is not None and controls.shape != (steps, worlds * nu):
            raise Failure("bad_request", f"ctrl_sequence has shape {list(controls.shape)}, "
                          f"want [{steps}, {worlds * nu}]")
        rows, most, overflow = run_rollout(self.engine, batch, steps, every, controls, nu)
        out = [(k, np.stack([r[k].reshape(-1) for r in rows])) for k in ("qpos", "qvel", "act")]
        out.append(("ncon_max", most.reshape(worlds, 1)))
        return {"capacity": self.engine.capacity(batch), "overflow": overflow,
                "unvaried": unvaried}, out

    def throughput(self, header, arrays):
        worlds, steps = header.get("worlds"), header.get("steps")
        if not (isinstance(worlds, int) and worlds >= 1 and isinstance(steps, int) and steps >= 0):
            raise Failure("bad_request", '"worlds" and "steps" must be positive integers')
        if any(v.ndim != 2 or v.shape[0] != 1 for v in arrays.values()):
            raise Failure("bad_request", "throughput takes state arrays of one row")
        tiled = {name: np.repeat(value, worlds, axis=0) for name, value in arrays.items()}
        batch, _, _ = self.start(tiled, worlds)
        began = time.perf_counter()
        self.engine.step(batch)
        self.engine.sync(batch)
        compiled = time.perf_counter()
        for _ in range(steps):
            self.engine.step(batch)
        self.engine.sync(batch)
        ended = time.perf_counter()
        return {"seconds": ended - compiled, "compile_seconds": compiled - began}, []


def record_stages(mjm, engine, batch, worlds):
    """The stages' arrays of every world, read back from the engine through an MjData."""
    per_world = {k: [] for k in ("xpos", "xquat", "qM", "qacc", "sensordata")}
    contacts, rows = [], []
    mjd = mujoco.MjData(mjm)
    dense = np.zeros((mjm.nv, mjm.nv))
    force = np.zeros(6)
    for world in range(worlds):
        engine.world_into(batch, world, mjd)
        per_world["xpos"].append(mjd.xpos.reshape(-1).copy())
        per_world["xquat"].append(mjd.xquat.reshape(-1).copy())
        per_world["qacc"].append(mjd.qacc.copy())
        per_world["sensordata"].append(mjd.sensordata.copy())
        if mjm.nv <= DENSE_QM_LIMIT:
            mujoco.mj_fullM(mjm, mjd, dense)
            per_world["qM"].append(dense.reshape(-1).copy())
        else:
            per_world["qM"].append(np.zeros(0))
        for i in range(mjd.ncon):
            c = mjd.contact[i]
            force[:] = 0  # a contact outside the constraint (no rows) carries no force
            if 0 <= c.efc_address < mjd.nefc:
                mujoco.mj_contactForce(mjm, mjd, i, force)
            contacts.append(np.concatenate([[world], c.geom, [c.dist], c.pos,
                                            c.frame, [c.dim], force]))
        owner = contact_of_rows(mjd)
        for j in range(mjd.nefc):
            rows.append([world, mjd.efc_type[j], owner.get(j, mjd.efc_id[j]), mjd.efc_pos[j],
                         mjd.efc_force[j]])
    out = [(k, np.stack(v)) for k, v in per_world.items()]
    c = np.array(contacts, dtype=float).reshape(-1, 23)
    out += [("contact_world", c[:, 0:1]), ("contact_geom", c[:, 1:3]),
            ("contact_dist", c[:, 3:4]), ("contact_pos", c[:, 4:7]),
            ("contact_frame", c[:, 7:16]), ("contact_dim", c[:, 16:17]),
            ("contact_force", c[:, 17:23])]
    r = np.array(rows, dtype=float).reshape(-1, 5)
    out += [(name, r[:, i:i + 1]) for i, name in
            enumerate(("efc_world", "efc_type", "efc_id", "efc_pos", "efc_force"))]
    return out


CONTACT_ROWS = None  # the mjtConstraint values of contact rows (set in main)


def contact_of_rows(mjd):
    """{row: index of its contact in this world's list} for contact rows: an engine may number
    a contact row's efc_id across all worlds (Warp does), the protocol numbers it per world. A
    contact's rows run from its efc_address to the next contact's (or the last contact row)."""
    starts = sorted((c.efc_address, i) for i, c in enumerate(mjd.contact) if c.efc_address >= 0)
    owner = {}
    for k, (address, i) in enumerate(starts):
        end = starts[k + 1][0] if k + 1 < len(starts) else mjd.nefc
        for j in range(address, end):
            if mjd.efc_type[j] not in CONTACT_ROWS:
                break
            owner[j] = i
    return owner


def run_rollout(engine, batch, steps, every, controls, nu):
    """Steps the batch, recording qpos/qvel/act at the start and every k-th step; returns the
    rows, the most contacts each world held and the overflow (worst step)."""
    names = ("qpos", "qvel", "act")
    rows = [engine.read(batch, names)]
    engine.forward(batch)  # the start's contacts count too
    tally = engine.tally(batch, None)
    for step in range(steps):
        if controls is not None and nu:
            engine.set_ctrl(batch, controls[step].reshape(-1, nu))
        engine.step(batch)
        tally = engine.tally(batch, tally)
        if (step + 1) % every == 0:
            rows.append(engine.read(batch, names))
    most, overflow = engine.tally_result(batch, tally)
    return rows, np.asarray(most, dtype=float), overflow


def mujoco_library():
    folder = os.path.dirname(mujoco.__file__)
    names = sorted(n for n in os.listdir(folder) if n.startswith("libmujoco.so"))
    return os.path.join(folder, names[-1]) if names else folder


# ---------------------------------------------------------------------------------------------
# Main loop

def log(text):
    print(f"adapter: {text}", file=sys.stderr, flush=True)


def serve(session, requests, replies):
    """Answers requests until quit or the end of the input; returns the exit code."""
    handlers = {"hello": session.hello, "load": session.load, "stages": session.stages,
                "rollout": session.rollout, "throughput": session.throughput}
    while True:
        try:
            message = read_message(requests)
        except BrokenInput as error:
            log(f"input broke off: {error}")
            return 3
        except Failure as failure:
            refuse(replies, failure.kind, failure.message)
            continue
        if message is None:
            return 0
        header, arrays = message
        op = header.get("op")
        if op == "quit":
            write_message(replies, {"ok": True})
            return 0
        try:
            if op not in handlers:
                raise Failure("bad_request", f"unknown op {op!r}")
            reply, out = handlers[op](header, arrays)
            write_message(replies, dict({"ok": True}, **reply), out)
        except Failure as failure:
            refuse(replies, failure.kind, failure.message)
        except NotImplementedError as error:  # a feature the engine lacks, met while running
            refuse(replies, "refused", verbatim(error))
        except Exception as error:
            log(traceback.format_exc().rstrip())
            refuse(replies, "engine_error", verbatim(error))


def refuse(replies, kind, message):
    """An error reply."""
    write_message(replies, {"ok": False, "error": kind, "message": message})


def protocol_streams():
    """The protocol's output (the real stdout) and input, with fd 1 then pointed at stderr so
    that whatever the engines print cannot reach plumb."""
    replies = os.fdopen(os.dup(1), "wb", buffering=0)
    os.dup2(2, 1)
    sys.stdout = sys.stderr
    return sys.stdin.buffer, replies


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--engine", choices=("warp", "mjx"), required=True)
    parser.add_argument("--device", choices=("cpu", "cuda"), default="cpu")
    options = parser.parse_args()
    requests, replies = protocol_streams()
    if options.engine == "mjx" and options.device == "cpu":
        os.environ["JAX_PLATFORMS"] = "cpu"
    global mujoco, np, CONTACT_ROWS  # imported after the streams are set, like the engines
    import mujoco
    import numpy as np
    c = mujoco.mjtConstraint
    CONTACT_ROWS = {int(c.mjCNSTR_CONTACT_FRICTIONLESS), int(c.mjCNSTR_CONTACT_PYRAMIDAL),
                    int(c.mjCNSTR_CONTACT_ELLIPTIC)}
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    try:
        if options.engine == "warp":
            import _warp as engine_module
        else:
            import _mjx as engine_module
        engine = engine_module.Engine(options.device)
    except engine_module.NoDevice as error:  # every request gets no_device, then exit as usual
        return serve_failure(Failure("no_device", str(error)), requests, replies)
    return serve(Session(engine), requests, replies)


def serve_failure(failure, requests, replies):
    """Replies failure to every request (quit excepted) when the engine could not start."""
    log(failure.message)
    while True:
        try:
            message = read_message(requests)
        except BrokenInput:
            return 3
        except Failure:
            message = ({}, {})
        if message is None:
            return 0
        if message[0].get("op") == "quit":
            write_message(replies, {"ok": True})
            return 0
        refuse(replies, failure.kind, failure.message)


mujoco = np = None

if __name__ == "__main__":
    sys.exit(main())
