"""Every scene of every system: trajectories of Pinocchio and MuJoCo (scipy-integrated forward dynamics and
MuJoCo's own RK4) against the confirmed symbolic reference, invariants, and pruning (harness/trajectories.py
states the tolerances and their reasons)."""

import pytest

import models
from harness.trajectories import run_scene

SCENES = [(name, scene) for name in models.catalogue() for scene in models.scenes(name)]


@pytest.mark.parametrize("name, scene", SCENES, ids=[f"{n}-{s.name}" for n, s in SCENES])
def test_scene(name, scene):
    result = run_scene(models.get(name), scene)
    failed = [c for c in result.checks if c[2] > c[3]]
    assert not failed, failed
    assert any(c[0].startswith("trajectory") for c in result.checks)
