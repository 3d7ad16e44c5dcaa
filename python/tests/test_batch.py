"""plumb.rollout and plumb.sweep: the plumb.Batch they return, their store, and Ctrl-C."""

import json
import os
import signal
import sqlite3
import subprocess
import sys
import textwrap
import time

import mujoco
import numpy as np
import pytest

import plumb
from conftest import run_cli

RANDOMIZE = ["dof_damping[hinge]=*U(0.5,1.5)", "body_mass[link]=*U(0.8,1.2)"]
METRICS = ["qpos[hinge]@1", "energy_drift"]
START = ["qpos[hinge]=0.7"]
VARY = ["dof_damping[hinge]=0:0.5:5", "opt.integrator=Euler,RK4"]

# a model with an actuator (control noise) and a keyframe
ARM = """
<mujoco model="arm">
  <option timestep="0.002"/>
  <worldbody>
    <body name="link" pos="0 0 1">
      <joint name="hinge" type="hinge" axis="0 1 0" damping="0.1"/>
      <geom name="rod" type="capsule" fromto="0 0 0 0.5 0 0" size="0.04" mass="0.5"/>
    </body>
  </worldbody>
  <actuator><motor name="motor" joint="hinge" ctrlrange="-1 1"/></actuator>
  <keyframe><key name="up" qpos="1.2"/></keyframe>
</mujoco>
"""


def _rollout(model, **more):
    options = dict(randomize=RANDOMIZE, metrics=METRICS, set=START, until=1, seed=3)
    options.update(more)
    return plumb.rollout(model, 12, **options)


def _rollout_cli(*more):
    return [
        "rollout", "models/pendulum.xml", "--count", "12", "--until", "1", "--seed", "3",
        "--set", START[0], "--randomize", RANDOMIZE[0], "--randomize", RANDOMIZE[1],
        "--metric", METRICS[0], "--metric", METRICS[1], *more,
    ]


@pytest.fixture
def arm(tmp_path):
    path = tmp_path / "arm.xml"
    path.write_text(ARM)
    return str(path)


def test_rollout_equals_the_cli_json(pendulum, cli_json):
    batch = _rollout(pendulum)
    assert batch.to_dict() == cli_json(*_rollout_cli())
    assert json.loads(batch.to_json()) == batch.to_dict()
    assert len(batch) == 12 and batch.kind == "rollout"


def test_rollout_summary_is_what_the_cli_prints(pendulum):
    batch = _rollout(pendulum)
    done = run_cli(*_rollout_cli(), "--format", "json")
    # the first line holds the rate (rollouts/s), which is a timing
    ours = repr(batch).splitlines()
    theirs = done.stderr.strip().splitlines()
    assert ours[0].startswith("12 rollouts, 0 diverged (0.0%), ")
    assert ours[1:] == theirs[1:]
    assert len(ours) == 3  # one line per metric
    summary = batch.summary
    assert summary["count"] == 12 and summary["run_now"] == 12 and summary["resumed"] == 0
    drift = summary["metrics"]["energy_drift"]
    assert drift["n"] == 12 and drift["missing"] == 0
    assert drift["mean"] == pytest.approx(np.mean(batch.metrics[:, 1]), rel=1e-12)
    assert drift["min"] == np.min(batch.metrics[:, 1])
    assert drift["median"] == pytest.approx(np.median(batch.metrics[:, 1]), rel=1e-12)


def test_the_table_is_numpy_arrays(pendulum):
    batch = _rollout(pendulum)
    assert batch.parameters == ["dof_damping[hinge]", "body_mass[link]"]
    assert batch.metric_names == METRICS
    assert batch.columns == ["rollout", *batch.parameters, *METRICS, "diverged", "diverged_at",
                             "problem"]
    assert batch.index.dtype == np.int64 and list(batch.index) == list(range(12))
    assert batch.params.shape == (12, 2) and batch.metrics.shape == (12, 2)
    assert batch.diverged.dtype == np.bool_ and not batch.diverged.any()
    assert np.isnan(batch.diverged_at).all()
    assert batch.problems == [""] * 12
    # the draws are within the distributions' bounds of the nominal values (0.05, 1)
    assert ((batch.params[:, 0] >= 0.025) & (batch.params[:, 0] <= 0.075)).all()
    assert ((batch.params[:, 1] >= 0.8) & (batch.params[:, 1] <= 1.2)).all()
    rows = batch.to_dict()
    for k, row in enumerate(rows):
        assert batch.metrics[k, 0] == row["metrics"][METRICS[0]]
        assert batch.params[k, 1] == row["params"]["body_mass[link]"]
    np.testing.assert_array_equal(batch.column("energy_drift"), batch.metrics[:, 1])
    with pytest.raises(plumb.ArgumentError):
        batch.column("nothing")


def test_results_are_identical_for_any_thread_count(pendulum):
    one = _rollout(pendulum, threads=1)
    two = _rollout(pendulum, threads=2)
    every = _rollout(pendulum, threads=0)
    assert one.to_json() == two.to_json() == every.to_json()
    np.testing.assert_array_equal(one.metrics, two.metrics)
    s1 = plumb.sweep(pendulum, VARY, METRICS, set=START, threads=1)
    s2 = plumb.sweep(pendulum, VARY, METRICS, set=START, threads=2)
    assert s1.to_json() == s2.to_json()


def test_the_callers_mjmodel_is_unchanged_by_randomization(pendulum):
    model = mujoco.MjModel.from_xml_path(pendulum)
    before = {name: getattr(model, name).copy()
              for name in ("body_mass", "dof_damping", "body_inertia", "qpos0", "dof_invweight0")}
    timestep = model.opt.timestep
    batch = _rollout(model, set=START + ["opt.timestep=0.001", "dof_damping[hinge]=0.2"])
    sweep = plumb.sweep(model, VARY, METRICS, set=START + ["body_mass[link]=2"])
    # the batches did draw and vary: different masses and dampings gave different metrics
    assert len(set(batch.metrics[:, 0])) == 12
    assert len(set(sweep.metrics[:, 0])) == len(sweep)
    assert model.opt.timestep == timestep
    for name, values in before.items():
        np.testing.assert_array_equal(getattr(model, name), values, err_msg=name)
    # and an MjModel gives what its file gives
    assert _rollout(model).to_json() == _rollout(pendulum).to_json()


def test_sweep_equals_the_cli_json(pendulum, cli_json):
    batch = plumb.sweep(pendulum, VARY, METRICS, set=START)
    ours = batch.to_dict()
    theirs = cli_json("sweep", "models/pendulum.xml", "--vary", VARY[0], "--vary", VARY[1],
                      "--metric", METRICS[0], "--metric", METRICS[1], "--set", START[0])
    # the model is named by the path each was given
    assert ours.pop("model") == pendulum
    theirs.pop("model")
    assert ours == theirs
    assert len(batch) == 10 and batch.kind == "sweep"
    assert batch.parameters == ["dof_damping[hinge]", "opt.integrator"]
    assert batch.columns[:3] == ["case", *batch.parameters]
    # the first axis varies slowest; the integrator as its number (Euler 0, RK4 1)
    np.testing.assert_array_equal(batch.params[:2], [[0, 0], [0, 1]])
    assert repr(batch).startswith("10 cases, 0 diverged")


def test_sweep_until_and_a_metric_that_cannot_be_measured(pendulum, cli_json):
    # hanging still, the pendulum never crosses: no period, with the reason, as the CLI says
    batch = plumb.sweep(pendulum, "dof_damping[hinge]=0,0.1", ["period(qpos[hinge])"], until=1)
    theirs = cli_json("sweep", "models/pendulum.xml", "--vary", "dof_damping[hinge]=0,0.1",
                      "--metric", "period(qpos[hinge])", "--until", "1")
    ours = batch.to_dict()
    ours.pop("model"), theirs.pop("model")
    assert ours == theirs
    assert np.isnan(batch.metrics).all()
    assert all(batch.problems)
    assert batch.summary["metrics"]["period(qpos[hinge])"]["missing"] == 2


def test_ctrl_noise_keyframe_and_shard_as_the_cli(arm, cli_json):
    options = dict(ctrl_noise=0.5, metrics=["qpos[hinge]@0.5"], keyframe="up", until=0.5)
    batch = plumb.rollout(arm, 6, **options)
    cli = ["rollout", arm, "--count", "6", "--ctrl-noise", "0.5", "--metric", "qpos[hinge]@0.5",
           "--keyframe", "up", "--until", "0.5"]
    assert batch.to_dict() == cli_json(*cli)
    quiet = plumb.rollout(arm, 6, **dict(options, ctrl_noise=0))
    assert not np.array_equal(batch.metrics, quiet.metrics)  # the noise moved the arm
    assert len(set(quiet.metrics[:, 0])) == 1  # no noise, no draws: six equal runs
    # a keyframe given to plumb.load is the start too
    assert plumb.rollout(plumb.load(arm, keyframe="up"), 6, ctrl_noise=0.5,
                         metrics=["qpos[hinge]@0.5"], until=0.5).to_json() == batch.to_json()
    half = plumb.rollout(arm, 6, **options, shard="1/2")
    assert list(half.index) == [1, 3, 5]
    assert half.to_dict() == cli_json(*cli, "--shard", "1/2")
    assert half.to_dict() == [row for row in batch.to_dict() if row["rollout"] % 2 == 1]


def test_nan_and_counts_beyond_memory_are_refused_by_name(arm, pendulum):
    # issue 46: ctrl_noise=nan ran as no noise; count=2**63-1 raised MemoryError
    with pytest.raises(plumb.ArgumentError) as caught:
        plumb.rollout(arm, 2, ctrl_noise=float("nan"), until=0.1)
    assert caught.value.argument == "ctrl_noise"
    for count in (2**63 - 1, 10**12):
        with pytest.raises(plumb.ArgumentError, match="more than this machine's memory") as caught:
            plumb.rollout(pendulum, count, until=0.01)
        assert caught.value.argument == "count"
    with pytest.raises(plumb.ArgumentError) as caught:
        plumb.sweep(pendulum, ["qpos[hinge]=0.1,0.2"], ["maxabs(qpos[hinge])"], until=float("nan"))
    assert caught.value.argument == "until"


def test_bad_arguments_name_the_python_keyword(pendulum):
    cases = [
        (dict(randomize="dof_damping[hinge]=*U(0.9"), "randomize"),
        (dict(randomize=["dof_damping[hinge]=LogU(-1,1)"]), "randomize"),
        (dict(metrics=["qpos[hinge]@0.0001"]), "metrics"),
        (dict(metrics=["qpos[hinge]@"]), "metrics"),
        (dict(shard="2/2"), "shard"),
        (dict(threads=-1), "threads"),
        (dict(resume=True), "resume"),
        (dict(set=["qpos[hinge]=x"]), "set"),
    ]
    for options, keyword in cases:
        with pytest.raises(plumb.ArgumentError) as caught:
            plumb.rollout(pendulum, 2, **options)
        assert caught.value.argument == keyword, (options, str(caught.value))
        assert isinstance(caught.value, ValueError)
    for vary in ("dof_damping[hinge]=0:1", "dof_damping[hinge]=a,b", "dof_damping[hinge]"):
        with pytest.raises(plumb.ArgumentError) as caught:
            plumb.sweep(pendulum, vary, "qpos[hinge]@1")
        assert caught.value.argument == "vary", str(caught.value)
    with pytest.raises(plumb.ArgumentError) as caught:
        plumb.sweep(pendulum, VARY, "nothing(qpos[hinge])")
    assert caught.value.argument == "metrics"
    with pytest.raises(plumb.PathError, match="hinj"):
        plumb.rollout(pendulum, 2, randomize="dof_damping[hinj]=*U(0.9,1.1)")
    with pytest.raises(TypeError, match="randomize"):
        plumb.rollout(pendulum, 2, randomize=[1, 2])


def test_to_pandas_is_the_table(pendulum):
    batch = _rollout(pendulum)
    frame = batch.to_pandas()
    assert list(frame.columns) == batch.columns
    assert len(frame) == 12
    np.testing.assert_array_equal(frame["energy_drift"].to_numpy(), batch.metrics[:, 1])
    np.testing.assert_array_equal(frame["rollout"].to_numpy(), np.arange(12))
    assert frame["diverged"].dtype == bool


def test_repr_html_is_the_report(pendulum, tmp_path):
    batch = plumb.sweep(pendulum, VARY, METRICS, set=START)
    html = batch._repr_html_()
    assert html.lstrip().lower().startswith("<!doctype html>")
    assert html.rstrip().endswith("</html>")
    assert "dof_damping[hinge]" in html and "energy_drift" in html
    batch.save_report(tmp_path / "sweep.html")
    saved = (tmp_path / "sweep.html").read_text()
    assert saved.lstrip().lower().startswith("<!doctype html>")
    rollout_html = _rollout(pendulum)._repr_html_()
    assert "body_mass[link]" in rollout_html and rollout_html.rstrip().endswith("</html>")


def _stored(db):
    """The results table of a store: {index: (metrics, diverged)}."""
    with sqlite3.connect(f"file:{db}?mode=ro", uri=True) as store:
        return {idx: (json.loads(metrics), diverged)
                for idx, metrics, diverged in store.execute(
                    "select idx, metrics, diverged from results")}


def test_a_python_store_is_the_clis(pendulum, tmp_path, cli_json):
    whole = _rollout(pendulum)
    # the even rollouts from Python; the CLI's --resume runs only the rest
    db = str(tmp_path / "r.sqlite")
    half = _rollout(pendulum, shard="0/2", db=db)
    assert half.db == db and len(half) == 6
    with pytest.raises(plumb.ArgumentError) as caught:
        _rollout(pendulum, shard="0/2", db=db)  # stored already: resume=True to go on
    assert caught.value.argument == "db"
    rest = cli_json(*_rollout_cli("--db", db, "--resume"))
    assert [row["rollout"] for row in rest] == [1, 3, 5, 7, 9, 11]
    assert sorted(half.to_dict() + rest, key=lambda r: r["rollout"]) == whole.to_dict()
    # plumb results reads it: one finished run with every row
    runs = cli_json("results", db)
    assert len(runs) == 1 and runs[0]["finished"]
    assert [row["metrics"] for row in runs[0]["rollouts"]] == [
        row["metrics"] for row in whole.to_dict()]

    # and the other way: the CLI's odd rollouts, then Python resumes the whole batch
    db2 = str(tmp_path / "c.sqlite")
    cli_json(*_rollout_cli("--db", db2, "--shard", "1/2"))
    resumed = _rollout(pendulum, db=db2, resume=True)
    assert resumed.to_json() == whole.to_json()
    assert resumed.summary["resumed"] == 6 and resumed.summary["run_now"] == 6
    assert "(6 stored before it resumed, 6 run now)" in repr(resumed)
    assert len(_stored(db2)) == 12


def test_shards_stored_from_python_merge_into_the_whole_batch(pendulum, tmp_path, cli_json):
    shards = [str(tmp_path / f"shard{i}.sqlite") for i in range(2)]
    for i, db in enumerate(shards):
        assert len(_rollout(pendulum, shard=f"{i}/2", db=db)) == 6
    merged = str(tmp_path / "all.sqlite")
    run_cli("merge", *shards, "-o", merged, check_codes=(0,))
    runs = cli_json("results", merged)
    assert len(runs) == 1 and runs[0]["finished"]
    whole = _rollout(pendulum).to_dict()
    assert [(r["rollout"], r["params"], r["metrics"]) for r in runs[0]["rollouts"]] == [
        (r["rollout"], r["params"], r["metrics"]) for r in whole]
    # and resuming the merged store finds the batch complete
    again = _rollout(pendulum, db=merged, resume=True)
    assert again.summary["resumed"] == 12 and again.summary["run_now"] == 0
    assert again.to_json() == _rollout(pendulum).to_json()


def test_a_stored_sweep_resumes_from_the_cli(pendulum, tmp_path, cli_json):
    db = str(tmp_path / "s.sqlite")
    cli_args = ["sweep", "models/pendulum.xml", "--vary", VARY[0], "--vary", VARY[1],
                "--metric", METRICS[0], "--set", START[0], "--db", db]
    whole = cli_json(*cli_args)
    again = plumb.sweep(pendulum, VARY, METRICS[0], set=START, db=db, resume=True)
    assert again.summary["resumed"] == 10 and again.summary["run_now"] == 0
    ours = again.to_dict()
    ours.pop("model"), whole.pop("model")
    assert ours == whole


LONG_ROLLOUT = """
import sys, time, plumb
try:
    plumb.rollout(sys.argv[1], 8000, randomize="dof_damping[hinge]=*U(0.5,1.5)",
                  metrics="qpos[hinge]@1", set="qpos[hinge]=0.7", until=1, threads=2,
                  db=sys.argv[2])
    print("finished")
except KeyboardInterrupt as e:
    print("interrupted", time.monotonic(), flush=True)
    print(e, flush=True)
"""


def test_ctrl_c_keeps_the_finished_rollouts_and_resume_completes_them(pendulum, tmp_path):
    db = str(tmp_path / "r.sqlite")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    child = subprocess.Popen([sys.executable, "-c", textwrap.dedent(LONG_ROLLOUT), pendulum, db],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    try:
        # wait until the store holds some committed rows, then Ctrl-C
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and child.poll() is None:
            try:
                if len(_stored(db)) >= 200:
                    break
            except sqlite3.Error:
                pass  # not made yet
            time.sleep(0.05)
        assert child.poll() is None, child.communicate()
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=30)
    finally:
        child.kill()
    lines = out.splitlines()
    words = lines[0].split() if lines else []
    assert words[:1] == ["interrupted"], (out, err)
    # KeyboardInterrupt reached Python promptly (RunLong polls every 20 ms; the running
    # rollouts stop at their next step, those not started are skipped)
    assert float(words[1]) - sent < 0.1
    stored = _stored(db)
    assert 200 <= len(stored) < 8000
    # it says what the CLI says: how many finished, that they are stored, and how to go on
    assert lines[1] == (f"interrupted after {len(stored)} rollouts; {len(stored)} rollouts "
                        f"finished and stored in '{db}': call it again with resume=True to go on")
    # the rows kept are every one that finished (also past the first unfinished one), each
    # as an uninterrupted run makes it
    indices = sorted(stored)
    options = dict(randomize="dof_damping[hinge]=*U(0.5,1.5)", metrics="qpos[hinge]@1",
                   set="qpos[hinge]=0.7", until=1)
    sample = plumb.rollout(pendulum, indices[-1] + 1, **options)
    for k in (indices[0], indices[len(indices) // 2], indices[-1]):
        assert stored[k][0] == [sample.metrics[k, 0]]
    # resume=True completes the run: every row as the uninterrupted run, the stored ones kept
    resumed = plumb.rollout(pendulum, 8000, **options, threads=2, db=db, resume=True)
    assert resumed.summary["resumed"] == len(indices)
    assert resumed.summary["run_now"] == 8000 - len(indices)
    assert resumed.to_json() == plumb.rollout(pendulum, 8000, **options).to_json()
    assert len(_stored(db)) == 8000


def test_a_resumed_batch_says_what_it_found_as_batch_warnings(pendulum, tmp_path):
    db = str(tmp_path / "r.sqlite")
    # the first attempt of a resumable job starts the run, and says so
    with pytest.warns(plumb.BatchWarning) as first:
        _rollout(pendulum, shard="0/2", db=db, resume=True)
    assert [str(w.message) for w in first] == [
        f"note: resume=True: '{db}' holds no rollout run yet; starting one"]
    # the next one says how many are stored and runs the rest (as the CLI's --resume does)
    with pytest.warns(plumb.BatchWarning) as again:
        batch = _rollout(pendulum, db=db, resume=True)
    assert [str(w.message) for w in again] == [
        f"note: resume=True: 6 of 12 rollouts are stored in '{db}'; running the rest"]
    assert batch.summary["resumed"] == 6 and batch.summary["run_now"] == 6
    # and keeps it
    assert [(n.level, n.topic, n.subject) for n in batch.notices] == [
        ("note", "batch", "resume=True")]
    assert batch.notices[0].text == f"6 of 12 rollouts are stored in '{db}'; running the rest"


def test_a_sweep_says_what_it_could_not_measure_as_batch_warnings(pendulum):
    # from rest the pendulum never swings: no period in any case
    with pytest.warns(plumb.BatchWarning) as said:
        batch = plumb.sweep(pendulum, "dof_damping[hinge]=0,0.1", "period(qpos[hinge])")
    messages = [str(w.message) for w in said]
    assert messages[0].startswith("warning: case 0, period(qpos[hinge]): "), messages
    assert "warning: 2 of 2 measurements could not be made (see above)" in messages
    assert np.isnan(batch.metrics).all()


def test_a_sweep_over_a_parameter_with_no_effect_says_so(pendulum):
    humanoid = "/usr/share/mujoco/model/humanoid/humanoid.xml"
    if not os.path.exists(humanoid):
        pytest.skip(f"{humanoid} is not installed")
    # MuJoCo takes the larger friction of two geoms: the floor's, lowered, changes nothing
    batch = plumb.sweep(humanoid, "geom_friction[floor][0]=0.1,0.5", "xpos[torso][2]@0.5")
    assert len(batch.notes) == 1
    assert batch.notes[0].startswith("vary 'geom_friction[floor][0]=0.1,0.5' changed no metric")
    assert "larger friction of its two geoms" in batch.notes[0]
    assert "note: vary 'geom_friction" in repr(batch)
    assert plumb.sweep(pendulum, VARY, METRICS, set=START).notes == []


# A box on a floor, the box of geom priority 1: its friction decides their contact.
PRIORITY_BOX = """<mujoco><worldbody><geom name="floor" type="plane" size="1 1 0.1"/>
  <body name="box" pos="0 0 0.1"><freejoint/><geom name="box" type="box" size="0.1 0.1 0.1" priority="1"/>
  </body></worldbody></mujoco>"""


def test_a_rollout_over_a_parameter_with_no_effect_says_so_with_geom_priority(tmp_path):
    # the floor's friction has no say under a box of higher priority (issue 49): the note
    # plumb rollout prints, its reason the one sweep gives
    model = tmp_path / "box.xml"
    model.write_text(PRIORITY_BOX)
    with pytest.warns(plumb.BatchWarning) as said:
        batch = plumb.rollout(str(model), count=3, randomize="geom_friction[floor][0]=U(0.1,0.5)",
                              metrics="xpos[box][2]@0.2", until=0.2)
    assert len(batch.notes) == 1
    assert batch.notes[0].startswith(
        "randomize 'geom_friction[floor][0]=U(0.1,0.5)' changed no metric: all 3 measured "
        "rollouts gave bit-identical results. Geom 'floor' (priority 0) meets geoms of higher "
        "priority (priority 1: 'box')"), batch.notes[0]
    assert f"note: {batch.notes[0]}" in [str(w.message) for w in said]
    swept = plumb.sweep(str(model), "geom_friction[floor][0]=0.1,0.5", "xpos[box][2]@0.2",
                        until=0.2)
    assert "Geom 'floor' (priority 0) meets geoms of higher priority" in swept.notes[0]


def test_diverged_rollouts_are_rows_with_their_time_and_reason(pendulum, cli_json):
    # negative damping pumps energy in until MuJoCo's state check fires
    options = ["--count", "6", "--randomize", "dof_damping[hinge]=U(-20,-10)",
               "--metric", "qpos[hinge]@1", "--set", START[0], "--until", "1"]
    batch = plumb.rollout(pendulum, 6, randomize="dof_damping[hinge]=U(-20,-10)",
                          metrics="qpos[hinge]@1", set=START, until=1)
    assert batch.to_dict() == cli_json("rollout", "models/pendulum.xml", *options)
    assert batch.diverged.all()
    assert ((batch.diverged_at > 0) & (batch.diverged_at < 1)).all()
    assert all("diverged" in problem for problem in batch.problems)
    assert np.isnan(batch.metrics).all()
    assert batch.summary["diverged"] == 6
    assert repr(batch).startswith("6 rollouts, 6 diverged (100.0%)")


def test_pose_and_qpos_start_the_cases_as_the_cli_does(arm, tmp_path, cli_json):
    pose = tmp_path / "pose.txt"
    pose.write_text("qpos[hinge]=1.2\n")
    common = ["--count", "4", "--randomize", "dof_damping[hinge]=*U(0.5,1.5)",
              "--metric", "qpos[hinge]@0.5", "--until", "0.5"]
    options = dict(randomize="dof_damping[hinge]=*U(0.5,1.5)", metrics="qpos[hinge]@0.5",
                   until=0.5)
    from_file = plumb.rollout(arm, 4, pose=pose, **options)
    assert from_file.to_dict() == cli_json("rollout", arm, *common, "--pose", str(pose))
    from_qpos = plumb.rollout(arm, 4, qpos=[1.2], **options)
    assert from_qpos.to_dict() == cli_json("rollout", arm, *common, "--qpos", "1.2")
    assert from_qpos.to_json() == from_file.to_json() == plumb.rollout(
        arm, 4, keyframe="up", **options).to_json()
    sweep = plumb.sweep(arm, "dof_damping[hinge]=0,1", "qpos[hinge]@0.5", qpos="1.2")
    theirs = cli_json("sweep", arm, "--vary", "dof_damping[hinge]=0,1",
                      "--metric", "qpos[hinge]@0.5", "--qpos", "1.2")
    ours = sweep.to_dict()
    ours.pop("model"), theirs.pop("model")
    assert ours == theirs
    # the config line holds the qpos as its value: the CLI's --resume continues a Python batch
    db = str(tmp_path / "q.sqlite")
    plumb.rollout(arm, 4, qpos=[1.2], shard="0/2", db=db, **options)
    rest = cli_json("rollout", arm, *common, "--qpos", "1.2", "--db", db, "--resume")
    assert [row["rollout"] for row in rest] == [1, 3]
    with pytest.raises(plumb.ArgumentError) as caught:
        plumb.rollout(arm, 2, qpos=[1.0, 2.0])
    assert caught.value.argument == "qpos"
