"""Constraint forces of a map θ = φ(q) (ropes, rolling, gears): the tree's balance by bodies (Newton–Euler in the
tree joints) agrees with the Lagrange derivation, the declared forces are checked for doing no work and for
completeness, the balance rows the forces are not solved from hold too, cut forces of a map-coupled system add up
to the external forces, and claims at rest and typos of a force's name are classified."""

import dataclasses

import numpy as np
import pytest
import sympy as sp

import models
from harness.compare.claims import classify, on_motion
from harness.derivation import bodies
from harness.derivation.derive import derive
from harness.modeling import Claim, ConstraintForce, Point

# systems with a map θ = φ(q) (and so constraint forces) and two trees, the balance checked on each
BALANCED = ["drum_hoist", "drawbridge", "pulley", "drive_train", "cable_pulley", "toggle_press", "pendulum",
            "planar_manipulator"]
DECLARED = ["drum_hoist", "drawbridge", "pulley", "drive_train", "cable_pulley"]


def _numeric(system, rng):
    """``expr`` at a random state, random accelerations and the default parameters."""
    q = {s: v for s, v in zip(system.q, 0.3 + 0.5 * rng.uniform(-1, 1, len(system.q)))}
    values = {**q, **dict(zip(system.qd, rng.uniform(-1, 1, len(system.q)))),
              **{c.accel: v for c, v in zip(system.coordinates, rng.uniform(-1, 1, len(system.q)))},
              **{p.symbol: float(p.default) for p in system.parameters},
              **dict(zip(system.u, rng.uniform(-1, 1, len(system.u))))}
    return values


@pytest.mark.parametrize("name", BALANCED)
def test_the_balance_of_the_bodies_is_the_lagrange_derivation(name):
    """``(∂φ/∂q)ᵀ`` of the Newton–Euler balance in the tree joints is ``M q̈ + C q̇ + g − f_np`` (5.58): two
    derivations that share only the kinematics."""
    system = models.get(name)
    d = derive(system)
    qdd = sp.Matrix([c.accel for c in system.coordinates])
    residual = system.phi.jacobian(system.q).T * bodies.joint_space_balance(system) - (
        d.M * qdd + d.C * sp.Matrix(system.qd) + d.g - d.f_np)
    rng = np.random.default_rng(0)
    for _ in range(3):
        at = _numeric(system, rng)
        scale = max(1.0, float(np.max(np.abs(np.array(d.M.xreplace(at).evalf(), dtype=float)))))
        assert float(np.max(np.abs(np.array(residual.xreplace(at).evalf(), dtype=float)))) < 1e-10 * scale


@pytest.mark.parametrize("name", DECLARED)
def test_every_row_of_the_balance_holds_with_the_solved_forces(name):
    """λ is solved from a square block of rows; on the motion the other rows must hold too (the declared forces
    are the map's constraint forces, not a fit)."""
    system = models.get(name)
    forces = bodies.constraint_forces(system)
    lam = sp.Matrix([forces[cf.name] for cf in system.constraint_forces])
    residual = (bodies.joint_space_balance(system) - bodies.constraint_directions(system) * lam).xreplace(
        on_motion(system))
    rng = np.random.default_rng(1)
    for _ in range(3):
        at = _numeric(system, rng)
        values = np.array(residual.xreplace(at).evalf(), dtype=float)
        assert float(np.max(np.abs(values))) < 1e-9 * max(1.0, float(np.max(np.abs(np.array(
            bodies.joint_space_balance(system).xreplace(on_motion(system)).xreplace(at).evalf(), dtype=float)))))


def test_a_declaration_that_does_work_or_misses_a_constraint_is_refused():
    hoist = models.get("drum_hoist")
    rope, rolling = hoist.constraint_forces
    (drum, _, along), block = rope.forces           # the rope on the drum's centre, not on its inner radius
    off_centre = dataclasses.replace(rope, forces=((drum, Point("drum_centre"), along), block))
    with pytest.raises(ValueError, match="do work"):
        bodies.constraint_forces(dataclasses.replace(hoist, constraint_forces=(off_centre, rolling)))
    with pytest.raises(ValueError, match="declare 2 constraint force"):
        bodies.constraint_forces(dataclasses.replace(hoist, constraint_forces=(rope,)))
    with pytest.raises(ValueError, match="does not declare"):
        bodies.joint_force(dataclasses.replace(hoist, constraint_forces=()), "x_T")


def test_cut_forces_of_a_map_coupled_system_balance_the_external_forces():
    """The drawbridge held at rest by rope 2: the bearings' forces on the three bodies (rope 1 and the
    counterweight's arm are internal and must cancel) carry the weights and rope 2's pull."""
    bridge = models.get("drawbridge")
    claim = Claim("(t-rest)", "parameter", 0, reference=0, at="holding:f_S2")
    from harness.compare.claims import at_rest

    rest = at_rest(bridge, claim)
    total = sum((bodies.joint_force(bridge, j) for j in ("phi_B", "phi_A", "phi_m")), sp.zeros(3, 1))
    g = bridge.parameter("g").symbol
    weights = sum(sp.sympify(link.mass) for link in bridge.links) * g
    pull = sp.Symbol("f_S2", real=True)
    balance = (total - sp.Matrix([0, weights + pull, 0])).xreplace(rest)
    assert sp.simplify(balance) == sp.zeros(3, 1)


def test_a_misnamed_force_at_rest_is_a_notation_typo_of_the_defined_force():
    """(A.75) prints ``F_S`` for the rope force ``f_S`` that (A.70) defines: the renaming search includes the
    printed symbols other claims define, and the claim is checked at rest at the equilibrium."""
    hoist = models.get("drum_hoist")
    printed = models.claims("drum_hoist")
    by_name = {c.equation: c for c in printed}
    verdict = classify(hoist, by_name["(A.75)"], examples=20, claims=printed)
    assert verdict.classification == "notation typo" and verdict.renaming == {"F_S": "f_S"}
    r_i, r_a, m_B, g = (hoist.parameter(n).symbol for n in ("r_i", "r_a", "m_B", "g"))
    wrong = Claim("(t-sign)", "constraint:f_t", r_i / r_a * m_B * g, at="equilibrium")
    assert classify(hoist, wrong, examples=20, claims=[wrong]).classification == "erratum"
    moving = Claim("(t-static-in-motion)", "constraint:f_S", m_B * g)   # the static force, claimed in motion
    assert classify(hoist, moving, examples=20, claims=[moving]).classification == "erratum"


def test_at_rest_is_checked_when_the_claim_is_made():
    with pytest.raises(ValueError, match="at="):
        Claim("(t-at)", "constraint:f_S", 0, at="resting")
    with pytest.raises(ValueError, match="at="):
        Claim("(t-at-2)", "equilibrium", 0, at="equilibrium")


def test_a_constraint_force_acts_on_known_links_only():
    from harness.errors import ModelError

    hoist = models.get("drum_hoist")
    stray = ConstraintForce("f_x", forces=(("nowhere", Point("drum"), (1, 0, 0)),))
    with pytest.raises(ModelError, match="unknown link"):
        dataclasses.replace(hoist, constraint_forces=(*hoist.constraint_forces, stray))
