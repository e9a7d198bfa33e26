"""``harness robots``: our exporter as a pair (from_urdf, our MJCF, MuJoCo) against Pinocchio on small synthetic
fixed-base URDFs: it agrees; the quarter turns from_urdf snaps are a proven cause; an exporter defect (emulated)
stays open; what our pipeline refuses or does not cover is "not compared" with its reason."""

import dataclasses

import numpy as np

from harness.files import robots

EXPORT = f"pinocchio-{robots.EXPORT}"
ARM = """<?xml version="1.0"?>
<robot name="{name}">
  <link name="base"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>
  </inertial></link>
  <link name="upper"><inertial><origin xyz="0.2 0.01 -0.02" rpy="0.3 -0.2 0.5"/><mass value="1.5"/>
    <inertia ixx="0.004" ixy="0.0003" ixz="0" iyy="0.02" iyz="0.0001" izz="0.02"/></inertial></link>
  <link name="sensor"><inertial><origin xyz="0.05 0 0.03" rpy="0.7 0 0"/><mass value="0.2"/>
    <inertia ixx="0.0002" ixy="0" ixz="0" iyy="0.0003" iyz="0" izz="0.0004"/></inertial></link>
  <link name="lower"><inertial><origin xyz="0.15 0 0" rpy="0 0 0"/><mass value="0.8"/>
    <inertia ixx="0.002" ixy="0" ixz="0" iyy="0.006" iyz="0" izz="0.006"/></inertial></link>
  <link name="slider"><inertial><origin xyz="0 0 0.02"/><mass value="0.3"/>
    <inertia ixx="0.0004" ixy="0" ixz="0" iyy="0.0004" iyz="0" izz="0.0002"/></inertial></link>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/><axis xyz="0 0 1"/>
    <origin xyz="0 0 0.1" rpy="{twist} 0 0"/><limit lower="-3" upper="3" effort="10" velocity="5"/></joint>
  <joint name="mount" type="fixed"><parent link="upper"/><child link="sensor"/>
    <origin xyz="0.3 0 0.05" rpy="0 0.4 0.1"/></joint>
  <joint name="elbow" type="continuous"><parent link="sensor"/><child link="lower"/><axis xyz="0 1 0"/>
    <origin xyz="0.1 0 0" rpy="0.3 0 0"/></joint>
  <joint name="slide" type="prismatic"><parent link="lower"/><child link="slider"/><axis xyz="1 0 0"/>
    <origin xyz="0.3 0 0"/><limit lower="-1" upper="1" effort="10" velocity="5"/></joint>
</robot>
"""
QUARTER = "1.5707963267948966"     # the float of π/2: what from_urdf makes of it is the same number
TRUNCATED = "1.57079632679"        # π/2 − 4.9e-12, as the UR and Kinova files write it


def _sweep(tmp_path, text, name="synthetic_arm", states=4):
    path = tmp_path / f"{name}.urdf"
    path.write_text(text)
    record = robots.sweep_robot((name, str(path), states, 0))
    return record, {p["pair"]: p for p in record["pairs"]}


def test_our_export_agrees_on_a_fixed_base_arm(tmp_path):
    record, pairs = _sweep(tmp_path, ARM.format(name="synthetic_arm", twist=QUARTER))
    assert record["dof"] == 3
    assert {p: v["verdict"] for p, v in pairs.items()} == {
        "pinocchio-mujoco": "agree", "pinocchio-drake": "agree", EXPORT: "agree"}
    p = pairs[EXPORT]
    assert p["worst"]["ratio"] <= robots.MARGIN and p["cause"] is None
    assert {c["quantity"] for c in p["checks"]} >= {"M", "Cqd", "g", "qdd", "mass", "first moment of mass", "inertia"}
    assert record["engines"][robots.EXPORT]["bodies"] == 3 and record["engines"][robots.EXPORT]["snapped"] == []


def test_a_snapped_quarter_turn_is_a_proven_cause(tmp_path):
    record, pairs = _sweep(tmp_path, ARM.format(name="synthetic_arm", twist=TRUNCATED))
    assert pairs["pinocchio-mujoco"]["verdict"] == "agree"   # MuJoCo's importer reads the decimals as written
    p = pairs[EXPORT]
    assert p["verdict"] == robots.DISAGREE_EXPLAINED and p["worst"]["ratio"] > 1
    assert p["cause"]["proven"] and p["cause"]["after"] <= robots.MARGIN
    assert "shoulder" in p["cause"]["cause"] and TRUNCATED in p["cause"]["cause"]
    assert record["engines"][robots.EXPORT]["snapped"] == [f"shoulder {TRUNCATED}"]


def test_an_exporter_defect_stays_open(tmp_path, monkeypatch):
    """The pair is not blind: an exporter that dropped every joint's rpy (emulated on the numeric tree) disagrees,
    no cause is proven, and the command would fail."""
    real = robots.export_system

    def defective(robot, quarter_turns=True):
        system, tree = real(robot, quarter_turns)
        joints = tuple(dataclasses.replace(j, rpy=np.zeros(3)) for j in tree.joints)
        return system, dataclasses.replace(tree, joints=joints)

    monkeypatch.setattr(robots, "export_system", defective)
    record, pairs = _sweep(tmp_path, ARM.format(name="synthetic_arm", twist=TRUNCATED))
    p = pairs[EXPORT]
    assert p["verdict"] == robots.DISAGREE_OPEN and p["worst"]["ratio"] > 1e3
    assert not p["cause"]["proven"]      # the snapped angle is found, but taking it literally does not explain it
    assert pairs["pinocchio-mujoco"]["verdict"] == "agree"
    doc = robots.document([record], 4, 0, 1.0, 1, "test")
    assert doc["open"] == [f"synthetic_arm {EXPORT}"]
    _, pairs = _sweep(tmp_path, ARM.format(name="synthetic_arm", twist=QUARTER))
    assert pairs[EXPORT]["verdict"] == robots.DISAGREE_OPEN and pairs[EXPORT]["cause"] is None


def test_what_our_pipeline_refuses_is_not_compared_with_its_reason(tmp_path):
    """A tensor violating A + B >= C: our instantiate refuses it (the exporter never writes it for MuJoCo to
    balance): "not compared", the reason a finding, the other pairs compared as before."""
    text = ARM.format(name="synthetic_arm", twist="0").replace(
        'ixx="0.002" ixy="0" ixz="0" iyy="0.006" iyz="0" izz="0.006"',
        'ixx="0.001" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.02"')
    record, pairs = _sweep(tmp_path, text)
    p = pairs[EXPORT]
    assert p["verdict"] == robots.NOT_COMPARED and "triangle inequality" in p["error"]
    assert any(f["kind"] == "not compared" and "triangle inequality" in f["text"] for f in record["findings"])
    assert pairs["pinocchio-mujoco"]["verdict"] == robots.DISAGREE_EXPLAINED


def test_out_of_scope_is_not_compared(tmp_path):
    mimic = ARM.format(name="mimic_arm", twist="0").replace(
        '<origin xyz="0.3 0 0"/>', '<origin xyz="0.3 0 0"/><mimic joint="elbow" multiplier="0.1"/>')
    _, pairs = _sweep(tmp_path, mimic, "mimic_arm")
    assert pairs[EXPORT]["verdict"] == robots.NOT_COMPARED and "<mimic>" in pairs[EXPORT]["error"]
    assert pairs[EXPORT]["checks"] == []
