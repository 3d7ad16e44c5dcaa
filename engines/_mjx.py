"""MJX (MuJoCo in JAX) behind the adapter's engine interface (see adapter.py).

Worlds are a leading batch axis: jax.vmap over Data, and over the Model fields varied per world
(in_axes 0 for those, None for the rest). JAX runs in float32 (x64 is left off). MJX allocates
every contact its collision functions can produce, so nothing overflows: a contact is one with
dist <= 0, which is also what mjx.get_data_into exports.
"""

import dataclasses
import importlib.metadata

import jax
import jax.numpy as jnp
import mujoco
import numpy as np
from mujoco import mjx

STATE_FIELDS = ("time", "qpos", "qvel", "act", "ctrl", "qacc_warmstart", "qfrc_applied",
                "xfrc_applied", "mocap_pos", "mocap_quat")


class NoDevice(Exception):
    """The device asked for does not exist."""


@dataclasses.dataclass
class Batch:
    m: object  # mjx.Model, its varied fields with a leading world axis
    d: object  # mjx.Data, batched over worlds
    worlds: int
    functions: dict  # jitted forward, step, count for this Model's axes


class Engine:
    name = "mjx"
    precision = "float32"

    def __init__(self, device):
        platform = "gpu" if device == "cuda" else "cpu"
        try:
            self.jax_device = jax.devices(platform)[0]
        except RuntimeError as error:
            raise NoDevice(f"no CUDA device for JAX ({error}); use --device cpu") from None
        self.device = device
        self.version = importlib.metadata.version("mujoco-mjx")
        self.backend = f"jax {jax.__version__}, jaxlib {importlib.metadata.version('jaxlib')}"
        self.mjm = None
        self.model = None
        self.compiled = {}

    def load(self, mjm):
        self.model = None
        self.compiled = {}
        self.model = mjx.put_model(mjm, device=self.jax_device)  # NotImplementedError: refused
        self.mjm = mjm

    def start(self, datas, fields, capacity):
        """A batch of len(datas) worlds at the datas' states, fields varied per world."""
        worlds = len(datas)
        varied, unvaried = self.variable(fields)
        m = self.model
        if varied:
            m = m.tree_replace({name: per_world(getattr(m, name), fields[name])
                                for name in varied})
        one = mjx.put_data(self.mjm, mujoco.MjData(self.mjm), device=self.jax_device)
        d = jax.tree_util.tree_map(lambda x: jnp.repeat(x[None], worlds, axis=0), one)
        states = {}
        for name in STATE_FIELDS:
            values = np.stack([np.atleast_1d(getattr(mjd, name)).reshape(-1) for mjd in datas])
            states[name] = jnp.asarray(values.reshape(getattr(d, name).shape),
                                       getattr(d, name).dtype)
        # committed to the device like the step's output, so the warm-up step compiles the
        # only version the run needs (uncommitted inputs would compile a second one)
        d = jax.device_put(d.replace(**states), self.jax_device)
        m = jax.device_put(m, self.jax_device)
        return Batch(m, d, worlds, self.functions(m, tuple(varied))), unvaried

    def variable(self, fields):
        """The fields MJX can vary per world, and {field: reason} for the others. A field MJX's
        Model does not have is one it never reads: it is left out."""
        varied, unvaried = [], {}
        for name in fields:
            value = getattr(self.model, name, None)
            if value is None:
                continue
            if not isinstance(value, jax.Array):
                unvaried[name] = "MJX keeps " + name + " as a static numpy array"
            elif value.size != fields[name].shape[1]:
                unvaried[name] = "MJX stores " + name + " in another layout"
            else:
                varied.append(name)
        return varied, unvaried

    def functions(self, m, varied):
        """Jitted, vmapped forward, step and contact count for Models varied in these fields
        (compiled once for each set of fields)."""
        if varied not in self.compiled:
            axes = jax.tree_util.tree_map(lambda _: None, m)
            if varied:
                axes = axes.tree_replace({name: 0 for name in varied})
            count = jax.vmap(lambda d: jnp.sum(d._impl.contact.dist <= 0))
            self.compiled[varied] = {
                "forward": jax.jit(jax.vmap(mjx.forward, in_axes=(axes, 0))),
                "step": jax.jit(jax.vmap(mjx.step, in_axes=(axes, 0))),
                "tally": jax.jit(lambda d, most: jnp.maximum(most, count(d))),
            }
        return self.compiled[varied]

    def forward(self, batch):
        batch.d = batch.functions["forward"](batch.m, batch.d)

    def step(self, batch):
        batch.d = batch.functions["step"](batch.m, batch.d)

    def sync(self, batch):
        jax.block_until_ready(batch.d)

    def set_ctrl(self, batch, ctrl):
        batch.d = batch.d.replace(ctrl=jnp.asarray(ctrl, jnp.float32))

    def read(self, batch, names):
        return {n: np.asarray(getattr(batch.d, n), dtype=float).reshape(batch.worlds, -1)
                for n in names}

    def world_into(self, batch, world, mjd):
        one = jax.tree_util.tree_map(lambda x: x[world], batch.d)
        mjx.get_data_into(mjd, self.mjm, one)
        name_rows(self.mjm, mjd)

    def tally(self, batch, tally):
        """The most contacts each world held so far, kept on the device."""
        if tally is None:
            tally = jnp.zeros(batch.worlds, jnp.int32)
        return batch.functions["tally"](batch.d, tally)

    def tally_result(self, batch, tally):
        return np.asarray(tally), {"contacts": 0, "constraints": 0}

    def capacity(self, batch):
        """MJX's fixed sizes: every contact its collision functions can make, and the
        constraint rows for them."""
        impl = batch.d._impl
        return {"nconmax": int(impl.contact.dist.shape[-1]), "njmax": int(impl.efc_J.shape[-2])}


def name_rows(mjm, mjd):
    """Fills efc_id of the non-contact rows, which mjx.get_data_into leaves unset (measured: stray
    integers). MJX emits them in MuJoCo's order: equalities, dof and tendon friction, joint and
    tendon limits. An equality's or a friction's rows follow the elements in order; a limit row
    is the limited element whose distance to its range, in the engine's own state, is the row's."""
    c = mujoco.mjtConstraint
    eq = [i for i in range(mjm.neq) if mjd.eq_active[i]
          for _ in range({0: 3, 1: 6}.get(int(mjm.eq_type[i]), 1))]
    queues = {int(c.mjCNSTR_EQUALITY): eq,
              int(c.mjCNSTR_FRICTION_DOF): [i for i in range(mjm.nv) if mjm.dof_frictionloss[i] > 0],
              int(c.mjCNSTR_FRICTION_TENDON):
                  [i for i in range(mjm.ntendon) if mjm.tendon_frictionloss[i] > 0]}
    used = {k: 0 for k in queues}
    after = {int(c.mjCNSTR_LIMIT_JOINT): (-1, 1), int(c.mjCNSTR_LIMIT_TENDON): (-1, 1)}
    for row in range(mjd.nefc):
        kind = int(mjd.efc_type[row])
        if kind in queues and used[kind] < len(queues[kind]):
            mjd.efc_id[row] = queues[kind][used[kind]]
            used[kind] += 1
        elif kind in after:
            joints = kind == int(c.mjCNSTR_LIMIT_JOINT)
            found = limited(
                mjm.njnt if joints else mjm.ntendon,
                mjm.jnt_limited if joints else mjm.tendon_limited,
                mjm.jnt_range if joints else mjm.tendon_range,
                mjm.jnt_margin if joints else mjm.tendon_margin,
                (lambda j: joint_value(mjm, mjd, j)) if joints else (lambda t: mjd.ten_length[t]),
                mjd.efc_pos[row], after[kind])
            after[kind] = found
            mjd.efc_id[row] = found[0]


def joint_value(mjm, mjd, j):
    """A hinge's or slide's coordinate; a ball's rotation angle."""
    adr = mjm.jnt_qposadr[j]
    if mjm.jnt_type[j] == mujoco.mjtJoint.mjJNT_BALL:
        return 2 * np.arctan2(np.linalg.norm(mjd.qpos[adr + 1:adr + 4]), abs(mjd.qpos[adr]))
    return mjd.qpos[adr]


def limited(count, is_limited, ranges, margins, value, pos, after):
    """(element, side) of the limit row with distance `pos`: the first limited element past
    `after` (rows come in element order, lower side first) whose distance to that side of its
    range, in the engine's own state, is `pos` to float32 rounding; (-1, 1) when none is."""
    for i in range(max(after[0], 0), count):
        if not is_limited[i]:
            continue
        v, (low, high) = value(i), ranges[i]
        for side, distance in enumerate((v - low - margins[i], high - v - margins[i])):
            if (i, side) <= after:
                continue
            if abs(distance - pos) < 1e-4 * max(1.0, abs(pos)):
                return i, side
    return -1, 1


def per_world(value, rows):
    """rows [W, size] as the Model field value with a leading world axis (and its dtype)."""
    return jnp.asarray(rows.reshape((rows.shape[0],) + value.shape), value.dtype)
