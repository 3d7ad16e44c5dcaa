"""An output onto one of the call's inputs (issue 46): refused with plumb.ArgumentError naming
the output's keyword, before anything is written, under every name that reaches the input."""

import os
import shutil

import numpy as np
import pytest

import plumb


@pytest.fixture
def model(pendulum, tmp_path):
    """A copy of the pendulum the test may lose, and the names that reach it."""
    path = tmp_path / "p.xml"
    shutil.copy(pendulum, path)
    os.symlink("p.xml", tmp_path / "link.xml")
    os.link(path, tmp_path / "hard.xml")
    return path


def _names(path):
    """The input as given, relative with ./, through a symbolic and a hard link."""
    folder = path.parent
    return [path, str(path), f"./{path.name}", folder / "link.xml", folder / "hard.xml"]


def _refused(call, argument, path):
    before = path.read_bytes()
    listing = sorted(os.listdir(path.parent))
    with pytest.raises(plumb.ArgumentError) as caught:
        call()
    assert caught.value.argument == argument
    assert "is the same file" in caught.value.problem
    assert "the output would destroy its input; write it elsewhere." in str(caught.value)
    assert path.read_bytes() == before
    assert sorted(os.listdir(path.parent)) == listing
    return caught.value


def test_a_store_onto_the_model_is_refused(model):
    for name in _names(model):
        e = _refused(lambda: plumb.rollout(model, 2, metrics="qpos[hinge]@0.1", until=0.1,
                                           db=name), "db", model)
        assert f"the model '{model}'" in e.problem
        _refused(lambda: plumb.sweep(model, "dof_damping[hinge]=0.1,0.2", "qpos[hinge]@0.1",
                                     db=name), "db", model)


def test_a_store_onto_the_pose_file_is_refused(pendulum, tmp_path):
    pose = tmp_path / "pose.txt"
    pose.write_text("qpos[hinge] = 0.7\n")
    e = _refused(lambda: plumb.rollout(pendulum, 2, metrics="qpos[hinge]@0.1", until=0.1,
                                       pose=pose, db=pose), "db", pose)
    assert "the pose file" in e.problem


def test_a_picture_or_a_repro_folder_onto_the_model_is_refused(model):
    for name in _names(model):
        _refused(lambda: plumb.render(model, output=name), "output", model)
        _refused(lambda: plumb.audit(model, repro=name), "repro", model)


def test_a_repro_folder_onto_the_accept_list_is_refused(pendulum, tmp_path):
    accept = tmp_path / "accept.toml"
    accept.write_text("# reviewed\n")
    e = _refused(lambda: plumb.audit(pendulum, accept=accept, repro=accept), "repro", accept)
    assert "the accept list" in e.problem


def test_a_report_onto_the_model_is_refused(model):
    result = plumb.verify(model)
    for name in _names(model):
        _refused(lambda: result.save_report(name), "path", model)
    result.save_report(model.parent / "report.html")  # beside it: written
    assert (model.parent / "report.html").read_text().lstrip().lower().startswith("<!doctype")


def test_a_fitted_model_onto_the_model_or_a_log_is_refused(model, tmp_path):
    t = plumb.run(model, until=1, every=0.01, set={"qpos[hinge]": 0.7})
    log = tmp_path / "log.csv"
    np.savetxt(log, t.array, delimiter=",", header=",".join(t.columns), comments="",
               fmt="%.17g")
    r = plumb.identify(model, log, fit="dof_damping[hinge]")
    for name in _names(model):
        _refused(lambda: r.save_model(name), "path", model)
    e = _refused(lambda: r.save_model(log), "path", log)
    assert "the log" in e.problem
    _refused(lambda: r.save_report(log), "path", log)
    _refused(lambda: plumb.replay(model, log).save_report(log), "path", log)
    r.save_model(tmp_path / "fitted.xml")  # a new file: written
    assert plumb.load(tmp_path / "fitted.xml").nq == 1
