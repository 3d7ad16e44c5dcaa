"""plumb.replay's overall fit is honest about a nearly flat signal (issue 49): the mean of the
signals' fits let one signal whose spread is its noise sink an exact model below 70 %, and a
`.fit > 99` test failed a correct fit."""

import mujoco
import numpy as np

import plumb

FLAT = """<mujoco><option timestep="0.002"/><worldbody>
  <body name="link" pos="0 0 1.5"><joint name="hinge" axis="0 1 0" damping="0.05"/>
    <geom type="capsule" fromto="0 0 0 0 0 -1" size="0.05" mass="1"/>
    <site name="pivot" pos="0 0 -0.002"/></body></worldbody>
  <sensor><framepos name="pivot" objtype="site" objname="pivot"/></sensor></mujoco>"""


def test_a_nearly_flat_signal_does_not_sink_an_exact_model(tmp_path):
    path = tmp_path / "flat.xml"
    path.write_text(FLAT)
    # the robot: damping 0.2, from 0.7 rad; its pivot sensor 2 mm off the axis with 1 cm noise
    m = mujoco.MjModel.from_xml_path(str(path))
    m.dof_damping[0] = 0.2
    d = mujoco.MjData(m)
    d.qpos[0] = 0.7
    mujoco.mj_forward(m, d)
    rng = np.random.default_rng(1)
    rows = []
    for _ in range(1501):
        rows.append([d.time, d.qpos[0], d.qvel[0], d.sensordata[0]])
        mujoco.mj_step(m, d)
    log = np.array(rows)
    log[:, 1:] += rng.normal(size=(len(rows), 3)) * [1e-3, 1e-3, 1e-2]
    csv = tmp_path / "log.csv"
    np.savetxt(csv, log, delimiter=",", comments="", fmt="%.17g",
               header="time,qpos[hinge],qvel[hinge],sensordata[pivot][0]")
    exact = plumb.replay(str(path), str(csv), set="dof_damping[hinge]=0.2")
    assert exact.fits[2] < 10  # the flat signal's own fit: its spread is its noise
    assert np.mean(exact.fits) < 75  # what the mean made of an exact model
    assert exact.fit > 99
    assert (exact.fits_beyond_noise > 90).all()
    wrong = plumb.replay(str(path), str(csv))  # the nominal damping, 0.05
    assert wrong.fit < 70
