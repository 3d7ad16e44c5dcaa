"""The peer side of bench/rollout_peer.sh: MuJoCo's own mujoco.rollout (C++ threads under
Python) on COUNT rollouts of NSTEP steps from the model's reset state with zero controls.
Prints one JSON object: the median wall time of the rollout call over REPEAT runs, steps/s,
and the norm of each rollout's final (qpos, qvel, act), which plumb's state@T metric reports.
Run only inside the throw-away virtual environment bench/rollout_peer.sh makes."""

import json
import statistics
import sys
import time

import mujoco
import numpy as np
from mujoco import rollout


def main():
    path, count, nstep, threads, repeat = sys.argv[1], *map(int, sys.argv[2:6])
    model = mujoco.MjModel.from_xml_path(path)
    data = mujoco.MjData(model)
    mujoco.mj_resetData(model, data)
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    state0 = np.empty(mujoco.mj_stateSize(model, spec))
    mujoco.mj_getState(model, data, state0, spec)
    initial = np.tile(state0, (count, 1))
    control = np.zeros((count, nstep, model.nu))
    datas = [mujoco.MjData(model) for _ in range(threads)]
    times, state = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        state, _ = rollout.rollout(model, datas, initial, control, nstep=nstep)
        times.append(time.perf_counter() - start)
    final = state[:, -1, 1:1 + model.nq + model.nv + model.na]  # after time
    seconds = statistics.median(times)
    print(json.dumps({
        "mujoco": mujoco.mj_versionString(),
        "seconds": seconds,
        "steps_per_s": count * nstep / seconds,
        "norms": [float(np.linalg.norm(row)) for row in final],
    }))


if __name__ == "__main__":
    main()
