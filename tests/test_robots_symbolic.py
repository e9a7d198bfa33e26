"""``harness robots --symbolic``: our symbolic derivation (from_urdf's System, M, C q̇, g derived and compiled) as a
pair against Pinocchio: it agrees on the package's double pendulum and on a synthetic arm (rotated inertials, a fixed
link, a prismatic joint, a tensor our exporter refuses); the quarter turns from_urdf snaps are a proven cause; a
defect of the derivation (emulated) stays open; a page per robot is written and linked from robots.html."""

import re

import numpy as np

from harness.engines.symbolic import SymbolicTree
from harness.files import robots
from harness.report.site import build_site
from tests.test_robots_export import EXPORT, QUARTER, TRUNCATED

SYMBOLIC = f"pinocchio-{robots.SYMBOLIC}"
TWO = """<?xml version="1.0"?>
<robot name="two">
  <link name="base"/>
  <link name="upper"><inertial><origin xyz="0.2 0.01 -0.02" rpy="0.3 -0.2 0.5"/><mass value="1.5"/>
    <inertia ixx="0.004" ixy="0.0003" ixz="0" iyy="0.02" iyz="0.0001" izz="0.02"/></inertial></link>
  <link name="sensor"><inertial><origin xyz="0.05 0 0.03"/><mass value="0.2"/>
    <inertia ixx="0.0002" ixy="0" ixz="0" iyy="0.0003" iyz="0" izz="0.0004"/></inertial></link>
  <link name="lower"><inertial><origin xyz="0.15 0 0"/><mass value="0.8"/>
    <inertia ixx="0.002" ixy="0" ixz="0" iyy="0.006" iyz="0" izz="0.006"/></inertial></link>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/><axis xyz="1 0 0"/>
    <origin xyz="0 0 0.1" rpy="0 {twist} 0"/><limit lower="-3" upper="3" effort="10" velocity="5"/></joint>
  <joint name="mount" type="fixed"><parent link="upper"/><child link="sensor"/><origin xyz="0.3 0 0.05"/></joint>
  <joint name="elbow" type="continuous"><parent link="sensor"/><child link="lower"/><axis xyz="0 1 0"/>
    <origin xyz="0.1 0 0"/></joint>
</robot>
"""
"""Two joints, a rotated inertial, a fixed link lumped, a quarter turn (``twist``): small enough to derive in a
second (the three-joint arm of the exporter's tests takes ~10 s with an empty cache)."""


def _sweep(tmp_path, text, name="two", states=4):
    path = tmp_path / f"{name}.urdf"
    path.write_text(text)
    record = robots.sweep_robot((name, str(path), states, 0, None, True))
    return record, {p["pair"]: p for p in record["pairs"]}


def test_symbolic_pair_only_when_asked_and_agrees_on_the_double_pendulum(tmp_path):
    path = robots.select(["double_pendulum"])["double_pendulum"]
    plain = robots.sweep_robot(("double_pendulum", str(path), 3, 0))
    assert SYMBOLIC not in {p["pair"] for p in plain["pairs"]}
    assert SYMBOLIC not in robots.document([plain], 3, 0, 1.0, 1, "test")["pairs"]
    record = robots.sweep_robot(("double_pendulum", str(path), 3, 0, None, True))
    p = next(p for p in record["pairs"] if p["pair"] == SYMBOLIC)
    assert p["verdict"] == robots.AGREE and p["worst"]["ratio"] <= robots.MARGIN
    assert {c["quantity"] for c in p["checks"]} >= {"M", "bias", "Cqd", "g", "qdd", "mass", "first moment of mass",
                                                    "inertia"}
    facts = record["engines"][robots.SYMBOLIC]
    assert facts["nv"] == 2 and "Christoffel" in facts["derivation"] and "compile s" in facts
    doc = robots.document([record], 3, 0, 1.0, 1, "harness robots --symbolic")
    assert SYMBOLIC in doc["pairs"] and doc["summary"][SYMBOLIC]["agree"] == 1

    out = tmp_path / "reports"
    out.mkdir()
    robots.write(doc, out)
    result = build_site(out, progress=open("/dev/null", "w"))
    assert "robots/double_pendulum.html" in result["pages"] and not result["failed"]
    page = (out / "robots" / "double_pendulum.html").read_text()
    for text in ("our symbolic derivation", "agree", "Stepping", "Findings", "joint damping/friction",
                 'href="../robots.html"', 'href="../index.html"'):
        assert text in page, text
    assert 'href="robots/double_pendulum.html"' in (out / "robots.html").read_text()
    for target in re.findall(r'href="([^"#]+)', page):   # every link of the page resolves inside the report
        assert target.startswith("data:") or (out / "robots" / target).resolve().is_file(), target


def test_symbolic_agrees_on_a_small_arm_and_refuses_what_from_urdf_refuses(tmp_path):
    """A rotated inertial, a fixed link lumped, the file's quarter turn exact: agree. A tensor violating
    A + B >= C: our System refuses it (as instantiate does for our MJCF): not compared, the reason given."""
    _, pairs = _sweep(tmp_path, TWO.format(twist=QUARTER))
    assert pairs[SYMBOLIC]["verdict"] == robots.AGREE and pairs[SYMBOLIC]["cause"] is None
    assert pairs[EXPORT]["verdict"] == robots.AGREE
    text = TWO.format(twist="0").replace('ixx="0.002" ixy="0" ixz="0" iyy="0.006" iyz="0" izz="0.006"',
                                         'ixx="0.001" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.02"')
    _, pairs = _sweep(tmp_path, text)
    assert pairs[EXPORT]["verdict"] == pairs[SYMBOLIC]["verdict"] == robots.NOT_COMPARED
    assert "triangle inequality" in pairs[SYMBOLIC]["error"]


def test_a_snapped_quarter_turn_is_a_proven_cause_of_the_symbolic_pair(tmp_path):
    record, pairs = _sweep(tmp_path, TWO.format(twist=TRUNCATED))
    p = pairs[SYMBOLIC]
    assert p["verdict"] == robots.DISAGREE_EXPLAINED and p["worst"]["ratio"] > 1
    assert p["cause"]["proven"] and p["cause"]["after"] <= robots.MARGIN
    assert "our symbolic derivation agrees" in p["cause"]["cause"] and TRUNCATED in p["cause"]["cause"]


def test_a_derivation_defect_stays_open(tmp_path, monkeypatch):
    """The pair is not blind: gravity torques off by 1e-9 of their size (emulated) disagree without a cause."""
    real = SymbolicTree.terms

    def defective(self, theta, theta_dot, base=None, forward=True):
        out = real(self, theta, theta_dot, base, forward)
        out["bias"] = out["bias"] + 1e-9 * out["g"] if forward else out["bias"] * (1 + 1e-9)
        if forward:
            out["g"] = out["g"] * (1 + 1e-9)
        return out

    monkeypatch.setattr(SymbolicTree, "terms", defective)
    record, pairs = _sweep(tmp_path, TWO.format(twist=QUARTER))
    p = pairs[SYMBOLIC]
    assert p["verdict"] == robots.DISAGREE_OPEN and p["cause"] is None
    assert {c["quantity"] for c in p["checks"] if not c["passed"]} >= {"g"}
    assert robots.document([record], 4, 0, 1.0, 1, "test")["open"] == [f"two {SYMBOLIC}"]


def test_joints_matched_by_name(tmp_path):
    """Our coordinates are in the file's joint order; the view follows the reference's order by name."""
    path = tmp_path / "two.urdf"
    path.write_text(TWO.format(twist=QUARTER))
    system = robots.our_system(robots.load_robot("two", path))
    gravity = np.array([0, 0, -9.81])
    swapped = SymbolicTree(system, ["elbow", "shoulder"], gravity)
    straight = SymbolicTree(system, ["shoulder", "elbow"], gravity)
    theta, rate = np.array([0.3, -0.5]), np.array([1.1, -0.4])
    a, b = swapped.terms(theta, rate), straight.terms(theta[::-1], rate[::-1])
    for q in ("M", "Cqd", "g", "qdd"):
        expected = b[q][::-1, ::-1] if q == "M" else b[q][::-1]
        assert np.array_equal(a[q], expected), q
    parts = swapped.subtree_parts(theta)
    assert len(parts["shoulder"]) == 2 and len(parts["elbow"]) == 1
