"""``harness robots``: the sweep over example-robot-data on a fixed-base arm and a floating-base quadruped, with
the real engines; joints matched by name and the free-joint convention mapped (both shown by controls)."""

import json

import numpy as np
import pytest
from lxml import etree

from harness import run
from harness.cli import main
from harness.engines.base import FREE_JOINT
from harness.engines.mujoco_engine import MujocoModel, add_free_joint
from harness.engines.pinocchio_engine import PinocchioModel, load_urdf, moving_joints
from harness.files import importer, robots

pytestmark = pytest.mark.skipif(not robots.available(), reason="example-robot-data is not installed")
ARM, FLOATING = "ur5_robot", "solo12"


def test_sweep_records_and_files(tmp_path, capsys):
    assert main(["robots", ARM, FLOATING, "--out", str(tmp_path), "--states", "4"]) == 0
    out = capsys.readouterr().out
    assert f"{ARM}: 6 dof, fixed; pinocchio-mujoco agree" in out
    assert f"{FLOATING}: 18 dof, floating; pinocchio-mujoco agree" in out
    doc = json.loads((tmp_path / "robots.json").read_text())
    assert doc["schema"] == robots.SCHEMA
    assert doc["pairs"] == ["pinocchio-mujoco", "pinocchio-drake", "pinocchio-mujoco (our export)"]
    by_name = {r["robot"]: r for r in doc["robots"]}
    for name, dof, base in ((ARM, 6, "fixed"), (FLOATING, 18, "floating")):
        r = by_name[name]
        assert (r["dof"], r["base"]) == (dof, base)
        pair = r["pairs"][0]
        assert pair["verdict"] == "agree" and pair["worst"]["ratio"] <= 1
        assert {c["quantity"] for c in pair["checks"]} >= {"M", "Cqd", "g", "qdd", "mass", "inertia"}
        drake = r["pairs"][1]
        assert drake["pair"] == "pinocchio-drake" and drake["verdict"] == "agree" and drake["worst"]["ratio"] <= 0.1
        assert {c["quantity"] for c in drake["checks"]} >= {"M", "Cqd", "g", "qdd", "mass", "inertia"}
        assert r["engines"]["mujoco"]["step"]["steps"] == 500
        assert r["engines"]["mujoco"]["step"]["warnings"] == []
        assert r["seconds"] is not None
        assert any(f["kind"] == "geometry removed" for f in r["findings"])
    checks = [c for r in doc["robots"] for p in r["pairs"] for c in p["checks"]]
    assert all(("worst_state" in c) == (not c["passed"]) for c in checks)   # a state only as a counterexample
    for pair in (p for r in doc["robots"] for p in r["pairs"] if p["checks"]):  # the worst of each quantity kept
        assert max(c["ratio"] for c in pair["checks"]) == pytest.approx(pair["worst"]["ratio"])
    ours = by_name[ARM]["pairs"][2]      # our export: the file's truncated quarter turns, snapped (proven)
    assert ours["verdict"] == "disagree-explained" and ours["cause"]["proven"] and "1.57079632679" in \
        ours["cause"]["cause"]
    assert by_name[FLOATING]["pairs"][2]["verdict"] == "not compared"
    assert doc["open"] == []
    md = (tmp_path / "robots.md").read_text()
    assert f"| [{ARM}](robots/{ARM}.html) | 6 | fixed | agree | agree | disagree-explained |" in md   # its page linked
    assert f"| [{FLOATING}](robots/{FLOATING}.html) | 18 | floating | agree | agree | not compared (out of scope) |" in md


def test_unknown_robot_is_one_line(capsys):
    assert main(["robots", "no_such_robot"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: unknown robot(s) no_such_robot") and "Traceback" not in err


def _floating_models(mujoco_text=None):
    path = robots.available()[FLOATING]
    text = path.read_text()
    pmodel = load_urdf(text, FLOATING, floating=True)
    joints = moving_joints(pmodel, FREE_JOINT)
    mj, _, bound = importer.load_import(importer.without_geometry(mujoco_text or text), FLOATING, add_free_joint)
    return pmodel, joints, mj, bound


def _mujoco(mj, joints, cls=MujocoModel, gravity=None):
    view = cls.loaded(mj, joints, FREE_JOINT)
    view.set_gravity(gravity)
    return view


def test_joints_matched_by_name_not_by_order():
    """MuJoCo reads the file with its joints (and links) in reverse order: its dof order is not Pinocchio's, the
    comparison by name still agrees; handing MuJoCo's view the names in another order than the reference's is
    seen (the views are not compared by position)."""
    text = robots.available()[FLOATING].read_text()
    root = etree.fromstring(text.encode())
    for tag in ("joint", "link"):
        elements = root.findall(tag)
        for el in elements:
            root.remove(el)
        for el in reversed(elements):
            root.append(el)
    pmodel, joints, mj, bound = _floating_models(etree.tostring(root, encoding="unicode"))
    ref = PinocchioModel.loaded(pmodel, joints, FREE_JOINT)
    imported = _mujoco(mj, joints, gravity=ref.gravity)
    mj_order = sorted(joints, key=lambda j: imported.address(j)[1])
    assert mj_order != joints
    checks = importer.compare(imported, ref, joints, set(), 3, bound=bound, forward=True)
    assert all(c["passed"] for c in checks)
    shuffled = joints[3:] + joints[:3]
    wrong = importer.compare(_mujoco(mj, shuffled, gravity=ref.gravity), ref, joints, set(), 3, bound=bound,
                             forward=True)
    assert not all(c["passed"] for c in wrong)


class _WorldLinearAsLocal(MujocoModel):
    """MuJoCo's free-joint velocity taken as Pinocchio's (linear velocity in local axes): the wrong convention."""

    def _map(self):
        n = len(self.view_dofs)
        return np.eye(n), np.zeros(n)


def test_free_joint_convention_is_mapped():
    pmodel, joints, mj, bound = _floating_models()
    ref = PinocchioModel.loaded(pmodel, joints, FREE_JOINT)
    wrong = importer.compare(_mujoco(mj, joints, _WorldLinearAsLocal, ref.gravity), ref, joints, set(), 3,
                             bound=bound, forward=True)
    failed = {c["quantity"] for c in wrong if not c["passed"]}
    assert {"M", "qdd"} <= failed


def test_sweep_in_parallel_keeps_the_order():
    doc, written = run.robots([FLOATING, ARM], states=2, jobs=2)
    assert [r["robot"] for r in doc["robots"]] == [FLOATING, ARM] and written == []
    assert doc["summary"]["pinocchio-mujoco"]["agree"] == 2


def test_drake_floating_joint_convention_is_mapped():
    """Drake's QuaternionFloatingJoint (angular then linear velocity, world axes) mapped to Pinocchio's free flyer
    agrees; taken as Pinocchio's own coordinates (no map) it is seen."""
    from harness.engines.drake_engine import DrakeImport, load_urdf_plant

    text = robots.available()[FLOATING].read_text()
    pmodel = load_urdf(text, FLOATING, floating=True)
    joints = moving_joints(pmodel, FREE_JOINT)
    ref = PinocchioModel.loaded(pmodel, joints, FREE_JOINT)
    plant, _ = load_urdf_plant(importer.without_geometry(text), FLOATING, FREE_JOINT, ref.gravity)
    checks = importer.compare(DrakeImport(plant, joints, FREE_JOINT), ref, joints, set(), 3, forward=True)
    assert all(c["passed"] for c in checks)

    class Unmapped(DrakeImport):
        def _map(self):
            n = len(self.view_dofs)
            return np.eye(n), np.zeros(n)

    wrong = importer.compare(Unmapped(plant, joints, FREE_JOINT), ref, joints, set(), 3, forward=True)
    assert {"M", "qdd"} <= {c["quantity"] for c in wrong if not c["passed"]}
