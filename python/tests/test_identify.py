"""plumb.replay and plumb.identify on a log of the pendulum made with a known damping."""

import mujoco
import numpy as np
import pytest

import plumb

TRUE_DAMPING = 0.2


@pytest.fixture
def log(pendulum, tmp_path):
    """3 s of the pendulum let go at 0.7 rad with damping 0.2, with 1 mrad(/s) of noise."""
    t = plumb.run(pendulum, until=3, every=0.01,
                  set={"qpos[hinge]": 0.7, "dof_damping[hinge]": TRUE_DAMPING})
    samples = t.array.copy()
    samples[:, 1:] += np.random.default_rng(7).normal(0, 1e-3, samples[:, 1:].shape)
    path = tmp_path / "decay.csv"
    np.savetxt(path, samples, delimiter=",", header=",".join(t.columns), comments="",
               fmt="%.17g")
    return path


def test_replay_equals_the_cli_json(pendulum, log, cli_json):
    r = plumb.replay(pendulum, log)
    ours, theirs = r.to_dict(), cli_json("replay", "models/pendulum.xml", "--log", str(log))
    ours.pop("model"), theirs.pop("model")
    assert ours == theirs
    assert r.columns == ["qpos[hinge]", "qvel[hinge]"]
    # the nominal damping (0.05) is not the log's: a poor fit
    assert r.fit < 90 and r.fits.shape == (2,)
    # with the true damping, the replay fits to the noise
    right = plumb.replay(pendulum, log, set={"dof_damping[hinge]": TRUE_DAMPING})
    assert right.fit > 99
    assert right.rms.max() < 3e-3
    assert len(right.simulated) == 2 and right.simulated[0].shape == (301,)
    np.testing.assert_allclose(right.times[0], np.arange(301) * 0.01, atol=1e-12)
    # the simulated and logged values differ by the noise alone (1e-3)
    error = right.simulated[0] - right.logged[0]
    assert 5e-4 < error.std() < 2e-3


def test_replay_table_pandas_and_report(root, log, monkeypatch):
    from conftest import run_cli

    monkeypatch.chdir(root)  # the table names the model as given: the same relative path
    r = plumb.replay("models/pendulum.xml", log, window=0.5)
    table = run_cli("replay", "models/pendulum.xml", "--log", str(log), "--window", "0.5").stdout
    assert repr(r) == table
    assert list(r.to_pandas()["column"]) == r.columns
    html = r._repr_html_()
    assert html.lstrip().lower().startswith("<!doctype html>") and "</html>" in html


def test_replay_errors_name_the_keyword(pendulum, log):
    with pytest.raises(plumb.ArgumentError) as caught:
        plumb.replay(pendulum, log, window=-1)
    assert caught.value.argument == "window"
    with pytest.raises(plumb.ArgumentError) as caught:
        plumb.replay(pendulum, log, set={"qpos[hinge]": 0.1})
    assert caught.value.argument == "set"


def test_identify_finds_the_damping_and_equals_the_cli(pendulum, log, cli_json):
    model = mujoco.MjModel.from_xml_path(pendulum)
    before = model.dof_damping.copy()
    r = plumb.identify(model, log, fit="dof_damping[hinge]", threads=1)
    np.testing.assert_array_equal(model.dof_damping, before)  # the caller's model unchanged
    assert r.paths == ["dof_damping[hinge]"]
    assert abs(r.values[0] - TRUE_DAMPING) < 3 * r.std_errors[0]
    assert r.covariance.shape == (1, 1)
    assert r.covariance[0, 0] == pytest.approx(r.std_errors[0] ** 2)
    assert r.fits_after[0] > 99 > r.fits_before[0]
    assert isinstance(r.fitted, plumb.Model)
    fitted = plumb.replay(r.fitted, log)
    assert fitted.fit > 99
    ours = plumb.identify(pendulum, log, fit="dof_damping[hinge]", threads=1).to_dict()
    theirs = cli_json("identify", "models/pendulum.xml", "--log", str(log), "--fit",
                      "dof_damping[hinge]", "--threads", "1")
    ours.pop("model"), theirs.pop("model")
    assert ours == theirs


def test_identify_is_the_same_for_any_thread_count(pendulum, log):
    fit = ["dof_damping[hinge]", "body_mass[link]"]
    one = plumb.identify(pendulum, [log], fit=fit, threads=1)
    two = plumb.identify(pendulum, [log], fit=fit, threads=2)
    assert one.to_json() == two.to_json()
    np.testing.assert_array_equal(one.correlation, two.correlation)
    assert one.correlation.shape == (2, 2)


def test_identify_outputs_and_errors(pendulum, root, log, monkeypatch):
    from conftest import run_cli

    monkeypatch.chdir(root)  # the table names the model as given: the same relative path
    r = plumb.identify("models/pendulum.xml", log, fit="dof_damping[hinge]", validate=str(log))
    table = run_cli("identify", "models/pendulum.xml", "--log", str(log), "--fit",
                    "dof_damping[hinge]", "--validate", str(log)).stdout
    assert repr(r) == table
    assert list(r.to_pandas()["path"]) == ["dof_damping[hinge]"]
    html = r._repr_html_()
    assert html.lstrip().lower().startswith("<!doctype html>") and "</html>" in html
    with pytest.raises(plumb.ArgumentError) as caught:
        plumb.identify(pendulum, log, fit="dof_damping[hinge]", delay="ctl")
    assert caught.value.argument == "delay"
    with pytest.raises(plumb.ArgumentError) as caught:
        plumb.identify(pendulum, log, fit="dof_damping[hinge]", max_delay=0)
    assert caught.value.argument == "max_delay"
    with pytest.raises(plumb.PathError, match="hinj"):
        plumb.identify(pendulum, log, fit="dof_damping[hinj]")


def test_save_model_writes_every_model_form(pendulum, log, tmp_path):
    # issue 46: a mujoco.MjModel once gave "ParseXML: Error opening file '<MjModel ...>'"
    model = mujoco.MjModel.from_xml_path(pendulum)
    for name, given in [("path", pendulum), ("mjmodel", model), ("loaded", plumb.load(model))]:
        r = plumb.identify(given, log, fit="dof_damping[hinge]", threads=1)
        out = tmp_path / f"{name}.xml"
        r.save_model(out)
        saved = mujoco.MjModel.from_xml_path(str(out))
        assert saved.dof_damping[0] == pytest.approx(r.values[0], rel=1e-5)  # 6 digits
        assert saved.body_mass[1] == pytest.approx(model.body_mass[1])


def test_save_model_of_an_mjmodel_without_its_xml_says_what_to_give(pendulum, log, tmp_path):
    model = mujoco.MjModel.from_xml_path(pendulum)
    r = plumb.identify(model, log, fit="dof_damping[hinge]", threads=1)
    # MuJoCo's last parsed XML is now another model's
    mujoco.MjModel.from_xml_string("<mujoco><worldbody><body><joint/><geom size='.1'/></body>"
                                   "<body pos='1 0 0'><joint/><geom size='.1'/></body>"
                                   "</worldbody></mujoco>")
    out = tmp_path / "fitted.xml"
    with pytest.raises(plumb.ValueError, match="no MJCF file of its own.*source") as caught:
        r.save_model(out)
    assert "<MjModel 'pendulum'>" in str(caught.value)
    assert not out.exists()
    r.save_model(out, source=pendulum)  # what the message says to do
    assert mujoco.MjModel.from_xml_path(str(out)).dof_damping[0] == pytest.approx(r.values[0])
    # a source that is another model is refused
    other = tmp_path / "other.xml"
    other.write_text("<mujoco><worldbody><body name='b'><joint name='hinge'/>"
                     "<geom size='.1'/></body></worldbody></mujoco>")
    with pytest.raises(plumb.ValueError, match="is not the MJCF of the fitted model"):
        r.save_model(tmp_path / "wrong.xml", source=other)


def test_identify_on_a_cut_log_warns_and_keeps_the_notice(pendulum, log, tmp_path):
    # issue 47: only the CLI said that a log's last line was cut (the bridge killed mid-write)
    # a flight recorder's log (a `kind` column) ends every line with a newline: one without
    # was cut short by a kill
    rows = [line.split(",", 1) for line in log.read_text().splitlines()]
    text = "".join(f"{t},{'state' if i else 'kind'},{rest}\n" for i, (t, rest) in enumerate(rows))
    cut = tmp_path / "cut.csv"
    cut.write_text(text[:-4])  # the newline and three characters before it
    with pytest.warns(plumb.LogWarning, match="cut.csv: the last line is cut short"):
        r = plumb.identify(pendulum, cut, fit="dof_damping[hinge]", threads=1)
    assert [(n.level, n.topic, n.subject) for n in r.notices] == [("note", "log", str(cut))]
    assert "left out" in r.notices[0].text
    assert r.to_dict()["notices"][0]["subject"] == str(cut)  # as plumb identify's JSON
    with pytest.warns(plumb.LogWarning, match="cut.csv"):  # a held-out log too
        held = plumb.identify(pendulum, log, fit="dof_damping[hinge]", validate=cut, threads=1)
    assert [n.subject for n in held.notices] == [str(cut)]
    assert plumb.identify(pendulum, log, fit="dof_damping[hinge]", threads=1).notices == []


def test_identify_refuses_no_log_or_no_parameter_naming_the_keyword(pendulum, log):
    with pytest.raises(plumb.ArgumentError) as caught:
        plumb.identify(pendulum, [], fit="dof_damping[hinge]")
    assert caught.value.argument == "log"
    with pytest.raises(plumb.ArgumentError) as caught:
        plumb.identify(pendulum, log, fit=[])
    assert caught.value.argument == "fit"
