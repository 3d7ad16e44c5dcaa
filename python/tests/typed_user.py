"""A user's script over every result type of plumb, for mypy --strict (test_typing.py checks it
with the stubs of this build; it is type-checked, not run). A type the stubs get wrong (an array
typed `object`, a bare list) fails the check here before it fails a user's."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

import plumb

MODEL = "models/pendulum.xml"


def rows(result: plumb.VerifyResult | plumb.AuditResult | plumb.RehearsalResult) -> list[str]:
    return [f"{row.status} {row.id} {row.measured:.3g} {row.fix}" for row in result.rows]


def verify_and_audit() -> bool:
    v = plumb.verify(MODEL, set={"qpos[hinge]": 0.7}, keyframe=0, qpos=[0.3])
    a = plumb.audit(plumb.load(MODEL))
    until: float = v.horizon["until"]
    page: str = v.html(full=False)
    v.save_report("verify.html")
    return v.ok and a.ok and len(rows(v) + rows(a)) > 0 and until > 0 and bool(page)


def converge() -> float:
    c = plumb.converge(MODEL, "qpos[hinge]@1")
    return float(c.dt.max() + c.values.mean() + np.nanmax(c.errors))


def snapshot_and_diff() -> int:
    s = plumb.snapshot(MODEL)
    d = plumb.diff(s, MODEL, set={"dof_damping[hinge]": 0.3})
    return len([c["path"] for c in d.changes]) + len(d.compiler)


def run() -> tuple[int, ...]:
    t = plumb.run(MODEL, until=1.0)
    column: npt.NDArray[np.float64] = t["qpos[hinge]"]
    assert t.divergence is None or "reason" in t.divergence
    return t.array.shape + t.time.shape + column.shape + (len(t.warnings), len(t.to_dict()))


def inspect() -> float:
    i = plumb.inspect(MODEL)
    names = [b["name"] for b in i.bodies] + [j["name"] for j in i.joints]
    return float(i.gravity[2]) + len(names) + len(i.units["length"]) + i.sizes["nq"]


def render() -> tuple[int, ...]:
    picture = plumb.render(MODEL, width=64, height=48, camera=0)
    frames = plumb.render(MODEL, until=0.2, width=64, height=48)
    assert isinstance(picture, np.ndarray) and isinstance(frames, plumb.Frames)
    return picture.shape + frames.array.shape + frames[0].shape + frames.times.shape


def batch() -> float:
    b = plumb.sweep(MODEL, "dof_damping[hinge]=0:1:3", "qpos[hinge]@0.5", until=0.5)
    r = plumb.rollout(MODEL, 4, randomize="dof_damping[hinge]*=U(0.9,1.1)",
                      metrics="qpos[hinge]@0.5", until=0.5)
    count: int = b.summary["count"]
    return float(b.params.sum() + b.metrics.sum() + b.index.sum() + b.diverged.sum()
                 + np.nansum(b.diverged_at) + len(b.problems) + r.column(r.columns[0]).size
                 + count)


def replay_and_identify(log: str) -> float:
    r = plumb.replay(MODEL, log)
    i = plumb.identify(MODEL, log, fit="dof_damping[hinge]")
    return float(r.fits.mean() + r.rms.sum() + r.max_abs.sum() + r.noise.sum()
                 + sum(s.size for s in r.simulated + r.times + r.logged)
                 + i.values[0] + i.nominal[0] + i.std_errors[0] + i.lo[0] + i.hi[0]
                 + i.correlation.shape[0] + i.covariance.shape[0] + i.singular_values.size
                 + i.fits_before.mean() + i.fits_after.mean())


def rehearsal(result: plumb.RehearsalResult) -> str:
    motors = [m.name for m in result.view.motors]
    return f"{result.client.kind} {result.bridge.commands} {motors} {len(rows(result))}"


def model() -> int:
    m = plumb.load(MODEL)
    wrapped = m.mjmodel
    return m.nq + (0 if wrapped is None else 1)


def notices(result: plumb.VerifyResult) -> list[str]:
    return [f"{n.level} {n.topic}: {n.text}" for n in result.notices]
