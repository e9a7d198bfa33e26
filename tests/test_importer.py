"""MuJoCo's own URDF importer against our MJCF and Pinocchio (harness/files/importer.py), and that the comparison
sees the known importer defects when they are there (emulated on the rotated-inertials test model)."""

import json

import pytest

import models
from harness import cli
from harness.files import importer

QUANTITIES = set(importer.QUANTITIES)


def test_rotated_inertial_frames_agree_with_pinocchio():
    (path,) = importer.FIXTURES
    record = importer.compare_urdf(path, path.read_text())
    assert record["loaded"] and record["refused"] is None
    assert {c["quantity"] for c in record["checks"]} == QUANTITIES
    assert record["passed"], record["findings"]


def test_known_importer_defects_would_be_found():
    controls = importer.controls(states=5)
    assert [c["defect"] for c in controls] == list(importer.CONTROLS)
    for control in controls:
        assert control["detected"], control
        assert control["max_error"]["M"] > 1e-3 and control["max_error"]["inertia"] > 1e-3


@pytest.mark.parametrize("name, refused", [("planar_manipulator", False), ("spherical_pendulum", True)])
def test_import_of_our_urdf_matches_our_mjcf(name, refused):
    record = importer.compare_system(models.get(name))
    assert (record["refused"] is not None) == refused
    assert record["loaded"] and record["passed"], record["findings"]


def test_importer_command_writes_json_and_markdown(tmp_path, capsys):
    assert cli.main(["importer", "pendulum", "--states", "3", "--out", str(tmp_path)]) == 0
    doc = json.loads((tmp_path / "importer.json").read_text())
    assert doc["schema"] == importer.SCHEMA and doc["states"] == 3
    assert [r["model"] for r in doc["models"]][:2] == ["pendulum", "rotated_inertials"]
    assert doc["summary"]["agree"] == len(doc["models"]) and all(c["detected"] for c in doc["controls"])
    assert "| pendulum |" in (tmp_path / "importer.md").read_text()


def test_edge_cases_of_the_importer():
    """Legal edits of the test model: the importer agrees with Pinocchio except for a fixed link lighter than
    MuJoCo's mjMINVAL (1e-15 kg) that still has an inertia tensor — MuJoCo drops that inertia when it fuses the
    link into its parent, Pinocchio keeps it (a finding, in reports/importer.md)."""
    by_name = {p["probe"]: p for p in importer.probes(states=5)}
    assert set(by_name) == set(importer.PROBES)
    light = by_name.pop("fixed link lighter than mjMINVAL, with rotational inertia")
    assert light["loaded"] and not light["agrees"] and light["max_error"]["inertia"] > 1e-3
    assert all(p["loaded"] and p["agrees"] for p in by_name.values()), by_name


def test_our_files_with_an_explained_compiler_warning_are_compared():
    """The tower crane's MJCF and URDF make MuJoCo warn at qpos0 (M singular there, in Pinocchio too: explained,
    as the conformance run accepts it): compared, not dropped as 'not compared'; the Euler top's import differs
    in M by the bound on its two massless gimbal links, which our MJCF fuses: within what that bound moves M by
    (``importer.bound_allowances``; a finding before M had that allowance)."""
    crane = importer.compare_system(models.get("tower_crane"), states=5)
    assert crane["error"] is None and crane["passed"], crane["error"] or crane["findings"]
    assert any("explained: MuJoCo's compiler evaluates M at qpos0" in a for a in crane["adjustments"])
    top = importer.compare_system(models.get("euler_top"))   # its M within what the bound moves it by
    M = next(c for c in top["checks"] if c["quantity"] == "M")
    assert top["error"] is None and top["passed"] and M["allowance"] > 0 and M["ratio"] <= 1
