"""Unit tests of the modeling core: validation, kinematics (chapter 4), derivation (chapter 5), cache."""

import json
import pickle

import numpy as np
from hypothesis import given, strategies as st
import pytest
import sympy as sp

import models
from harness.derivation.derive import SYMBOLIC_FIELDS, christoffel, derive
from harness.errors import ModelError
from harness.export.numeric import check_inertia
from harness.derivation.kinematics import rotation, rpy_rotation
from harness.modeling import Claim, Scene, StickSlip, standard_gravity
from harness.modeling.claims import validate_claims
from harness.modeling.system import Coordinate, Gravity, Inertia, Input, Joint, JointInput, Link, Parameter, System

m, l, g = Parameter("m", 1.0, "kg", "mass"), Parameter("l", 1.0, "m", "length"), standard_gravity()
phi = Coordinate("phi", "rad", "angle")


def _pendulum(**changes):
    fields = dict(name="p", title="p", lecture="-", coordinates=(phi,), links=(Link("bob", m, (0, 0, -l)),),
                  joints=(Joint("phi", "revolute", "world", "bob", axis="x"),), gravity=Gravity(g, (0, 0, -1)))
    fields.update(changes)
    return System(**fields)


def test_elementary_rotations_match_4_9():
    a = sp.Symbol("a")
    assert rotation((0, 0, 1), a) == sp.Matrix([[sp.cos(a), -sp.sin(a), 0], [sp.sin(a), sp.cos(a), 0], [0, 0, 1]])
    general = rotation((0, 0.6, 0.8), a).subs(a, 0.4)
    assert np.allclose(np.array(general * general.T, dtype=float), np.eye(3))
    assert rpy_rotation((0, 0, sp.pi / 2)) == rotation((0, 0, 1), sp.pi / 2)


def test_pendulum_equation_3_111():
    d = derive(models.get("pendulum"), use_cache=False)
    m, l, g = sp.symbols("m l g", positive=True)
    phi = sp.Symbol("phi", real=True)
    assert sp.simplify(d.M[0, 0] - m * l**2) == 0
    assert sp.simplify(d.g[0] - m * g * l * sp.sin(phi)) == 0
    assert d.C == sp.zeros(1, 1)


def test_christoffel_symbols_are_symmetric_in_i_j():
    s = models.get("planar_manipulator")
    d = derive(s)
    q = s.q
    for k in range(2):
        for i in range(2):
            for j in range(2):
                assert sp.simplify(christoffel(d.M, q, i, j, k) - christoffel(d.M, q, j, i, k)) == 0


def test_cache_hit_and_corrupted_cache_is_rebuilt(tmp_path, monkeypatch):
    monkeypatch.setenv("HARNESS_CACHE_DIR", str(tmp_path))
    s = models.get("cart_pendulum")
    first = derive(s)
    assert not first.from_cache
    second = derive(s)
    assert second.from_cache and second.M == first.M
    (entry,) = tmp_path.glob("*.json")
    doc = json.loads(entry.read_text())
    doc["entries"]["M"] = doc["entries"]["M"].replace("2", "3")  # damage without fixing the checksum
    entry.write_text(json.dumps(doc))
    third = derive(s)
    assert not third.from_cache and third.M == first.M
    entry.write_text("{not json")
    assert not derive(s).from_cache


def _derive_slowly(name: str, start, cache: str) -> bool:
    """In a worker process: derive ``name`` (slowed by 1 s, so that the other worker asks while it is computing)
    once both workers are ready; whether this one computed it."""
    import os
    import time

    from harness.derivation import derive as derive_module

    os.environ["HARNESS_CACHE_DIR"] = cache
    uncached = derive_module.derive_uncached

    def slow(system):
        time.sleep(1.0)
        return uncached(system)

    derive_module.derive_uncached = slow
    system = models.get(name)
    start.wait()
    return not derive_module.derive(system).from_cache


def test_two_processes_deriving_the_same_model_derive_it_once(tmp_path):
    """Two test workers (or two commands at once) that need the same missing derivation: one derives it, the other
    waits for it and reads what it stored (cache.once), instead of deriving it too."""
    import multiprocessing

    context = multiprocessing.get_context("spawn")
    with context.Manager() as manager:
        start = manager.Barrier(2)
        with context.Pool(2) as pool:
            computed = pool.starmap(_derive_slowly, [("pendulum", start, str(tmp_path))] * 2)
    assert sorted(computed) == [False, True]
    assert len(list(tmp_path.glob("pendulum-*.json"))) == 1 and not list(tmp_path.glob("*.lock"))


@pytest.mark.parametrize("payload", [
    "__import__('os').system('touch {marker}')",                      # a call of a builtin
    "Add(Integer(1), Symbol('x').__class__)",                          # attribute access
    "Add('__import__(\"os\").system(\"touch {marker}\")', Integer(1))",  # a string SymPy would sympify (eval)
    "sympify('x')",                                                    # a SymPy function that is not a class
    "Add(*[Integer(k) for k in range(3)])",                            # any other syntax
])
def test_a_forged_cache_entry_runs_no_code(tmp_path, monkeypatch, payload):
    """The checksum detects damage, not tampering: an entry rewritten with a recomputed checksum is still read by
    a parser that accepts only what srepr writes, so the payload never runs and the derivation is rebuilt."""
    from harness.derivation import cache

    monkeypatch.setenv("HARNESS_CACHE_DIR", str(tmp_path / "cache"))
    marker = tmp_path / "ran"
    s = models.get("pendulum")
    first = derive(s)
    (entry,) = (tmp_path / "cache").glob("*.json")
    doc = json.loads(entry.read_text())
    doc["entries"]["M"] = payload.format(marker=marker)
    doc["sha256"] = cache.checksum(doc["entries"])  # the forger recomputes the checksum
    entry.write_text(json.dumps(doc))
    again = derive(s)
    assert not marker.exists()
    assert not again.from_cache and again.M == first.M


def test_a_symbolic_result_is_remembered_as_computed(tmp_path, monkeypatch):
    """cache.remembered: computed once, read back by later calls as the same tree (a lecture-notation name, the
    factored form ``factor_terms`` gave, ``−2 x`` which srepr writes as ``Mul(-1, 2, x)``), keyed by the code that
    computes it; a damaged entry is computed again."""
    from harness.derivation import cache

    monkeypatch.setenv("HARNESS_CACHE_DIR", str(tmp_path))
    x, inertia = sp.Symbol("x", real=True), sp.Symbol("I_zz^S", real=True)
    value = sp.Tuple(sp.Matrix([sp.factor_terms(x / 8 + inertia / 8), -2 * x]), sp.true)
    calls = []
    code = tmp_path / "code.py"
    code.write_text("one")

    def compute():
        calls.append(1)
        return value
    first = cache.remembered("demo", (code,), (x,), compute)
    second = cache.remembered("demo", (code,), (x,), compute)
    assert len(calls) == 1 and sp.srepr(first) == sp.srepr(second) == sp.srepr(value)
    cache.remembered("demo", (code,), (inertia,), compute)
    assert len(calls) == 2  # other inputs
    code.write_text("two")
    cache.remembered("demo", (code,), (x,), compute)
    assert len(calls) == 3  # other code
    for entry in tmp_path.glob("demo-*.json"):
        entry.write_text(entry.read_text().replace("Rational", "Integer"))
    assert cache.remembered("demo", (code,), (x,), compute) == value and len(calls) == 4


def test_per_body_derivation_is_cached_as_a_graph(tmp_path, monkeypatch):
    """A tree derived body by body (from ``PER_BODY_MIN_DOF`` = 6 DoF) is stored as its shared subexpressions and
    read back to the same expressions the cold run uses; a damaged replacement is detected and the derivation
    rebuilt. A 3-link chain with the threshold lowered takes the same path: compiling a 6-link chain's trees twice
    took 90 of the test's 98 s on a fresh clone."""
    from harness.bench.derivation import chain
    from harness.derivation import derive as derive_module
    from harness.derivation.derive import is_per_body

    assert is_per_body(chain(derive_module.PER_BODY_MIN_DOF)) and not is_per_body(chain(3))
    monkeypatch.setattr(derive_module, "PER_BODY_MIN_DOF", 3)
    monkeypatch.setenv("HARNESS_CACHE_DIR", str(tmp_path))
    s = chain(3)
    assert is_per_body(s)
    first = derive(s)
    assert not first.from_cache
    (entry,) = tmp_path.glob("*.json")
    doc = json.loads(entry.read_text())
    assert doc["replacements"] and all(name.startswith("_cse_") for name, _ in doc["replacements"])
    lazy = derive(s)  # the trees are built when first read: θ = q needs none of the replacements
    assert lazy.from_cache and "M" not in vars(lazy) and list(lazy.phi) == list(s.q) and not lazy._trees._shared
    assert "replacements" not in vars(lazy.graph)  # the graph's values too: built when a compiler needs them
    assert "M" in lazy._trees and not hasattr(lazy, "N") and "M" not in vars(lazy)
    second = derive(s)
    assert second.from_cache and second.M == first.M and second.C == first.C and second.g == first.g
    copy = pickle.loads(pickle.dumps(lazy))  # to another process: the trees and the graph's values built
    assert copy.M_dot == first.M_dot and copy.graph.replacements == lazy.graph.replacements
    _compiled_from_the_stored_graph_equals_compiled_from_the_trees(s, second)
    doc["replacements"][0][1] = doc["replacements"][0][1].replace("1", "2", 1)  # damage, checksum kept
    entry.write_text(json.dumps(doc))
    third = derive(s)
    assert not third.from_cache and third.M == first.M


def test_a_derivation_is_the_same_derived_or_loaded(tmp_path, monkeypatch):
    """A run that derives and a run that loads the cache use the same expressions, to the last node (and so the
    same compiled arithmetic): the Euler top's C was ``Mul(1/8, Add(…))`` as derived (``factor_terms``) and
    distributed as read back, which moved its Christoffel checks in the 17th digit between a cold and a warm
    run."""
    monkeypatch.setenv("HARNESS_CACHE_DIR", str(tmp_path))
    system = models.get("euler_top")
    derived, loaded = derive(system), derive(system)
    assert not derived.from_cache and loaded.from_cache
    for name in SYMBOLIC_FIELDS:
        assert sp.srepr(getattr(derived, name)) == sp.srepr(getattr(loaded, name)), name


def _compiled_from_the_stored_graph_equals_compiled_from_the_trees(system, derivation):
    """The compiler takes a cached per-body derivation in its stored form (the common subexpressions found when it
    was stored, not searched again in the trees: harness.derivation.cache.Graph): the same numbers as the trees
    compiled with their own common subexpressions, to round-off; each function computes only the replacements
    its quantities need, in their stored order."""
    import dataclasses

    from harness.derivation.compile import CompiledModel

    graph = derivation.graph
    assert graph is not None and set(graph.reduced) == set(SYMBOLIC_FIELDS)
    needed, exprs = graph.cse(list(graph.reduced["g"]))
    assert 0 < len(needed) < len(graph.replacements) and exprs == list(graph.reduced["g"])
    order = {symbol: k for k, (symbol, _) in enumerate(graph.replacements)}
    assert [order[symbol] for symbol, _ in needed] == sorted(order[symbol] for symbol, _ in needed)
    stored = CompiledModel(system, derivation)
    searched = CompiledModel(system, dataclasses.replace(derivation, graph=None))
    rng = np.random.default_rng(3)
    p = list(system.default_parameters().values())
    for _ in range(5):
        q, qd = rng.uniform(-2, 2, len(system.q)), rng.uniform(-3, 3, len(system.q))
        for a, b in zip(stored.terms(q, qd, p, []), searched.terms(q, qd, p, [])):
            np.testing.assert_allclose(a, b, rtol=1e-13, atol=1e-13 * np.max(np.abs(b)))
        for quantity in ("M", "C", "g", "M_dot"):
            np.testing.assert_allclose(stored(quantity, q, qd, p), searched(quantity, q, qd, p), rtol=1e-13,
                                       atol=1e-13 * np.max(np.abs(searched(quantity, q, qd, p))))
            np.testing.assert_allclose(stored.batched(quantity, [q, -q], [qd, qd], p),
                                       searched.batched(quantity, [q, -q], [qd, qd], p), rtol=1e-13,
                                       atol=1e-13 * np.max(np.abs(searched(quantity, q, qd, p))))


def test_cache_key_changes_with_the_model():
    assert _pendulum().fingerprint() != _pendulum(gravity=Gravity(g, (0, -1, 0))).fingerprint()


def test_parameters_are_symbols_collected_in_declaration_order():
    a = Parameter("a", 0.5, "m", "declared first, used second")
    mu = Parameter("mu", 0.3, "1", "used by a scene only", assumption="nonnegative")
    b = Parameter("b", 2.0, "kg", "declared last, used first")
    s = _pendulum(links=(Link("bob", b, (0, 0, -a)),), parameters=(mu,))
    assert [p.name for p in s.parameters] == ["g", "a", "mu", "b"]  # g: declared at import, before the others
    assert s.parameter("mu").default == 0.3 and s.parameter("b").unit == "kg"
    # a tuple that lists every parameter keeps its order (what dataclasses.replace passes on)
    assert [p.name for p in _pendulum(parameters=(l, g, m)).parameters] == ["l", "g", "m"]
    # the same for inputs: collected from the forces that use them
    f = Input("f", "N", "a torque")
    driven = _pendulum(forces=(JointInput("drive", "phi", f),))
    assert [i.name for i in driven.inputs] == ["f"] and driven.forces[0].input == "f"


def test_a_declaration_is_its_own_symbol_and_the_model_holds_plain_ones():
    """SymPy caches symbols by name and assumptions: two declarations of l with other values stay apart, and what a
    System, Claim, Scene or event holds are plain symbols — the same expressions, fingerprint and strings as a model
    written with plain symbols."""
    import pickle

    other_l = Parameter("l", 0.5, "m", "length")
    assert other_l != l and hash(other_l) != hash(l) and (l - other_l) != 0
    assert _pendulum(links=(Link("bob", m, (0, 0, -other_l)),)).parameter("l").default == 0.5
    s = _pendulum()
    used = [s.links[0].mass, *s.links[0].com, s.gravity.g]
    assert all(type(x) is sp.Symbol for e in used for x in sp.sympify(e).free_symbols)
    plain = _pendulum(parameters=(m, l, g), links=(Link("bob", m.symbol, (0, 0, -l.symbol)),),
                      gravity=Gravity(g.symbol, (0, 0, -1)))
    assert plain.fingerprint() == s.fingerprint()
    eom = Claim("(3.111)", "eom", m * l**2 * phi.accel + m * g * l * sp.sin(phi))
    assert sp.srepr(eom.printed) == sp.srepr(m.symbol * l.symbol**2 * phi.accel
                                             + m.symbol * g.symbol * l.symbol * sp.sin(phi.symbol))
    # in a model module, differentiate with respect to the coordinate itself (not the plain symbol of SYSTEM.q)
    assert sp.diff(m * sp.sin(phi), phi) == m * sp.cos(phi) and sp.diff(m * sp.sin(phi), phi.symbol) == 0
    scene = Scene("s", "-", (0.0,), (0.0,), 1.0, ["friction"], params={m: 2.0},
                  events=(StickSlip(phi, l, m, m * g),))
    assert scene.params == {"m": 2.0} and scene.events[0].mu_H == "l" and scene.events[0].coordinate == "phi"
    assert scene.effects == frozenset({"friction"}) and type(scene.events[0].normal_force.args[0]) is sp.Symbol
    copy = pickle.loads(pickle.dumps(l))
    assert copy == l and copy.default == 1.0 and copy.symbol == l.symbol
    with pytest.raises(AttributeError, match="fixed when it is declared"):
        l.default = 2.0


def test_symbols_the_system_does_not_declare_are_caught():
    with pytest.raises(ModelError, match=r"gravity uses undeclared symbol\(s\) \['g'\]"):
        _pendulum(gravity=Gravity(sp.Symbol("g", positive=True), (0, 0, -1)))
    mu = Parameter("mu", 0.3, "1", "not used by the system")
    with pytest.raises(ModelError, match=r"uses 'mu', which p does not declare: .*System\(parameters=...\)"):
        validate_claims(_pendulum(), [Claim("(1)", "parameter", mu, reference=m)])


@pytest.mark.parametrize("change, message", [
    (dict(links=(Link("bob", 1.0, (0, 0, -1)), Link("loose", 1.0))), "link 'loose' must be the child of exactly one joint"),
    (dict(links=(Link("bob", sp.Symbol("M", positive=True), (0, 0, -1)),)), "undeclared symbol(s) ['M']"),
    (dict(joints=(Joint("phi", "revolute", "nowhere", "bob", axis="x"),)), "connects unknown link"),
    (dict(joints=(Joint("theta", "revolute", "world", "bob", axis="x"),)), "set Joint.phi"),
    (dict(links=(Link("bob", 0, (0, 0, -1)),)), "no link has mass"),
    # an inertia tensor that is not positive definite / violates the triangle inequality (at the defaults)
    (dict(links=(Link("bob", 1.0, (0, 0, -1), Inertia(1.0, -1.0, 1.0)),)), "link bob: inertia tensor is not positive"),
    (dict(links=(Link("bob", 1.0, (0, 0, -1), Inertia(1.0, 1.0, 3.0)),)), "violate the triangle inequality"),
    (dict(links=(Link("bob", 1.0, (0, 0, -1), Inertia(1.0, 1.0, 3.0)),)), "fix Link('bob', inertia=...)"),
    # a map whose dimensions do not match the coordinates
    (dict(coordinates=(Coordinate("phi", "rad", "angle"), Coordinate("psi", "rad", "unused"))), "coordinate psi moves no joint"),
    (dict(joints=(Joint("phi", "revolute", "world", "bob", axis="x", phi=(sp.Symbol("phi", real=True),) * 2),)),
     "phi must be one scalar expression"),
    (dict(coordinates=(Coordinate("phi", "rad", "a"), Coordinate("psi", "rad", "b")),
          links=(Link("a", 1.0, (0, 0, -1)), Link("bob", 1.0, (0, 0, -1))),
          joints=(Joint("j1", "revolute", "world", "a", axis="x", phi=sp.Symbol("phi", real=True) + sp.Symbol("psi", real=True)),
                  Joint("j2", "revolute", "a", "bob", axis="x", phi=2 * sp.Symbol("phi", real=True) + 2 * sp.Symbol("psi", real=True)))),
     "Jacobian rank 1 < 2"),
    (dict(coordinates=(Coordinate("phi", "rad", "angle", range=(1.0, -1.0)),)), "range must be (low, high)"),
    # an input named but not declared: the message says how to declare it
    (dict(forces=(JointInput("motor", "phi", "tau"),)),
     "uses undeclared input 'tau': declare it, tau = Input('tau', UNIT, DESCRIPTION)"),
])
def test_modeling_mistakes_are_caught_at_load(change, message):
    with pytest.raises(ModelError) as exc:
        _pendulum(**change)
    assert message in str(exc.value)


def test_joint_and_parameter_mistakes():
    with pytest.raises(ModelError, match="unit vector"):
        Joint("j", "revolute", "world", "b", axis=(1, 1, 0))
    with pytest.raises(ModelError, match="type must be"):
        Joint("j", "ball", "world", "b")
    with pytest.raises(ModelError, match="give a unit"):
        Parameter("m", 1.0, "", "mass")
    with pytest.raises(ModelError, match="must be positive"):
        Parameter("m", -1.0, "kg", "mass")
    with pytest.raises(ModelError, match="parameter m: give a default value in SI units"):
        Parameter("m", unit="kg", description="mass")
    with pytest.raises(ModelError, match="parameter l: give a unit"):
        Parameter("l", 1.0)


def test_a_model_file_that_does_not_load_names_the_file_and_the_fix(tmp_path, monkeypatch):
    (tmp_path / "broken_model.py").write_text("from harness.modeling.system import Parameter\nm = Parameter('m', unit='kg')\n")
    monkeypatch.setattr(models, "__path__", [*models.__path__, str(tmp_path)])
    models.reload()
    try:
        assert "pendulum" in models.catalogue()  # the others still load
        with pytest.raises(ModelError) as exc:
            models.get("broken_model")
    finally:
        models.reload()
    assert "broken_model.py" in str(exc.value) and "give a default value" in str(exc.value)


def test_inertia_checks():
    check_inertia("ok", 1.0, np.diag([1.0, 2.0, 3.0]))
    check_inertia("point mass", 1.0, np.zeros((3, 3)))
    with pytest.raises(ModelError, match="positive"):
        check_inertia("x", 1.0, np.diag([1.0, -2.0, 3.0]))
    with pytest.raises(ModelError, match="triangle inequality"):
        check_inertia("x", 1.0, np.diag([1.0, 1.0, 3.0]))
    with pytest.raises(ModelError, match="symmetric"):
        check_inertia("x", 1.0, np.array([[1.0, 0.5, 0], [0, 1.0, 0], [0, 0, 1.0]]))
    cuboid = np.array(Inertia.cuboid(2.0, 0.1, 0.2, 0.3).matrix, dtype=float)
    check_inertia("cuboid", 2.0, cuboid)


@given(st.floats(1e-3, 1e3), st.floats(1e-3, 10.0), st.floats(0.0, 10.0), st.sampled_from("xyz"))
def test_a_cylinder_is_a_valid_inertia_for_any_dimensions(m, r, h, axis):
    """``Inertia.cylinder``: ``m r²/2`` about its axis (3.122), ``m (3 r² + h²)/12`` about a diameter, valid for every
    mass, radius and length a check may draw (a disc, h = 0, on the triangle inequality's edge)."""
    inertia = np.array(Inertia.cylinder(m, r, h, axis).matrix, dtype=float)
    check_inertia("cylinder", m, inertia)
    k = "xyz".index(axis)
    assert inertia[k, k] == pytest.approx(m * r**2 / 2, rel=1e-12)
    assert [inertia[i, i] for i in range(3) if i != k] == pytest.approx([m * (3 * r**2 + h**2) / 12] * 2, rel=1e-12)
    with pytest.raises(ModelError, match="give 'x', 'y' or 'z'"):
        Inertia.cylinder(m, r, h, "w")


def test_joint_loop_is_caught():
    with pytest.raises(ModelError, match="loop"):
        _pendulum(links=(Link("bob", 1.0, (0, 0, -1)), Link("a", 1.0), Link("b", 1.0)),
                  joints=(Joint("phi", "revolute", "world", "bob", axis="x"),
                          Joint("ja", "revolute", "b", "a", phi=0), Joint("jb", "revolute", "a", "b", phi=0)))


def test_the_tests_cache_is_a_copy_of_the_projects(tmp_path):
    """The test run's cache folder is seeded with a copy of the project's (tests/conftest.py): each entry copied
    whole, an entry the run already holds kept, the project's folder never the one the tests write to."""
    from conftest import _seed

    from harness.derivation.cache import PROJECT_ROOT, cache_dir

    assert cache_dir() != PROJECT_ROOT / ".cache" / "derivations"
    source, target = tmp_path / "project", tmp_path / "run"
    source.mkdir()
    (source / "a.json").write_text("{\"a\": 1}")
    (source / "b.json").write_text("{\"b\": 1}")
    target.mkdir()
    (target / "b.json").write_text("{\"b\": 2}")
    _seed(source, target)
    assert sorted(p.name for p in target.iterdir()) == ["a.json", "b.json"]
    assert (target / "a.json").read_text() == "{\"a\": 1}" and (target / "b.json").read_text() == "{\"b\": 2}"
    _seed(tmp_path / "absent", tmp_path / "elsewhere")
    assert not (tmp_path / "elsewhere").exists()


def test_a_derivation_of_large_trees_is_cached_and_compiled_as_a_graph(tmp_path, monkeypatch):
    """A four-bar linkage whose closed chain is a closed-form map (nested ``atan2`` and ``arccos``, Uicker et al.,
    Ch. 3) derives trees of 327 543 nodes (its C alone 1.7 MB of ``srepr``): read back from the cache they took
    7 CPU s at every run, and compiling them 5 s. Past ``GRAPH_MIN_NODES`` a derivation is cached as a graph, its
    common subexpressions written once (26 kB), and compiled from it; its forward dynamics equals the trees'. The
    catalogue's derivations stay trees (the largest, the trebuchet's, has 3546 nodes)."""
    from sympy import acos, atan2, cos, sin, sqrt

    from harness.derivation import derive as derive_module
    from harness.derivation.compile import CompiledModel
    from harness.modeling import Closure, Coordinate, Gravity, Inertia, Joint, Link, Parameter, Point, System

    trebuchet = models.get("trebuchet")
    assert not derive_module.as_graph(trebuchet, derive_module.derive(trebuchet))
    monkeypatch.setenv("HARNESS_CACHE_DIR", str(tmp_path / "derivations"))
    L_0, a, b, c = (Parameter(n, v, "m", n, range=(0.95 * v, 1.05 * v))
                    for n, v in (("L_0", 0.4), ("a", 0.1), ("b", 0.35), ("c", 0.3)))
    masses = [Parameter(f"m_{k}", v, "kg", f"mass {k}") for k, v in (("a", 0.2), ("b", 0.5), ("c", 0.4))]
    q = Coordinate("q", "rad", "crank angle")
    Bx, By = a * cos(q), a * sin(q)
    d = sqrt((L_0 - Bx) ** 2 + By**2)
    th_b = atan2(-By, L_0 - Bx) + acos((b**2 + d**2 - c**2) / (2 * b * d))
    th_c = atan2(-(By + b * sin(th_b)), L_0 - Bx - b * cos(th_b))
    rod = [Link(n, mass=m, com=(length / 2, 0, 0), inertia=Inertia(0, m * length**2 / 12, m * length**2 / 12))
           for n, m, length in zip(("crank", "coupler", "rocker"), masses, (a, b, c))]
    end = Point("rocker", (c, 0, 0), "D_end")
    system = System(name="fourbar", title="four-bar", lecture="(none)", coordinates=(q,), links=tuple(rod),
                    joints=(Joint("q", "revolute", "world", "crank", axis="z"),
                            Joint("coupler_joint", "revolute", "crank", "coupler", origin=(a, 0, 0), phi=th_b - q),
                            Joint("rocker_joint", "revolute", "coupler", "rocker", origin=(b, 0, 0), phi=th_c - th_b)),
                    gravity=Gravity(9.81, (0, -1, 0)), forces=(),
                    closures=(Closure("x", end, (1, 0, 0), L_0), Closure("y", end, (0, 1, 0), 0)))
    trees = derive_module.derive_uncached(system)
    assert derive_module.as_graph(system, trees)
    monkeypatch.setattr(derive_module, "derive_uncached", lambda s: trees)   # derived once (4 s)
    stored = derive_module.derive(system)                        # stored as a graph, returned as read back
    assert stored.graph is not None
    entry = next((tmp_path / "derivations").glob("fourbar-*.json"))
    assert entry.stat().st_size < 100_000 and "replacements" in json.loads(entry.read_text())
    loaded = derive_module.derive(system)                        # a later run's cache hit
    assert loaded.from_cache and loaded.graph is not None
    p = np.array([x.default for x in system.parameters])
    from_trees, from_graph = CompiledModel(system, trees), CompiledModel(system, loaded)   # each compiled once
    for state in ([0.3, 1.2], [2.0, -0.7], [-1.1, 3.0]):
        qd = np.array(state[1:])
        expected = from_trees.forward_dynamics(np.array(state[:1]), qd, p, np.zeros(0))
        got = from_graph.forward_dynamics(np.array(state[:1]), qd, p, np.zeros(0))
        assert np.allclose(got, expected, rtol=1e-12, atol=1e-12)
