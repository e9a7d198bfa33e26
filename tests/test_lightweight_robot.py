"""``harness.files.from_urdf`` against Pinocchio's own URDF parser, and the lightweight robot built with it.

The Panda file of ``example-robot-data`` is parsed by both; Pinocchio's model with the finger joints locked
(``buildReducedModel``, which lumps the fixed and locked links into their parent joint's inertia, as we do) must
hold the same masses, centres of mass (``lever``), inertia tensors and joint placements as our System. Rotated
inertials (``<inertial><origin rpy>``, none in the Panda) and a free ``<mimic>`` joint are checked on a small
URDF written here. The conformance of the system against both engines is ``tests/test_conformance.py``.

Tolerance ``RTOL = 1e-12`` relative (float64 round-off of the same lumping in two programs, as
``harness.compare.roundtrip.ROUNDTRIP_RTOL``), except the joint rotations: we take the file's quarter turns
``1.5707963267948966`` as exact π/2 (``cos = 0``, where the file's float gives ``6.1e-17``), an absolute 1e-15.
"""

import numpy as np
import pinocchio as pin
import pytest
import sympy as sp

import models
from harness.errors import ModelError
from harness.export.numeric import instantiate
from harness.files.from_urdf import exact_angle, from_urdf, parse
from harness.derivation.kinematics import rpy_rotation
from models.lightweight_robot import FINGER_OPENING, urdf_file

RTOL = 1e-12
ROTATION_ATOL = 1e-15


def _close(ours, theirs, rtol=RTOL):
    ours, theirs = np.asarray(ours, dtype=float), np.asarray(theirs, dtype=float)
    scale = max(np.abs(theirs).max(initial=0.0), 1e-300)
    assert np.abs(ours - theirs).max(initial=0.0) <= rtol * scale, (ours, theirs)


def _pinocchio_reduced(path, lock: dict):
    model = pin.buildModelFromUrdf(str(path))
    q = pin.neutral(model)
    ids = []
    for name, value in lock.items():
        jid = model.getJointId(name)
        q[model.joints[jid].idx_q] = value
        ids.append(jid)
    return pin.buildReducedModel(model, ids, q)


@pytest.fixture(scope="module")
def panda():
    system = models.get("lightweight_robot")
    reduced = _pinocchio_reduced(urdf_file(), {"panda_finger_joint1": FINGER_OPENING,
                                               "panda_finger_joint2": FINGER_OPENING})
    return system, instantiate(system, system.default_parameters()), reduced


def test_panda_bodies_match_pinocchio_parse(panda):
    system, tree, model = panda
    assert model.nv == len(system.coordinates) == 7
    for link in tree.links:
        joint = system.joint_of_link(link.name)
        inertia = model.inertias[model.getJointId(joint.name)]
        _close([link.mass], [inertia.mass])
        _close(link.com, inertia.lever)
        _close(link.inertia, inertia.inertia)
    hand = tree.links[-1]  # link 7 + hand + fingers, lumped
    assert hand.mass == pytest.approx(0.735522 + 0.73 + 2 * 0.015, rel=1e-15)


def test_panda_joint_placements_match_pinocchio_parse(panda):
    system, tree, model = panda
    for joint in tree.joints:
        placement = model.jointPlacements[model.getJointId(joint.name)]
        _close(joint.origin, placement.translation)
        rotation = np.array(rpy_rotation(system.joint(joint.name).rpy), dtype=float)
        assert np.abs(rotation - placement.rotation).max() <= ROTATION_ATOL
        assert joint.type == "revolute" and list(joint.axis) == [0, 0, 1]


def test_panda_parameters_and_map(panda):
    system, _, _ = panda
    assert [p.name for p in system.parameters] == [f"m_panda_link{k}" for k in range(1, 8)] + ["g"]
    assert [c.name for c in system.coordinates] == [f"q_{k}" for k in range(1, 8)]
    assert list(system.phi) == system.q
    assert system.joint("panda_joint2").rpy == (-sp.pi / 2, 0, 0)


ROTATED = """<?xml version="1.0"?>
<robot name="rotated">
  <link name="base"/>
  <link name="arm">
    <inertial>
      <origin xyz="0.1 -0.2 0.3" rpy="0.3 -0.7 1.1"/>
      <mass value="2.5"/>
      <inertia ixx="0.4" ixy="0.01" ixz="-0.02" iyy="0.3" iyz="0.03" izz="0.2"/>
    </inertial>
  </link>
  <link name="tool">
    <inertial>
      <origin xyz="0.05 0 0.02" rpy="-0.4 0.2 0.9"/>
      <mass value="0.5"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.015"/>
    </inertial>
  </link>
  <link name="left"><inertial><mass value="0.1"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial></link>
  <link name="right"><inertial><mass value="0.1"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial></link>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.5" rpy="1.5707963267948966 0 0.25"/><axis xyz="0 1 0"/>
    <limit effort="1" lower="-1" upper="1" velocity="1"/>
  </joint>
  <joint name="wrist" type="fixed">
    <parent link="arm"/><child link="tool"/><origin xyz="0.4 0.1 0" rpy="0 0.5 -0.3"/>
  </joint>
  <joint name="finger_left" type="prismatic">
    <parent link="tool"/><child link="left"/><origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>
    <limit effort="1" lower="0" upper="0.04" velocity="1"/>
  </joint>
  <joint name="finger_right" type="prismatic">
    <parent link="tool"/><child link="right"/><origin xyz="0 0 0.1"/><axis xyz="0 -1 0"/>
    <limit effort="1" lower="0" upper="0.04" velocity="1"/><mimic joint="finger_left" multiplier="2" offset="0.01"/>
  </joint>
</robot>
"""


def test_rotated_inertials_and_locked_mimic_match_pinocchio(tmp_path):
    path = tmp_path / "rotated.urdf"
    path.write_text(ROTATED)
    system = from_urdf(path, name="rotated", title="t", lecture="-", lock={"finger_left": 0.02})
    tree = instantiate(system, system.default_parameters())
    model = _pinocchio_reduced(path, {"finger_left": 0.02, "finger_right": 2 * 0.02 + 0.01})
    (arm,) = tree.links  # tool and both fingers lumped into arm
    inertia = model.inertias[model.getJointId("shoulder")]
    _close([arm.mass], [inertia.mass])
    _close(arm.com, inertia.lever)
    _close(arm.inertia, inertia.inertia)
    _close(tree.joints[0].origin, model.jointPlacements[1].translation)
    assert np.abs(np.array(rpy_rotation(system.joints[0].rpy), dtype=float)
                  - model.jointPlacements[1].rotation).max() <= ROTATION_ATOL


def test_free_mimic_becomes_a_map(tmp_path):
    path = tmp_path / "rotated.urdf"
    path.write_text(ROTATED)
    system = from_urdf(path, name="mimic", title="t", lecture="-", masses=False)
    assert [c.name for c in system.coordinates] == ["q_1", "q_2"]
    q_2 = system.coordinates[1].symbol
    assert system.joint("finger_right").phi == 2 * q_2 + sp.Float(0.01)
    assert system.joint("finger_right").parent == "arm"  # attached through the fixed wrist, composed


def test_bad_urdf_is_one_model_error(tmp_path):
    with pytest.raises(ModelError, match="DOCTYPE|entity"):
        parse('<?xml version="1.0"?><!DOCTYPE r [<!ENTITY x "y">]><robot name="r">&x;</robot>')
    with pytest.raises(ModelError, match="floating"):
        parse('<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="floating">'
              '<parent link="a"/><child link="b"/></joint></robot>')
    with pytest.raises(ModelError, match="not a list of numbers"):
        parse('<robot name="r"><link name="a"><inertial><mass value="x"/>'
              '<inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link></robot>')
    with pytest.raises(ModelError, match="missing ixy"):
        parse('<robot name="r"><link name="a"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1"/>'
              '</inertial></link></robot>')
    with pytest.raises(ModelError, match="cannot read"):
        parse(tmp_path / "missing.urdf")


def test_exact_quarter_turns():
    assert exact_angle(1.5707963267948966) == sp.pi / 2
    assert exact_angle(-1.57079632679) == -sp.pi / 2
    assert exact_angle(0.0) == 0
    assert exact_angle(0.25) == sp.Float(0.25)


@pytest.mark.parametrize("name", ["cart_pendulum", "spherical_pendulum"])
def test_per_body_christoffel_equals_differentiated_M(name, monkeypatch):
    """The body-by-body M, C (Christoffel), Ṁ, g used from 6 DoF on equal the derivation that differentiates M,
    on small systems with revolute and prismatic joints (float64 round-off apart)."""
    from harness.derivation import derive as derive_module
    from harness.derivation.compile import CompiledModel

    system = models.get(name)
    reference = CompiledModel(system, derive_module.derive_uncached(system))
    monkeypatch.setattr(derive_module, "PER_BODY_MIN_DOF", 1)
    per_body = CompiledModel(system, derive_module.derive_uncached(system))
    rng = np.random.default_rng(5)
    p = list(system.default_parameters().values())
    for _ in range(10):
        q, qd = rng.uniform(-2, 2, len(system.q)), rng.uniform(-3, 3, len(system.q))
        for quantity in ("M", "C", "M_dot", "g"):
            _close(per_body(quantity, q, qd, p), reference(quantity, q, qd, p), rtol=1e-13)


def test_fixed_joint_with_moving_child_matches_pinocchio():
    """``harness/files/fixtures/rotated_inertials.urdf``: rotated inertials everywhere and a prismatic joint behind a
    rotated fixed joint, whose origin we compose into the joint; bodies and placements as Pinocchio parses them."""
    from pathlib import Path

    import harness

    path = Path(harness.__file__).parent / "files" / "fixtures" / "rotated_inertials.urdf"
    system = from_urdf(path, name="rotated_inertials", title="t", lecture="-")
    tree = instantiate(system, system.default_parameters())
    model = pin.buildModelFromUrdf(str(path))
    assert [j.name for j in tree.joints] == ["j1", "j2", "j3"] and model.nv == 3
    for link in tree.links:
        inertia = model.inertias[model.getJointId(system.joint_of_link(link.name).name)]
        _close([link.mass], [inertia.mass])
        _close(link.com, inertia.lever)
        _close(link.inertia, inertia.inertia)
    for joint in tree.joints:
        placement = model.jointPlacements[model.getJointId(joint.name)]
        _close(joint.origin, placement.translation)
        rotation = np.array(rpy_rotation(system.joint(joint.name).rpy).evalf(), dtype=float)
        assert np.abs(rotation - placement.rotation).max() <= 1e-14
