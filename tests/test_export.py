"""The committed urdf/ folder is what `harness export` writes now; the numeric tree it is written from."""

from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings, strategies as st

import models
from harness.compare.strategies import parameters
from harness.errors import ModelError
from harness.export.files import export_files
from harness.export.numeric import instantiate
from harness.modeling.system import Coordinate, Joint, Link, Parameter, System

URDF_DIR = Path(__file__).resolve().parent.parent / "urdf"


def test_committed_exports_are_current():
    files = export_files(models.catalogue().values())
    stale = [name for name, text in files.items()
             if not (URDF_DIR / name).exists() or (URDF_DIR / name).read_text() != text]
    assert not stale, f"stale exports {stale}: run `harness export` and commit urdf/"
    extra = {p.name for p in URDF_DIR.iterdir()} - set(files)
    assert not extra, f"urdf/ has files no system exports: {sorted(extra)}"


# ----------------------------------------------------------------------- the numeric tree (instantiate)


def _substituted(system, params) -> list[tuple[str, float, float, float]]:
    """``(what, compiled number, SymPy's number, bound)`` of each link's and joint's entries: SymPy substitutes the
    values into the model's expression and evaluates it with 30 digits (then rounded to float64: half an ulp);
    ``bound`` is that half ulp plus the forward error bound of evaluating the expression in float64,
    ``k ε · magnitude`` (:func:`_magnitude`, ``k`` its operations plus one)."""
    tree = instantiate(system, params)
    subs = {system.parameter(k).symbol: sp.Float(v, 30) for k, v in params.items()}

    def entry(what, number, expr):
        expr = sp.sympify(expr)
        value = float(expr.xreplace(subs).evalf(30))
        bound = np.finfo(float).eps * ((sp.count_ops(expr) + 1) * _magnitude(expr, subs) + abs(value) / 2)
        return what, number, value, bound

    out = []
    for link, numeric in zip(system.links, tree.links):
        out += [entry(f"{link.name} mass", numeric.mass, link.mass)]
        out += [entry(f"{link.name} com", a, e) for a, e in zip(numeric.com, link.com_vector)]
        out += [entry(f"{link.name} inertia", a, e) for a, e in zip(numeric.inertia.ravel(), link.inertia.matrix)]
    for joint, numeric in zip(system.joints, tree.joints):
        out += [entry(f"{joint.name} origin", a, e) for a, e in zip(numeric.origin, joint.origin_vector)]
        out += [entry(f"{joint.name} rpy", a, e) for a, e in zip(numeric.rpy, joint.rpy)]
    return out


def _magnitude(expr, subs) -> float:
    """The magnitude of the terms ``expr`` is made of, to which the rounding error of its float evaluation is
    relative (Higham, *Accuracy and Stability*, §3.1: a sum or product of ``k`` operations is off by at most
    ``γ_k`` times the same evaluated with every term's absolute value): a sum's terms add up in absolute value, a
    product's factors multiply; a quotient, a power or a function is taken at its value (each one rounding, counted
    in ``k``). Where a lumped body's Steiner terms cancel (the Panda's hand: link 7's inertia), its value is far
    below this magnitude, and so is its precision relative to the value."""
    if expr.is_Add:
        return sum(_magnitude(a, subs) for a in expr.args)
    if expr.is_Mul:
        return float(np.prod([_magnitude(a, subs) for a in expr.args]))
    if expr.is_Pow and expr.exp.is_Integer and expr.exp > 0:
        return _magnitude(expr.base, subs) ** int(expr.exp)
    return abs(float(expr.xreplace(subs).evalf(30)))


@settings(max_examples=5)
@given(st.data())
def test_the_compiled_tree_is_sympys_substitution(data):
    """instantiate evaluates compiled functions of the parameters (float arithmetic, in another order than
    SymPy's): each number is SymPy's 30-digit value within the forward error bound of float64 arithmetic, the
    lumped bodies' Steiner terms included (the tower crane's tower, the rotating body, the Panda's hand). Measured
    over 40 draws of every system: at most 0.36 of the bound (planar_robot, a centre of mass)."""
    for system in models.catalogue().values():
        params = data.draw(parameters(system))
        for what, number, value, bound in _substituted(system, params):
            assert abs(number - value) <= bound, (system.name, what, number, value, bound)


def test_a_model_that_cannot_be_evaluated_at_its_parameters_is_one_clear_error():
    """A division by zero at admissible parameter values (two non-negative masses, both zero) is a ModelError
    naming the system, not a ZeroDivisionError from inside a compiled function."""
    m1 = Parameter("m_a", 1.0, "kg", "first mass", assumption="nonnegative")
    m2 = Parameter("m_b", 1.0, "kg", "second mass", assumption="nonnegative")
    length = Parameter("l_ab", 1.0, "m", "distance of the masses")
    x = Coordinate("x_ab", "m", "position")
    system = System(name="lumped", title="lumped", lecture="-", coordinates=(x,),
                    links=(Link("body", m1 + m2, (0, 0, length * m2 / (m1 + m2))),),
                    joints=(Joint("x_ab", "prismatic", "world", "body", axis="x"),))
    assert instantiate(system, {"m_a": 1.0, "m_b": 3.0, "l_ab": 2.0}).links[0].com[2] == 1.5
    with pytest.raises(ModelError, match="lumped: cannot evaluate the model at these parameter values"):
        instantiate(system, {"m_a": 0.0, "m_b": 0.0, "l_ab": 2.0})
