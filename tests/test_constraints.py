"""Closed chains and couplings with their constraints inside the engines (harness/scenes/phenomena/closures.py)."""

import numpy as np
import pytest
import sympy as sp

import models
from harness.scenes.phenomena import closures as constraints
from harness.scenes import simulate as sim
from harness.derivation.kinematics import link_poses, point_position
from harness.modeling.scenes import Scene, effects_of

CONSTRAINED = [name for name, s in models.catalogue().items() if constraints.constrained(s)]


def _scene(system):
    """A scene with every effect: the pruned system is the catalogue's, so its derivation is shared."""
    return Scene("probe", "probe", tuple(0.1 for _ in system.coordinates), tuple(0.0 for _ in system.coordinates),
                 1.0, effects_of(system))


@pytest.mark.parametrize("name", CONSTRAINED)
def test_every_constrained_map_is_couplings_and_closures(name):
    """Each extra tree joint is an affine coupling or is matched by a declared closure."""
    system = models.get(name)
    dyn = sim.Dynamics(system, _scene(system), "symbolic")
    found = constraints.couplings(system, dyn)
    assert len(found) + len(system.closures) == len(system.joints) - len(system.coordinates)


def test_a_map_the_engines_cannot_impose_is_said_and_its_dynamics_still_checked():
    """A point on a circle written with two prismatic joints, ``x = R sin θ``, ``z = R cos θ``: no tree joint is θ
    or an affine function of it, and a circle is not a closure's plane, so the engines cannot hold the tree to the
    map. The scene says so, with the fix, and still checks every engine's mapped forward dynamics (it had failed
    with "the map's affine rows do not determine the lecture coordinates")."""
    from harness.errors import ModelError
    from harness.modeling import WORLD, Coordinate, Gravity, Joint, Link, Parameter, System, standard_gravity
    from harness.scenes.trajectories import run_scene

    m, R = Parameter("m", 1.0, "kg", "particle"), Parameter("R", 1.0, "m", "radius of the circle")
    theta = Coordinate("theta", "rad", "angle from the top", range=(-1.0, 1.0))
    system = System(name="circle_xz", title="a particle on a circle", lecture="test", coordinates=(theta,),
                    links=(Link("slider_x", 0), Link("particle", m)),
                    joints=(Joint("x", "prismatic", WORLD, "slider_x", axis="x", phi=R * sp.sin(theta)),
                            Joint("z", "prismatic", "slider_x", "particle", axis="z", phi=R * sp.cos(theta))),
                    gravity=Gravity(standard_gravity(), (0, 0, -1)))
    scene = Scene("slides", "from near the top", (0.1,), (0.0,), 0.5, {"gravity"})
    dyn = sim.Dynamics(system, scene, "symbolic")
    assert "make each lecture coordinate a tree joint" in constraints.not_imposable(system, dyn)
    with pytest.raises(ModelError, match="affine rows do not determine the lecture coordinates"):
        constraints.couplings(system, dyn)
    result = run_scene(system, scene)
    assert result.notes["constrained tree in the engines"].startswith("not simulated: the map's affine rows")
    assert {c.source for c in result.checks if c.name.startswith("trajectory")} == {"pinocchio", "mujoco"}
    assert all(c.passed for c in result.checks), [c for c in result.checks if not c.passed]


def test_drive_train_coupling_is_the_gear_ratio():
    system = models.get("drive_train")
    dyn = sim.Dynamics(system, _scene(system), "symbolic")
    (coupling,) = constraints.couplings(system, dyn)
    assert (coupling.dependent, coupling.independent) == ("phi_m", "phi_1")
    assert coupling.ratio == pytest.approx(system.default_parameters()["i_g"], rel=1e-15)


@pytest.mark.parametrize("name", [n for n in CONSTRAINED if models.get(n).closures])
def test_the_map_keeps_the_closure(name):
    """The nonlinear map solves the declared closed chain: nᵀ p(point) = value for every q (symbolically
    at random q)."""
    system = models.get(name)
    poses = link_poses(system)
    subs_map = dict(zip(system.theta, system.phi))
    rng = np.random.default_rng(0)
    params = system.default_parameters()
    for closure in system.closures:
        height = (sp.Matrix(closure.normal).T * point_position(poses, closure.point))[0] - closure.value
        height = height.subs(subs_map)
        for _ in range(5):
            values = {c.symbol: rng.uniform(*(c.range or (-0.3, 0.3))) for c in system.coordinates}
            values.update({p.symbol: params[p.name] for p in system.parameters})
            assert abs(float(height.subs(values))) < 1e-12


def test_pinocchio_kkt_keeps_the_toggle_press_closed():
    system, scene = models.get("toggle_press"), models.scenes("toggle_press")[0]
    tr = constraints.pinocchio_constrained(system, scene, horizon=0.2)
    ref = sim.integrate(system, scene, "symbolic")
    assert tr.notes["drift"] < constraints.DRIFT_TOL
    assert sim.max_error(tr, ref) < 1e-6


def test_the_governors_open_tree_moves_as_its_constrained_tree():
    """Its coupling proved inactive (harness.scenes.effects.constraint_rows_idle), the open tree without the
    coupling row — Pinocchio's pin.aba, MuJoCo with its equality and constraint flags off — follows the constrained
    tree and stays on the constraint by itself (its drift at round-off)."""
    system, scene = models.get("governor"), next(s for s in models.scenes("governor") if s.name == "spin_up")
    closed, open_tree = (constraints.pinocchio_constrained(system, scene, horizon=1.0, rows=rows)
                         for rows in (True, False))
    assert sim.max_error(open_tree, closed) < 1e-7 and open_tree.notes["drift"] < 1e-12
    assert open_tree.evaluations < closed.evaluations   # no step limit for a stabilization it does not have
    dt = scene.horizon / sim.grid_steps(scene, 4000)
    closed, open_tree = (constraints.mujoco_constrained(system, scene, dt, horizon=1.0, rows=rows)
                         for rows in (True, False))
    assert sim.max_error(open_tree, closed) < 1e-9
    assert constraints.rows_of(system, scene) == ["coupling alpha_2 = -2 alpha_1"]
