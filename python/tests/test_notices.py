"""What a call says besides its result reaches Python as the plumb command says it on stderr:
each warning, note and hint is issued through `warnings` with plumb's class for its topic, and
the result keeps them (.notices, and "notices" in its JSON)."""

import warnings

import mujoco
import numpy as np
import pytest

import plumb

# MuJoCo shortens a delay longer than its buffer (20 samples x 2 ms) without a word
ARM = """<mujoco><worldbody>
  <body><joint name="a" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02"/>
    <body pos="0.3 0 0"><joint name="b" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02"/></body></body></worldbody>
  <actuator><motor name="m" joint="a" ctrlrange="-1 1" ctrllimited="true"/>{more}</actuator>
</mujoco>"""
LATE = '<motor name="late" joint="b" delay="0.5" nsample="20"/>'


@pytest.fixture
def arm(tmp_path):
    """Two hinges, motor 'm' with ctrlrange [-1, 1]."""
    path = tmp_path / "arm.xml"
    path.write_text(ARM.format(more=""))
    return str(path)


@pytest.fixture
def late(tmp_path):
    """The arm with a delay MuJoCo shortens (MuJoCo 3.5 and later), whose compile warns."""
    path = tmp_path / "late.xml"
    path.write_text(ARM.format(more=LATE))
    return str(path)


def _version():
    return tuple(int(part) for part in plumb.compiled_mujoco_version().split(".")[:2])


def _said(record, cls):
    return [str(w.message) for w in record if issubclass(w.category, cls)]


def test_every_warning_class_is_a_plumb_warning_and_a_user_warning():
    classes = [plumb.CompileWarning, plumb.StartWarning, plumb.LogWarning, plumb.BatchWarning,
               plumb.ModelWarning, plumb.PlumbWarning]
    for cls in classes:
        assert issubclass(cls, plumb.PlumbWarning) and issubclass(cls, UserWarning), cls


def test_loading_says_what_mujoco_s_compiler_said(tmp_path):
    if _version() < (4, 0):
        pytest.skip("settotalmass is deprecated from MuJoCo 4 on")
    path = tmp_path / "total.xml"
    path.write_text('<mujoco><compiler settotalmass="5"/><worldbody><body><freejoint/>'
                    '<geom size="0.1"/></body></worldbody></mujoco>')
    for call in (plumb.load, plumb.inspect, lambda p: plumb.run(p, until=0.002)):
        with pytest.warns(plumb.CompileWarning) as record:
            call(str(path))
        said = _said(record, plumb.CompileWarning)
        assert len([s for s in said if "settotalmass" in s]) == 1, said  # once, not twice


def test_loading_says_what_mujoco_did_to_the_model(late):
    if _version() < (3, 5):
        pytest.skip("delays came with MuJoCo 3.5")
    with pytest.warns(plumb.CompileWarning) as record:
        model = plumb.load(late)
    said = _said(record, plumb.CompileWarning)
    assert any(f"'{late}'" in s and "delay 0.5 s is longer than its buffer" in s for s in said)
    # a call given the path says it too, and its result keeps it
    with pytest.warns(plumb.CompileWarning):
        d = plumb.inspect(late)
    assert [n.topic for n in d.notices] == ["compile"]
    assert d.notices[0].subject == f"'{late}'"
    assert d.to_dict()["notices"][0]["topic"] == "compile"
    # a loaded plumb.Model said it once, when it was loaded
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert plumb.inspect(model).notices == []


def test_a_ctrl_outside_its_ctrlrange_is_a_start_warning(arm):
    with pytest.warns(plumb.StartWarning) as record:
        t = plumb.run(arm, until=0.01, set={"ctrl[m]": 5})
    [message] = _said(record, plumb.StartWarning)
    assert message.startswith("warning: set 'ctrl[m]=5': 5 is outside the ctrlrange")
    [notice] = t.notices
    assert (notice.level, notice.topic, notice.subject) == ("warning", "start", "set 'ctrl[m]=5'")
    assert str(notice) == message
    # verify and converge say it too, and their JSON carries it
    with pytest.warns(plumb.StartWarning):
        v = plumb.verify(arm, set=["ctrl[m]=5"], until=0.1)
    assert [n["subject"] for n in v.to_dict()["notices"]] == ["set 'ctrl[m]=5'"]
    with pytest.warns(plumb.StartWarning):
        plumb.converge(arm, "qpos[a]@0.05", set={"ctrl[m]": -2}, halvings=2)
    with pytest.warns(plumb.StartWarning):
        plumb.load(arm, set={"ctrl[m]": 5})
    # within the range: nothing to say
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert plumb.run(arm, until=0.01, set={"ctrl[m]": 0.5}).notices == []


def test_a_filter_turns_a_warning_into_an_error(arm):
    with warnings.catch_warnings():
        warnings.simplefilter("error", plumb.StartWarning)
        with pytest.raises(plumb.StartWarning, match="outside the ctrlrange"):
            plumb.run(arm, until=0.01, set={"ctrl[m]": 5})
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("ignore", plumb.PlumbWarning)
        t = plumb.run(arm, until=0.01, set={"ctrl[m]": 5})
    assert record == [] and len(t.notices) == 1  # filtered out, still kept


def test_a_replayed_log_whose_last_line_is_cut_is_a_log_warning(pendulum, tmp_path):
    # a flight recorder's log (a kind column: every line ends with a newline) whose last line
    # the bridge was killed while writing
    t = plumb.run(pendulum, until=1, every=0.01, set={"qpos[hinge]": 0.7})
    lines = ["time,kind," + ",".join(t.columns[1:])]
    rows = t.array.tolist()
    lines += [f"{row[0]!r},state," + ",".join(repr(v) for v in row[1:]) for row in rows]
    path = tmp_path / "cut.csv"
    path.write_text("\n".join(lines)[:-3])
    with pytest.warns(plumb.LogWarning, match="the last line is cut short") as record:
        r = plumb.replay(pendulum, path)
    assert [n.topic for n in r.notices] == ["log"]
    assert r.notices[0].level == "note" and r.notices[0].subject == str(path)
    assert r.to_dict()["notices"][0]["topic"] == "log"
    assert all(issubclass(w.category, plumb.PlumbWarning) for w in record)


def test_a_wrapped_mjmodel_says_only_what_mujoco_did_without_a_word(arm, late):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        plumb.load(mujoco.MjModel.from_xml_path(arm))
    if _version() < (3, 5):
        pytest.skip("delays came with MuJoCo 3.5")
    with pytest.warns(plumb.CompileWarning, match="delay 0.5 s is longer than its buffer"):
        plumb.load(mujoco.MjModel.from_xml_path(late))


def test_mujocos_warnings_of_a_run_are_plumb_warnings(tmp_path):
    # ten boxes on a floor in too little memory for their contacts: MuJoCo warns, the run goes on
    boxes = "".join(f'<body pos="{0.3 * i} 0 0.05"><freejoint/><geom type="box" '
                    'size="0.1 0.1 0.05"/></body>' for i in range(10))
    path = tmp_path / "crowded.xml"
    path.write_text('<mujoco><size memory="48K"/><worldbody><geom type="plane" size="5 5 0.1"/>'
                    + boxes + "</worldbody></mujoco>")
    with pytest.warns(plumb.PlumbWarning, match="MuJoCo CNSTRFULL raised") as record:
        t = plumb.run(str(path), until=0.1)
    [kind] = t.warnings
    said = [n for n in t.notices if "raised" in n.text]
    assert len(said) == 1 and said[0].text.startswith(f"MuJoCo {kind['kind']} raised")
    assert all(issubclass(w.category, plumb.PlumbWarning) for w in record)
