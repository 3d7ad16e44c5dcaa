"""plumb.audit, plumb.converge, plumb.snapshot and plumb.diff against the CLI."""

import json
import pathlib

import mujoco
import numpy as np
import pytest

import plumb


def test_audit_equals_the_cli_json(pendulum, cli_json):
    ours = plumb.audit(pendulum).to_dict()
    theirs = cli_json("audit", "models/pendulum.xml")
    ours.pop("model"), theirs.pop("model")
    assert ours == theirs
    assert ours["summary"]["fail"] == 0


def test_audit_rows_and_verdict(pendulum):
    result = plumb.audit(pendulum)
    assert result.ok
    sections = {row.section for row in result.rows}
    assert sections <= {"structure", "inertia", "actuator", "contact", "behaviour", "warnings"}
    assert result.count("FAIL") == 0
    assert len(result.to_pandas()) == len(result.rows)
    assert result.start == "qpos0"


def test_audit_names_a_start_outside_a_joint_range(tmp_path):
    # the same row the CLI prints: a start its authors would not have meant
    xml = tmp_path / "arm.xml"
    xml.write_text("""<mujoco><compiler angle="radian"/><worldbody><body>
      <joint name="elbow" range="0.3 1.2"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02" mass="1"/></body></worldbody></mujoco>""")
    result = plumb.audit(str(xml))
    assert result.start == "qpos0 (1 joint brought into its range)"
    [row] = [r for r in result.rows if r.id == "structure.start"]
    assert row.status == "FAIL"
    assert "elbow" in row.element
    inside = plumb.audit(str(xml), set=["qpos[elbow]=0.5"])
    assert inside.start == "qpos0 (1 joint brought into its range) with qpos[elbow]=0.5"
    assert [r.status for r in inside.rows if r.id == "structure.start"] == ["PASS"]


def test_audit_finds_the_defects_and_an_accept_list_clears_them(tmp_path, root):
    # a free marker that collides with nothing (FAIL contact.free_fall) and a motor without
    # bounds (WARN actuator.limits): the accept-list tests' model
    model = str(root / "tests" / "models" / "two_findings.xml")
    result = plumb.audit(model)
    assert not result.ok
    fail = next(row for row in result.rows if row.status == "FAIL")
    assert (fail.id, fail.element_type, fail.element_name) == ("contact.free_fall", "body", "marker")
    assert fail.fix
    assert plumb.audit(model, strict=True).ok is False

    accept = tmp_path / "accept.toml"
    accept.write_text(
        '[[accept]]\ncheck = "contact.free_fall"\nelement = "body \'marker\'"\n'
        'reason = "a marker, welded in the real build"\n'
    )
    accepted = plumb.audit(model, accept=accept)
    assert accepted.ok  # the FAIL is accepted; the WARN fails only with strict
    row = next(r for r in accepted.rows if r.id == "contact.free_fall")
    assert row.status == "FAIL" and row.accepted == "a marker, welded in the real build"
    assert not plumb.audit(model, accept=accept, strict=True).ok


def test_converge_pendulum_rk4_is_fourth_order(pendulum, cli_json):
    result = plumb.converge(
        pendulum, "qpos[hinge]@1", set={"qpos[hinge]": 0.7, "opt.integrator": "RK4"}
    )
    assert result.ok
    assert result.expected_order == 4
    assert abs(result.observed_order - 4) < 0.5
    assert result.dt.shape == result.values.shape == (5,)
    np.testing.assert_allclose(result.dt[1:] * 2, result.dt[:-1])
    theirs = cli_json(
        "converge", "models/pendulum.xml", "--set", "qpos[hinge]=0.7", "--set",
        "opt.integrator=RK4", "--metric", "qpos[hinge]@1",
    )
    ours = result.to_dict()
    ours.pop("model"), theirs.pop("model")
    assert ours == theirs
    assert len(result.to_pandas()) == 5


def test_converge_bad_arguments_name_the_keyword(pendulum):
    with pytest.raises(plumb.ArgumentError) as caught:
        plumb.converge(pendulum, "qpos[hinge]@1", dt=-1.0)
    assert caught.value.argument == "dt"
    with pytest.raises(plumb.ArgumentError) as caught:
        plumb.converge(pendulum, "period(qpos[hinge])")  # it never swings from rest
    assert caught.value.argument == "metric"


def test_snapshot_round_trip_and_diff(tmp_path, pendulum, cli_json):
    snap = plumb.snapshot(pendulum, set={"qpos[hinge]": 0.7})
    path = tmp_path / "pendulum.snap.json"
    snap.save(path)
    assert json.loads(path.read_text()) == snap.to_dict()
    loaded = plumb.Snapshot.load(path)
    assert loaded.text == snap.text

    same = plumb.diff(loaded, pendulum)
    assert same.ok and same.changes == []

    # the caller's edit of the MjModel is what diff sees; plumb does not change it
    model = mujoco.MjModel.from_xml_path(pendulum)
    model.dof_damping[0] = 0.3
    changed = plumb.diff(path, model)
    assert not changed.ok
    paths = [c["path"] for c in changed.changes]
    assert "dof_damping[hinge]" in paths
    assert model.dof_damping[0] == 0.3

    # the CLI reads the snapshot Python wrote, and says the same
    theirs = cli_json("diff", str(path), "models/pendulum.xml")
    ours = plumb.diff(path, pendulum).to_dict()
    ours.pop("model"), theirs.pop("model")
    assert ours == theirs
    html = changed._repr_html_()
    assert "dof_damping[hinge]" in html and "</html>" in html


def test_snapshot_load_refuses_a_model_file(pendulum):
    with pytest.raises(plumb.ValueError, match="not a plumb snapshot"):
        plumb.Snapshot.load(pendulum)
    with pytest.raises(plumb.IoError):
        plumb.Snapshot.load("no/such/file.json")


def test_diff_negative_tol_names_tol(tmp_path, pendulum):
    snap = plumb.snapshot(pendulum)
    with pytest.raises(plumb.ArgumentError) as caught:
        plumb.diff(snap, pendulum, tol=-1.0)
    assert caught.value.argument == "tol"
