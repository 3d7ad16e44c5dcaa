"""plumb.verify and the results every check shares."""

import mujoco
import numpy as np
import pytest

import plumb


def test_pendulum_from_mjmodel_gives_fifteen_passing_rows(pendulum):
    model = mujoco.MjModel.from_xml_path(pendulum)
    result = plumb.verify(model, set={"qpos[hinge]": 0.7})
    assert result.ok
    assert len(result.rows) == 15
    assert all(row.status == "PASS" for row in result.rows)
    assert result.count("PASS") == 15
    ids = [row.id for row in result.rows]
    assert "convergence" in ids and "energy" in ids


def test_equals_the_cli_json(pendulum, cli_json):
    ours = plumb.verify(pendulum, set={"qpos[hinge]": 0.7}).to_dict()
    theirs = cli_json("verify", "models/pendulum.xml", "--set", "qpos[hinge]=0.7")
    # the model is named by the path each was given
    ours.pop("model"), theirs.pop("model")
    assert ours == theirs


def test_rows_are_typed(pendulum):
    result = plumb.verify(pendulum, set={"qpos[hinge]": 0.7})
    row = next(r for r in result.rows if r.id == "convergence")
    assert isinstance(row.measured, float)
    assert row.status in ("PASS", "WARN", "FAIL", "SKIP")
    frame = result.to_pandas()
    assert list(frame["id"]) == [r.id for r in result.rows]


def test_repr_html_is_the_report(pendulum):
    result = plumb.verify(pendulum, set={"qpos[hinge]": 0.7})
    html = result._repr_html_()
    assert html.lstrip().lower().startswith("<!doctype html>")
    assert "analytic" in html and "</html>" in html


def test_the_callers_model_is_unchanged_by_set(pendulum):
    model = mujoco.MjModel.from_xml_path(pendulum)
    before = (model.opt.timestep, model.dof_damping.copy(), model.body_mass.copy())
    result = plumb.verify(model, set={"dof_damping[hinge]": 0.3, "opt.timestep": 0.001})
    assert result.rows
    assert model.opt.timestep == before[0]
    np.testing.assert_array_equal(model.dof_damping, before[1])
    np.testing.assert_array_equal(model.body_mass, before[2])


def test_bad_set_raises_the_library_error(pendulum):
    with pytest.raises(plumb.PathError, match="hinj"):
        plumb.verify(pendulum, set={"qpos[hinj]": 0.7})
    with pytest.raises(plumb.ArgumentError) as caught:
        plumb.verify(pendulum, set=["qpos[hinge]=x"])
    assert caught.value.argument == "set"
    assert isinstance(caught.value, ValueError)


def test_missing_file_is_a_load_error(tmp_path):
    with pytest.raises(plumb.LoadError, match="nothing.xml"):
        plumb.verify(str(tmp_path / "nothing.xml"))
