"""plumb.rollout from Python, one batch at a time, for bench/python_rollout.sh.

    python_rollout.py import                                   imports only (the baseline)
    python_rollout.py plumb   MODEL COUNT NSTEP THREADS        one plumb.rollout batch
    python_rollout.py draws   MODEL COUNT NSTEP OUT.npy        the batch's initial states
    python_rollout.py mujoco  MODEL COUNT NSTEP THREADS IN.npy one mujoco.rollout batch
    python_rollout.py compare MODEL COUNT NSTEP THREADS REPEAT both, alternating: steps/s

The worlds are the same on both sides: the model as loaded, COUNT initial states that are the
reset state with every qvel drawn from U(-0.5, 0.5) (plumb draws them, keyed by rollout and
dof; mujoco.rollout is given plumb's draws as full physics states), zero controls, NSTEP steps,
THREADS threads. Every mode imports the same modules (mujoco, numpy, plumb), so the import
baseline is the same for all.
"""

import sys
import time

import mujoco
import numpy as np
from mujoco import rollout as mj_rollout

import plumb

RANDOMIZE = "qvel[*]=U(-0.5,0.5)"


def plumb_batch(path, count, nstep, threads, metric=True):
    model = mujoco.MjModel.from_xml_path(path)
    until = nstep * model.opt.timestep
    metrics = [f"state@{until!r}"] if metric else None
    return plumb.rollout(model, count, randomize=RANDOMIZE, metrics=metrics, until=until,
                         threads=threads)


def initial_states(model, batch):
    """plumb's draws as mujoco.rollout's initial full physics states (one row a rollout)."""
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    data = mujoco.MjData(model)
    states = np.empty((len(batch), mujoco.mj_stateSize(model, spec)))
    # one draw per dof, in dof order (qvel[root][0..5], qvel[abdomen_z], ...)
    assert len(batch.parameters) == model.nv, batch.parameters
    for k, qvel in enumerate(batch.params):
        mujoco.mj_resetData(model, data)
        data.qvel[:] = qvel
        mujoco.mj_getState(model, data, states[k], spec)
    return states


def mujoco_batch(path, nstep, threads, states):
    model = mujoco.MjModel.from_xml_path(path)
    datas = [mujoco.MjData(model) for _ in range(threads)]
    control = np.zeros((1, 1, model.nu))
    with mj_rollout.Rollout(nthread=threads) as pool:
        state, _ = pool.rollout(model, datas, states, control, nstep=nstep)
    return state


def final_norms(model, state):
    """The norm of qpos, qvel and act after the last step (plumb's state@T metric)."""
    end = state[:, -1, 1:1 + model.nq + model.nv + model.na]  # time comes first
    return np.linalg.norm(end, axis=1)


def main(argv):
    mode = argv[1]
    if mode == "import":
        return
    path, count, nstep = argv[2], int(argv[3]), int(argv[4])
    if mode == "plumb":
        plumb_batch(path, count, nstep, int(argv[5]))
    elif mode == "draws":
        model = mujoco.MjModel.from_xml_path(path)
        np.save(argv[5], initial_states(model, plumb_batch(path, count, 1, 1, metric=False)))
    elif mode == "mujoco":
        mujoco_batch(path, nstep, int(argv[5]), np.load(argv[6]))
    elif mode == "compare":
        threads, repeat = int(argv[5]), int(argv[6])
        model = mujoco.MjModel.from_xml_path(path)
        states = initial_states(model, plumb_batch(path, count, 1, 1, metric=False))
        steps = count * nstep
        rates = {"plumb": [], "mujoco": []}
        for _ in range(repeat):
            start = time.perf_counter()
            ours = plumb_batch(path, count, nstep, threads)
            rates["plumb"].append(steps / (time.perf_counter() - start))
            start = time.perf_counter()
            theirs = mujoco_batch(path, nstep, threads, states)
            rates["mujoco"].append(steps / (time.perf_counter() - start))
        difference = np.max(np.abs(ours.metrics[:, 0] - final_norms(model, theirs))
                            / np.abs(final_norms(model, theirs)))
        best = {name: max(values) for name, values in rates.items()}
        median = {name: float(np.median(values)) for name, values in rates.items()}
        print(f"{threads} {count}x{nstep} plumb {median['plumb']:.0f} mujoco "
              f"{median['mujoco']:.0f} ratio {median['plumb'] / median['mujoco']:.3f} "
              f"best {best['plumb']:.0f} {best['mujoco']:.0f} "
              f"ratio {best['plumb'] / best['mujoco']:.3f} max_rel_diff {difference:.2g}")
    else:
        sys.exit(f"unknown mode {mode}")


if __name__ == "__main__":
    main(sys.argv)
