"""plumb.converge holds the solref time constants MuJoCo clamps at 2*dt across the ladder."""

import plumb

STIFF_CONTACT = """<mujoco><option timestep="0.002"/>
  <default><geom solref="0.001 1"/></default>
  <worldbody><geom type="plane" size="1 1 0.1"/>
    <body pos="0 0 0.12"><freejoint/><geom type="sphere" size="0.1" mass="1"/></body>
  </worldbody></mujoco>"""


def test_converge_holds_the_solref_floor(tmp_path, cli_json):
    path = tmp_path / "stiff.xml"
    path.write_text(STIFF_CONTACT)
    result = plumb.converge(str(path), "qpos[2]@1")
    assert result.solref_floor == 0.004
    assert result.solref_held == "geom_solref (2)"
    assert result.recommended_dt == 0.002  # the levels run one model and agree
    theirs = cli_json("converge", str(path), "--metric", "qpos[2]@1")
    assert theirs["solref_floor"] == 0.004 and theirs["solref_held"] == "geom_solref (2)"


def test_converge_holds_nothing_where_nothing_is_clamped(pendulum):
    result = plumb.converge(pendulum, "qpos[hinge]@1", set={"qpos[hinge]": 0.7})
    assert result.solref_floor == 0 and result.solref_held == ""
