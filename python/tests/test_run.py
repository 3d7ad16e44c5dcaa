"""plumb.run and plumb.inspect: the samples in one numpy array, the CLI's outputs."""

import json

import mujoco
import numpy as np
import pytest

import plumb


def test_samples_equal_the_cli_jsonl(pendulum):
    from conftest import run_cli

    t = plumb.run(pendulum, until=0.5, set={"qpos[hinge]": 0.7})
    assert t.columns == ["time", "qpos[hinge]", "qvel[hinge]"]
    assert t.array.shape == (6, 3) and t.array.dtype == np.float64
    lines = run_cli("run", "models/pendulum.xml", "--set", "qpos[hinge]=0.7", "--until", "0.5",
                    "--format", "jsonl").stdout
    theirs = [json.loads(line) for line in lines.splitlines()]
    assert len(t.to_dict()) == len(theirs)
    # the array holds the same numbers, bit for bit; the time is MjData.time (issue 49), which
    # the CLI prints on its nominal grid (0.1 for 0.10000000000000007)
    for row, record, mine in zip(t.array, theirs, t.to_dict()):
        assert list(row[1:]) == [record[c] for c in t.columns[1:]]
        assert row[0] == pytest.approx(record["time"], abs=1e-12) and mine["time"] == row[0]


def test_time_is_mjdata_time(pendulum):
    # issue 49: Trajectory.time was the nominal grid (0.1), not what MjData.time reads after
    # the same steps (0.10000000000000007)
    t = plumb.run(pendulum, until=0.3, every=0.1)
    model = mujoco.MjModel.from_xml_path(pendulum)
    data = mujoco.MjData(model)
    times = [data.time]
    for _ in range(3):
        for _ in range(round(0.1 / model.opt.timestep)):
            mujoco.mj_step(model, data)
        times.append(data.time)
    assert t.time.tolist() == times
    assert t.time[1] != 0.1  # 0.10000000000000007: the clock as MuJoCo adds it up


def test_columns_every_and_views(pendulum):
    t = plumb.run(pendulum, until=1, every=0.25, columns="time,xpos[link][2]",
                  set={"qpos[hinge]": 0.7})
    assert t.columns == ["time", "xpos[link][2]"]
    np.testing.assert_allclose(t.time, [0, 0.25, 0.5, 0.75, 1.0])
    assert len(t) == 5
    # a column is a view of the one array, not a copy
    assert np.shares_memory(t["xpos[link][2]"], t.array)
    # the rod hangs from 1.5 m: its centre starts above the lowest point
    assert t["xpos[link][2]"][0] == pytest.approx(1.5)
    t2 = plumb.run(pendulum, until=0.2, columns=["qpos[*]", "qvel[hinge]"])
    assert t2.columns == ["qpos[hinge]", "qvel[hinge]"]


def test_the_callers_model_is_unchanged(pendulum):
    model = mujoco.MjModel.from_xml_path(pendulum)
    damping = model.dof_damping.copy()
    t = plumb.run(model, until=2, set={"dof_damping[hinge]": 2.0, "qpos[hinge]": 0.7})
    np.testing.assert_array_equal(model.dof_damping, damping)
    light = plumb.run(model, until=2, set={"qpos[hinge]": 0.7})
    # the heavy damping did act in the run: the swing decays far faster
    assert abs(t["qvel[hinge]"]).max() < abs(light["qvel[hinge]"]).max()


def test_errors_name_the_keyword(pendulum):
    with pytest.raises(plumb.ArgumentError) as caught:
        plumb.run(pendulum, until=1, every=0.0015)
    assert caught.value.argument == "every"
    with pytest.raises(plumb.ArgumentError) as caught:
        plumb.run(pendulum, until=-1)
    assert caught.value.argument == "until"
    with pytest.raises(plumb.PathError, match="columns: .*hinj"):
        plumb.run(pendulum, until=1, columns="qpos[hinj]")
    with pytest.raises(plumb.ArgumentError) as caught:
        plumb.run(pendulum, until=1, qpos=[0.1, 0.2])
    assert caught.value.argument == "qpos"


def test_samples_beyond_memory_are_refused_before_the_run(pendulum):
    # issue 46: the samples' buffer is sized from until: a huge one raised MemoryError
    with pytest.raises(plumb.ArgumentError, match="more than this machine's memory") as caught:
        plumb.run(pendulum, until=1e12, every=0.002)
    assert caught.value.argument == "until"


def test_divergence_keeps_the_samples_before_it(pendulum):
    t = plumb.run(pendulum, until=1, every=0.002,
                  set={"opt.timestep": 0.002, "qvel[hinge]": 1e12})
    assert t.diverged
    assert "diverged" in t.divergence["reason"]
    assert len(t) < 501 and t.array.shape[0] == len(t)


def test_to_pandas_repr_and_html(pendulum):
    t = plumb.run(pendulum, until=0.3, set={"qpos[hinge]": 0.7})
    frame = t.to_pandas()
    assert list(frame.columns) == t.columns
    np.testing.assert_array_equal(frame["qpos[hinge]"].to_numpy(), t["qpos[hinge]"])
    text = repr(t)
    assert "qpos[hinge]" in text.splitlines()[0] and "0.65403" in text
    html = t._repr_html_()
    assert html.lstrip().lower().startswith("<!doctype html>") and html.rstrip().endswith("</html>")
    assert "qvel[hinge]" in html
    # a long run's table shows its head and tail, and says how many rows there are
    long = repr(plumb.run(pendulum, until=100, set={"qpos[hinge]": 0.7}))
    lines = long.splitlines()
    assert len(lines) == 1 + 20 + 1 + 5
    assert "1001 rows in all" in lines[21]
    assert lines[-1].split()[0] == "100.00000"


def test_inspect_equals_the_cli_json(pendulum, cli_json):
    d = plumb.inspect(pendulum, set={"body_mass[link]": 2})
    ours, theirs = d.to_dict(), cli_json("inspect", "models/pendulum.xml", "--set",
                                         "body_mass[link]=2")
    ours.pop("model"), theirs.pop("model")
    assert ours == theirs
    assert d.sizes["nq"] == 1 and d.total_mass == pytest.approx(2)
    assert d.joints[0]["name"] == "hinge" and d.timestep == 0.002
    assert list(d.to_pandas("bodies")["name"]) == ["world", "link"]
    with pytest.raises(plumb.ArgumentError) as caught:
        d.to_pandas("bodys")
    assert caught.value.argument == "table"


def test_inspect_repr_is_the_cli_table_and_html_a_page(pendulum, root, monkeypatch):
    from conftest import run_cli

    monkeypatch.chdir(root)  # the table names the model as given: the same relative path

    model = mujoco.MjModel.from_xml_path(pendulum)
    d = plumb.inspect(model, set={"body_mass[link]": 3})
    assert model.body_mass[1] == pytest.approx(1)  # the caller's model is unchanged
    table = run_cli("inspect", "models/pendulum.xml").stdout
    mine = repr(plumb.inspect("models/pendulum.xml"))
    assert mine == table
    html = d._repr_html_()
    assert html.lstrip().lower().startswith("<!doctype html>") and "</html>" in html
    assert "hinge" in html and "Bodies" in html


def test_results_keep_a_wrapped_mjmodel_alive(pendulum):
    import gc

    model = mujoco.MjModel.from_xml_path(pendulum)
    t = plumb.run(model, until=0.2, set={"qpos[hinge]": 0.7})
    d = plumb.inspect(model)
    del model
    gc.collect()
    assert "qpos[hinge]" in t._repr_html_()
    assert "hinge" in d._repr_html_()


def test_ctrl_c_stops_a_long_run(pendulum):
    import os
    import signal
    import threading
    import time

    timer = threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    began = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        plumb.run(pendulum, until=1e6, every=1000)  # 5e8 steps: minutes, unless stopped
    timer.join()
    assert time.monotonic() - began < 5
