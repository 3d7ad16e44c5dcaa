"""MuJoCo Warp behind the adapter's engine interface (see adapter.py)."""

import dataclasses
import importlib.metadata

import mujoco
import numpy as np
import warp as wp

wp.config.quiet = True  # before wp.init: Warp's banner would be noise in the log
wp.config.log_level = wp.LOG_WARNING  # and so would a line for every kernel module it loads
import mujoco_warp as mjw  # noqa: E402
from mujoco_warp._src import types as mjw_types  # noqa: E402  (which Model fields batch)

STATE_FIELDS = ("time", "qpos", "qvel", "act", "ctrl", "qacc_warmstart", "qfrc_applied",
                "xfrc_applied", "mocap_pos", "mocap_quat")


class NoDevice(Exception):
    """The device asked for does not exist."""


@dataclasses.dataclass
class Batch:
    m: object  # mujoco_warp Model
    d: object  # mujoco_warp Data
    worlds: int
    capacity: dict


class Engine:
    name = "warp"
    precision = "float32"

    def __init__(self, device):
        wp.init()
        if device == "cuda":
            if wp.get_cuda_device_count() == 0:
                raise NoDevice("no CUDA device: Warp finds no GPU (use --device cpu)")
            device = "cuda:0"
        wp.set_device(device)
        self.device = "cuda" if device.startswith("cuda") else "cpu"
        self.version = importlib.metadata.version("mujoco-warp")
        self.backend = f"warp-lang {wp.config.version}"
        self.mjm = None
        self.model = None

    def load(self, mjm):
        self.model = None
        self.model = mjw.put_model(mjm)  # raises NotImplementedError for what Warp lacks
        self.mjm = mjm

    def start(self, datas, fields, capacity):
        """A batch of len(datas) worlds at the datas' states, fields varied per world."""
        worlds = len(datas)
        varied, unvaried = batchable(fields)
        m = self.model
        if varied:
            m = mjw.put_model(self.mjm, batch_sizes={name: worlds for name in varied})
            for name in list(varied):
                array = getattr(m, name)
                if array_elements(array) != fields[name].size:
                    unvaried[name] = "MuJoCo Warp stores " + name + " in another layout"
                    continue
                assign(array, fields[name])
        d = mjw.put_data(self.mjm, mujoco.MjData(self.mjm), nworld=worlds,
                         nconmax=capacity["nconmax"], njmax=capacity["njmax"])
        for name in STATE_FIELDS:
            values = np.stack([np.atleast_1d(getattr(mjd, name)).reshape(-1) for mjd in datas])
            assign(getattr(d, name), values)
        return Batch(m, d, worlds, dict(capacity)), unvaried

    def forward(self, batch):
        mjw.forward(batch.m, batch.d)

    def step(self, batch):
        mjw.step(batch.m, batch.d)

    def sync(self, batch):
        wp.synchronize()

    def set_ctrl(self, batch, ctrl):
        assign(batch.d.ctrl, ctrl)

    def read(self, batch, names):
        return {n: getattr(batch.d, n).numpy().reshape(batch.worlds, -1).astype(float)
                for n in names}

    def world_into(self, batch, world, mjd):
        mjw.get_data_into(mjd, self.mjm, batch.d, world_id=world)

    def tally(self, batch, tally):
        """(most contacts per world, worst overflow) so far; Warp's counters are read on the
        host each step (a few integers, and the contacts' world ids)."""
        counts, spill = counts_now(batch)
        if tally is None:
            return counts, spill
        most, overflow = tally
        return np.maximum(most, counts), {k: max(overflow[k], spill[k]) for k in overflow}

    def tally_result(self, batch, tally):
        return tally

    def capacity(self, batch):
        return batch.capacity


def counts_now(batch):
    """Contacts each world holds now, and what did not fit (contacts, constraint rows): Warp
    counts past its capacity (nacon against naconmax, nefc per world against njmax)."""
    d = batch.d
    nacon = int(d.nacon.numpy()[0])
    kept = min(nacon, d.naconmax)
    exported = mjw_types.ContactType.CONSTRAINT | mjw_types.ContactType.PASSIVE
    world = d.contact.worldid.numpy()[:kept]
    world = world[(d.contact.type.numpy()[:kept] & exported) != 0]
    per_world = np.bincount(world, minlength=batch.worlds)[:batch.worlds]
    nefc = d.nefc.numpy()
    overflow = {"contacts": max(0, nacon - d.naconmax),
                "constraints": int(np.maximum(nefc - d.njmax, 0).sum())}
    return per_world, overflow


def batchable(fields):
    """The fields Warp can vary per world, and {field: reason} for the others. A field Warp's
    Model does not have is one it never reads (a constant CPU MuJoCo derives for itself): it is
    left out, as nothing depends on it."""
    specs = {f.name: f.type for f in dataclasses.fields(mjw_types.Model)}
    varied, unvaried = [], {}
    for name in fields:
        spec = specs.get(name)
        if spec is None:
            continue
        if tuple(getattr(spec, "shape", ()))[:1] != ("*",):
            unvaried[name] = "MuJoCo Warp shares " + name + " across worlds (not batchable)"
        else:
            varied.append(name)
    return varied, unvaried


def array_elements(array):
    """The scalars in a Warp array (its vectors and matrices unrolled)."""
    return int(np.prod(array.shape + tuple(getattr(array.dtype, "_shape_", ()))))


def assign(array, values):
    """Copies values (one row a world) into a Warp array of the same element count."""
    if array.size == 0:
        return
    shape = array.shape + tuple(getattr(array.dtype, "_shape_", ()))
    host = np.asarray(values).reshape(shape)
    array.assign(wp.array(host, dtype=array.dtype, device=array.device))
