"""The committed urdf/ folder is what `harness export` writes now; the numeric tree it is written from."""

from pathlib import Path

import mujoco
import numpy as np
import pytest
import sympy as sp
from hypothesis import assume, given, settings, strategies as st

import models
from harness.compare.strategies import parameters
from harness.compare.roundtrip import rpy_matrix
from harness.errors import ModelError
from harness.export.files import system_files
from harness.export.mjcf import equivalent_box, equivalent_cylinder
from harness.export.numeric import instantiate
from harness.modeling.system import Coordinate, Joint, Link, Parameter, System

URDF_DIR = Path(__file__).resolve().parent.parent / "urdf"


def test_committed_exports_are_current():
    files = {name: text for system in models.catalogue().values() for name, text in system_files(system).items()}
    stale = [name for name, text in files.items()
             if not (URDF_DIR / name).exists() or (URDF_DIR / name).read_text() != text]
    assert not stale, f"stale exports {stale}: run `harness export` and commit urdf/"
    extra = {p.name for p in URDF_DIR.iterdir()} - set(files)
    assert not extra, f"urdf/ has files no system exports: {sorted(extra)}"


@settings(max_examples=200, deadline=None)
@given(mass=st.floats(1e-3, 1e3), half=st.tuples(*[st.floats(1e-3, 10.0)] * 3),
       rpy=st.tuples(*[st.floats(-3.2, 3.2)] * 3), diagonal=st.booleans())
def test_the_visual_box_has_the_body_s_mass_and_inertia(mass, half, rpy, diagonal):
    """``equivalent_box``: the homogeneous cuboid (3.128) of a body's mass and inertia tensor, built here from a
    cuboid (its half edges, any orientation; a diagonal tensor in the body's axes), gives that tensor back. Bound,
    relative to the largest moment: the eigendecomposition's residual (``mju_eig3``, at most 8.7e-15, measured
    over 20 000 random tensors) plus the round-off of ``I_j + I_k − I_i`` and of reassembling (a few ε), with a
    factor 100 to spare. (A half edge itself is ill-conditioned where it is small: ``c²`` is the difference of
    moments of the size of ``a²``.)"""
    a, b, c = half
    moments = mass / 3.0 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])
    R = np.eye(3) if diagonal else rpy_matrix(np.array(rpy))
    inertia = R @ np.diag(moments) @ R.T
    got_half, quat = equivalent_box(mass, inertia)
    x, y, z = got_half
    got_moments = mass / 3.0 * np.array([y * y + z * z, x * x + z * z, x * x + y * y])
    Q = np.zeros(9)
    mujoco.mju_quat2Mat(Q, quat)
    Q = Q.reshape(3, 3)
    assert np.abs(Q @ np.diag(got_moments) @ Q.T - inertia).max() <= 1e-12 * moments.max()
    if diagonal:  # in the body's axes, no rotation written
        assert quat.tolist() == [1.0, 0.0, 0.0, 0.0]



@settings(max_examples=200, deadline=None)
@given(mass=st.floats(1e-3, 1e3), radius=st.floats(1e-3, 10.0), half=st.floats(0.0, 10.0), axis=st.integers(0, 2),
       rpy=st.tuples(*[st.floats(-3.2, 3.2)] * 3), diagonal=st.booleans())
def test_the_visual_cylinder_has_the_body_s_mass_and_inertia(mass, radius, half, axis, rpy, diagonal):
    """``equivalent_cylinder``: the homogeneous cylinder (3.122) of a tensor with two equal principal moments, built
    here from a cylinder (radius, half length, its axis along x, y or z, turned anyhow; a disc where the length is
    0), gives that tensor back, its own axis (the geom's z) along the cylinder's; a tensor with three different
    moments (a cuboid's) or three equal ones (a sphere's) has none. Bound as for the box (above)."""
    along, across = mass * radius**2 / 2.0, mass * (3.0 * radius**2 + 4.0 * half**2) / 12.0
    assume(abs(along - across) > 1e-6 * max(along, across))  # a cylinder whose tensor is a sphere's: drawn as one
    moments = np.full(3, across)
    moments[axis] = along
    R = np.eye(3) if diagonal else rpy_matrix(np.array(rpy))
    inertia = R @ np.diag(moments) @ R.T
    got_radius, got_half, quat = equivalent_cylinder(mass, inertia)
    got_along, got_across = mass * got_radius**2 / 2.0, mass * (3.0 * got_radius**2 + 4.0 * got_half**2) / 12.0
    Q = np.zeros(9)
    mujoco.mju_quat2Mat(Q, quat)
    Q = Q.reshape(3, 3)
    assert np.abs(Q @ np.diag([got_across, got_across, got_along]) @ Q.T - inertia).max() <= 1e-12 * moments.max()
    assert abs(abs(Q[:, 2] @ R[:, axis]) - 1.0) <= 1e-12 * moments.max() / abs(along - across)  # its gap (Davis-Kahan)
    assert equivalent_cylinder(mass, R @ np.diag([across, along, (across + along) * 0.7]) @ R.T) is None
    assert equivalent_cylinder(mass, R @ np.diag([along] * 3) @ R.T) is None


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


@pytest.mark.parametrize("modules", ["math", "numpy", None])
def test_compiled_functions_keep_every_float_constant(modules):
    """SymPy's printers write a 53-bit Float with 15 digits; the project's ``lambdify`` writes its float64."""
    from harness.derivation.lambdified import lambdify

    x = sp.Symbol("x")
    constants = [0.014107263642161838, 0.00039487729711917775, 1 / 12, -2.8e-241, 6.02214076e23]
    fn = lambdify([x], [c * x + sp.Float(c) for c in constants], modules=modules)
    assert [float(v) for v in fn(0.0)] == constants
    assert float(sp.lambdify([], sp.Float(constants[0]))()) != constants[0]  # why the printer is ours


def test_the_texts_of_a_tree_are_kept_with_their_warnings_and_written_again_when_damaged(tmp_path, monkeypatch):
    """What the engines load in a check (``exported_mjcf``, ``exported_urdf``) is ``mjcf_string`` and
    ``urdf_string`` of the tree, kept on disk under the tree's bits and our installation; the warnings writing the
    MJCF raised are logged again when it is read back (the tower crane's "Inertia matrix is too close to singular"
    at qpos0), a damaged entry is written again, another tree is another entry."""
    import harness.kept
    from harness.engines import warnings_log
    from harness.export import mjcf, urdf

    monkeypatch.setattr(harness.kept, "cache_dir", lambda: tmp_path / "derivations")
    system = models.get("tower_crane")
    tree = instantiate(system, system.default_parameters())
    write, written = mjcf.mjcf_string, []
    monkeypatch.setattr(mjcf, "mjcf_string", lambda t: written.append(t) or write(t))

    def exported(t=tree):
        with warnings_log.discarded():
            start = warnings_log.logged()
            text = mjcf.exported_mjcf(t)
            return text, warnings_log.messages_since(start)

    first = exported()
    with warnings_log.discarded():
        assert len(written) == 1 and first[0] == write(tree)
    assert len(first[1]) > 0 and all("too close to singular" in m for m in first[1])
    assert exported() == first and len(written) == 1          # read back: not written, the same warnings logged
    (entry,) = (tmp_path / "exports").glob("*-tower_crane.mjcf-*.json")
    entry.write_text(entry.read_text().replace("<body", "<body pos='1 0 0'", 1))   # damaged: the checksum fails
    assert exported() == first and len(written) == 2
    other = instantiate(system, {**system.default_parameters(), "m_L": 25.0})
    assert exported(other)[0] != first[0] and len(written) == 3   # another tree: another entry

    texts = {id(t): urdf._urdf_string(t) for t in (tree, other)}
    for t in (tree, other):
        assert urdf.exported_urdf(t) == texts[id(t)]
    monkeypatch.setattr(urdf, "_urdf_string", lambda t: pytest.fail("written again, not read back"))
    for t in (other, tree, other):
        assert urdf.exported_urdf(t) == texts[id(t)]
