"""The claims machinery classifies correctly (confirmed, erratum, C differs but C q̇ agrees,
convention-dependent), and every printed equation of every system can be evaluated and classified."""

import pytest
import sympy as sp

import models
from harness.compare.claims import Claim, classify, record_fields
from harness.settings import property_test

SYSTEM = models.get("planar_manipulator")
(p1, p2), (w1, w2) = SYSTEM.q, SYSTEM.qd
m_2, l_1, l_s2 = (SYSTEM.parameter(n).symbol for n in ("m_2", "l_1", "l_s2"))
h = m_2 * l_1 * l_s2 * sp.sin(p2)
CHRISTOFFEL = sp.Matrix([[-h * w2, -h * (w1 + w2)], [h * w1, 0]])


def test_correct_claim_is_confirmed():
    assert classify(SYSTEM, Claim("(t1)", "C", CHRISTOFFEL), examples=20).classification == "confirmed"


def test_wrong_claim_is_an_erratum_with_minimal_counterexample():
    wrong = CHRISTOFFEL.copy()
    wrong[1, 0] = -wrong[1, 0]
    verdict = classify(SYSTEM, Claim("(t2)", "C", wrong), examples=20)
    assert verdict.classification == "erratum"
    assert verdict.counterexample and "q=[" in verdict.counterexample and verdict.corrected
    assert verdict.corrected.startswith("Matrix([[")   # a printed matrix: the derived one beside it


def test_a_scalar_erratum_reads_its_derived_value_as_a_scalar():
    """A printed scalar (an entry, one equation of motion) is set beside its derived value as a scalar: the errata
    sheet had shown ``derived: Matrix([[…]])`` beside ``printed: …`` for 9 of the lecture's findings."""
    verdict = classify(SYSTEM, Claim("(t3)", "M", 2 * h, index=(0, 1)), examples=20)
    assert verdict.classification == "erratum" and "Matrix" not in verdict.corrected, verdict.corrected
    from harness.derivation.compile import compiled

    assert verdict.corrected == str(compiled(SYSTEM).derivation.M[0, 1])


def test_the_systems_states_come_first_and_a_failure_is_shrunk_from_their_seed(monkeypatch):
    """Every claim is checked first on the system's states (strategies.system_states, the conformance run's): a
    passing claim starts no hypothesis run; a failing one is met again by hypothesis from the same seed, which
    shrinks it; the same claim classified again gives the same counterexample, example count and errors."""
    from harness.compare import claims
    from harness.compare.strategies import states_seed

    wrong = CHRISTOFFEL.copy()
    wrong[0, 1] = 2 * wrong[0, 1]
    engines = ("pinocchio", "mujoco")
    seeds = []  # the hypothesis runs started, by their seed
    monkeypatch.setattr(claims, "property_test", lambda *a, **k: seeds.append(k.get("seed")) or property_test(*a, **k))
    right = claims.classify_as_printed(SYSTEM, Claim("(t6)", "C", CHRISTOFFEL), engines, 20)
    assert right.classification == "confirmed" and right.examples == 20 and not seeds
    first = claims.classify_as_printed(SYSTEM, Claim("(t5)", "C", wrong), engines, 20)
    assert first.classification == "erratum" and "q=[" in first.counterexample
    assert seeds and set(seeds) == {states_seed(SYSTEM)}
    again = claims.classify_as_printed(SYSTEM, Claim("(t7)", "C", wrong), engines, 20)
    assert (again.classification, again.counterexample, again.examples, again.errors) == \
        (first.classification, first.counterexample, first.examples, first.errors)


def test_a_shrunk_counterexample_is_kept_and_fails_again_when_read_back(monkeypatch, tmp_path):
    """The shrink's result is kept for the next run with the same code, packages, settings and seed (``.cache/
    counterexamples/``). Read back, the check must fail there again: then no hypothesis run, and the same verdict,
    counterexample and errors as shrunk. A kept state where the check passes, or a damaged entry, is shrunk again.
    The verdict counts the system's states up to the failing one and the counterexample: the shrink's candidates
    are its search, not examples."""
    import harness.kept
    from harness.compare import claims, strategies

    monkeypatch.setattr(harness.kept, "cache_dir", lambda: tmp_path / "derivations")  # what is kept: here
    wrong = CHRISTOFFEL.copy()
    wrong[1, 0] = -wrong[1, 0]
    claim, engines = Claim("(t10)", "C", wrong), ("pinocchio", "mujoco")
    runs = []
    real = claims._hypothesis_run
    monkeypatch.setattr(claims, "_hypothesis_run", lambda *a, **k: runs.append(1) or real(*a, **k))

    def verdict():
        v = claims.classify_as_printed(SYSTEM, claim, engines, 20)
        return v.classification, v.counterexample, v.examples, v.errors, v.state.q.tobytes(), v.state.qd.tobytes()

    shrunk = verdict()
    assert shrunk[0] == "erratum" and len(runs) == 2   # a printed C: its C q̇ is checked too
    kept = sorted((tmp_path / "counterexamples").iterdir())
    assert len(kept) == 2
    states = [s for batch in strategies.system_states(SYSTEM, 20) for s in batch]
    first_failing = next(k for k, s in enumerate(states)
                         if any(v > 1 for v in claims.evaluate_claim(SYSTEM, claim, s, engines).values()))
    assert shrunk[2] == first_failing + 2   # the states up to the failing one, and the counterexample

    assert verdict() == shrunk and len(runs) == 2   # read back and failing again: not shrunk again

    # C is linear in q̇: at q̇ = 0 the printed and the derived C vanish (C q̇ too): the check passes there
    harness.kept.keep(kept[0], {**harness.kept.read_kept(kept[0]), "qd": [0.0, 0.0]})
    assert verdict() == shrunk and len(runs) == 3
    kept[1].write_text(kept[1].read_text().replace('"q": [', '"q": [1.5, ', 1))  # damaged: the checksum fails
    assert verdict() == shrunk and len(runs) == 4


def test_claims_read_the_numbers_the_conformance_run_computed(monkeypatch):
    """Within evaluations.sharing() (a job of the main job), a claim of an engine quantity checked after the
    system's conformance run evaluates no engine again: the states and their numbers are the conformance run's."""
    from harness.compare import claims, conformance, evaluations
    from harness.engines import ENGINES

    calls = []
    for name in ("pinocchio", "mujoco"):
        real = ENGINES[name].evaluate
        monkeypatch.setattr(ENGINES[name], "evaluate", lambda self, state, real=real: calls.append(1) or real(self, state))
    with evaluations.sharing():
        assert conformance.run(SYSTEM, examples=20).passed
        before = len(calls)
        verdict = claims.classify_as_printed(SYSTEM, Claim("(t9)", "C", CHRISTOFFEL), ("pinocchio", "mujoco"), 20)
    assert verdict.classification == "confirmed" and verdict.examples == 20
    assert before == 2 * 20 and len(calls) == before  # every state evaluated once per engine, by the conformance run


def test_other_C_with_same_C_qd_is_not_an_erratum():
    other = CHRISTOFFEL + 0.7 * sp.Matrix([[w2, -w1], [w2, -w1]])  # adds S with S q̇ = 0
    assert classify(SYSTEM, Claim("(t3)", "C", other), examples=20).classification == "C differs, C·q̇ agrees"


CLOCKWISE = {"phi_2 counted clockwise": {p2: -p2}}   # its rate and acceleration follow: -phi_2', -phi_2''
S = sp.diag(1, -1)  # the Jacobian of that change, constant


def test_convention_dependent_claim():
    """Printed with the angle of link 2 counted the other way round: the printed C holds once phi_2 -> -phi_2 is
    substituted *and* C is taken to the model's coordinates as a matrix of coordinate pairs (Jᵀ C J). The same
    text with the coordinates substituted alone, as if C were a scalar, is wrong in every coordinate system."""
    claim = Claim("(t4)", "C", S * CHRISTOFFEL.xreplace({p2: -p2, w2: -w2}) * S, conventions=CLOCKWISE)
    verdict = classify(SYSTEM, claim, examples=20)
    assert verdict.classification == "convention-dependent" and verdict.convention == "phi_2 counted clockwise"
    substituted_only = Claim("(t4b)", "C", CHRISTOFFEL.xreplace({p2: -p2, w2: -w2}), conventions=CLOCKWISE)
    assert classify(SYSTEM, substituted_only, examples=20).classification == "erratum"


def test_a_coordinate_convention_takes_each_kind_to_the_models_coordinates():
    """M (Jᵀ M J), g and f_np (Jᵀ g), an entry of M (by J's diagonal), the equations of motion (Jᵀ R) and T (a
    scalar: the substitution alone), each printed with phi_2 and tau_2 counted clockwise, are
    convention-dependent; M's coupling entry had been an erratum, cos(-phi_2) = cos(phi_2) under the substitution."""
    from harness.derivation.derive import derive

    d = derive(SYSTEM)
    accel = sp.Matrix([c.accel for c in SYSTEM.coordinates])
    tau_2 = SYSTEM.u[1]
    clockwise = {"phi_2 and tau_2 counted clockwise": {p2: -p2, tau_2: -tau_2}}
    turned = {p2: -p2, w2: -w2, accel[1]: -accel[1], tau_2: -tau_2}   # the text's symbols in the model's
    residual = d.M * accel + d.C * sp.Matrix(SYSTEM.qd) + d.g - d.f_np
    printed = {"M": S * d.M.xreplace(turned) * S, "g": S * d.g.xreplace(turned), "f_np": S * d.f_np.xreplace(turned),
               "eom": S * residual.xreplace(turned), "T": sp.Matrix([d.T.xreplace(turned)])}
    for kind, value in printed.items():
        verdict = classify(SYSTEM, Claim(f"(c-{kind})", kind, value, conventions=clockwise), examples=10)
        assert verdict.classification == "convention-dependent", (kind, verdict.errors)
    entry = Claim("(c-M12)", "M", printed["M"][0, 1], index=(0, 1), conventions=clockwise)
    assert classify(SYSTEM, entry, examples=10).classification == "convention-dependent"


@pytest.mark.parametrize("convention, message", [
    ({p2: sp.sin(p2)}, "not affine"),
    ({p2: p1 + p2, w2: w2}, "but its coordinates' map gives"),
    ({w2: -w2}, "a rate or acceleration, and not its coordinate"),
    ({p2: 0 * p2}, "singular"),
])
def test_a_coordinate_convention_that_cannot_be_taken_through_is_refused_when_the_module_loads(convention, message):
    from harness.errors import ModelError
    from harness.modeling.claims import validate_claims

    with pytest.raises(ModelError, match=message):
        validate_claims(SYSTEM, [Claim("(c1)", "M", sp.zeros(2, 2), conventions={"other": convention})])


def test_a_convention_mixing_coordinates_needs_the_whole_quantity():
    from harness.errors import ModelError
    from harness.modeling.claims import validate_claims

    from harness.derivation.derive import derive

    absolute = {"absolute angles": {p2: p1 + p2}}   # the text's phi_2 is the model's phi_1 + phi_2: q_text = A q
    A_inv = sp.Matrix([[1, 0], [1, 1]]).inv()
    M_text = A_inv.T * derive(SYSTEM).M.xreplace({p2: p2 - p1}) * A_inv   # M in the text's coordinates
    verdict = classify(SYSTEM, Claim("(c2)", "M", M_text, conventions=absolute), examples=10)
    assert verdict.classification == "convention-dependent"   # the whole M: taken by Jᵀ M J
    with pytest.raises(ModelError, match="claim the whole quantity"):
        validate_claims(SYSTEM, [Claim("(c3)", "M", sp.S(0), index=(0, 1), conventions=absolute)])
    with pytest.raises(ModelError, match="cannot be taken to other coordinates"):
        validate_claims(SYSTEM, [Claim("(c4)", "steady:phi_2", sp.S(0), conventions=absolute)])


def test_holding_force_is_checked_against_every_source():
    """A holding claim (the drawbridge's rope force at rest, (A.7)): the value that holds the system at any phi_B is
    confirmed by the derivation and both engines; the printed one, with its extra cos(phi_B), is an erratum."""
    bridge = models.get("drawbridge")
    names = ("m_B", "m_T", "m", "l_B", "l_T", "l_m", "R", "g")
    m_B, m_T, m, l_B, l_T, l_m, R, g = (bridge.parameter(n).symbol for n in names)
    phi = bridge.q[0]
    right = (m_B * l_B + m_T * l_T - m * l_m) * g * sp.cos(phi) / R
    assert classify(bridge, Claim("(h1)", "holding:f_S2", right), examples=20).classification == "confirmed"
    printed = (m_B * g * l_B + m_T * g * l_T - m * g * l_m * sp.cos(phi)) / R * sp.cos(phi)
    assert classify(bridge, Claim("(h2)", "holding:f_S2", printed), examples=20).classification == "erratum"


# The four systems whose claims take longest (renaming searches, ingredients; 20-57 s each on 2 cores) run with
# `pytest -m slow`: the main job (`make check`, run first by CI) classifies every printed equation of every system
# and fails on "engines disagree"; tests/test_errata.py covers the mechanisms on small cases.
HEAVY_CLAIMS = {"planar_robot", "cart_pendulum", "planar_manipulator", "rotating_body"}


@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n in HEAVY_CLAIMS else n
                                  for n in models.catalogue()])
def test_every_printed_equation_is_classified(name, monkeypatch):
    """Every printed equation is classified without "engines disagree", and each finding's equations on the errata
    sheet (the printed, the corrected and the difference Δ, :func:`harness.report.equations.wide_math`) read back,
    as a reader reads them (tests/mathml_reading.py), as the expressions they were set from."""
    from harness.report import equations
    from tests.mathml_reading import misread

    system = models.get(name)
    printed = models.claims(name)
    sheet, wide_math = [], equations.wide_math

    def setting(expr, lhs="", residual=False, named=False):
        sheet.append((expr, residual, wide_math(expr, lhs, residual, named)))
        return sheet[-1][-1]

    monkeypatch.setattr(equations, "wide_math", setting)
    for claim in printed:
        verdict = classify(system, claim, examples=20, claims=printed)
        assert verdict.classification != "engines disagree", (claim.equation, verdict.errors)
        record_fields(system, verdict, printed)
    for expr, residual, mathml in sheet:
        if "<mo>…</mo>" not in mathml:   # too large to print
            wrong = misread(mathml, expr, residual, name)
            assert not wrong, (wrong, mathml)


def test_per_body_energies_sum_to_the_derivation():
    """(5.6), (5.12), (5.20) body by body add up to the T and V of (5.21), (5.20) the derivation assembles."""
    from harness.derivation import bodies
    from harness.derivation.derive import derive

    d = derive(SYSTEM)
    names = [link.name for link in SYSTEM.links if link.has_mass]
    T = sum(bodies.translational_energy(SYSTEM, n) + bodies.rotational_energy(SYSTEM, n) for n in names)
    V = sum(bodies.gravity_potential(SYSTEM, n) for n in names)
    assert sp.simplify(T - d.T) == 0
    assert sp.simplify(sp.Matrix([V]).jacobian(SYSTEM.q).T - d.g_gravity) == sp.zeros(len(SYSTEM.q), 1)


def test_a_wrong_steady_state_is_an_erratum_and_out_of_domain_states_are_not_examples():
    """``steady:<coordinate>``: the governor's printed arccos is real only for phi_dot² >= g/l (as printed beside
    it); states outside are rejected, not counted. Twice the printed angle is no steady state."""
    governor = models.get("governor")
    phi_dot = governor.qd[0]
    g, l = (governor.parameter(n).symbol for n in ("g", "l"))
    right = classify(governor, Claim("(t5)", "steady:alpha", sp.acos(g / (l * phi_dot**2))), examples=20)
    assert right.classification == "confirmed" and 0 < right.examples <= 20
    wrong = classify(governor, Claim("(t6)", "steady:alpha", 2 * sp.acos(g / (l * phi_dot**2))), examples=20)
    assert wrong.classification == "erratum"


def test_volume_integrals_of_standard_bodies_give_the_formulas_the_models_use():
    """(3.120)-(3.123), (3.128): the integrals the inertia claims are compared with, against the closed forms (and
    Inertia.cuboid), so that a wrong integral cannot confirm a wrong printed inertia."""
    from harness.derivation.bodies import Ball, Box, Cylinder, moment_of_inertia, solid_inertia, solid_volume
    from harness.modeling import Inertia

    m, R, l, a, b, c = sp.symbols("m R l a b c", positive=True)
    assert sp.simplify(moment_of_inertia(Ball(R), m / solid_volume(Ball(R))) - 2 * m * R**2 / 5) == 0
    assert sp.simplify(moment_of_inertia(Cylinder(R, l), m / solid_volume(Cylinder(R, l))) - m * R**2 / 2) == 0
    box = Box.around((0, -l / 2, 0), (a, l, c))
    about_S = solid_inertia(box, m / solid_volume(box), about=(0, -l / 2, 0))
    assert sp.simplify(about_S - Inertia.cuboid(m, a, l, c).matrix) == sp.zeros(3, 3)
    about_A = moment_of_inertia(box, m / solid_volume(box))
    assert sp.simplify(about_A - (m * (a**2 + l**2) / 12 + m * l**2 / 4)) == 0   # Steiner (3.135)


def test_a_wrong_cutting_force_is_an_erratum():
    """(3.112) against the joint's cut force (harness.derivation.bodies.joint_force): the centripetal term with the
    wrong sign is found; the printed one holds (tests the cut force, not only the claim)."""
    from harness.derivation.bodies import joint_force

    pendulum = models.get("pendulum")
    (phi,), (phi_dot,) = pendulum.q, pendulum.qd
    m, g, l = (pendulum.parameter(n).symbol for n in ("m", "g", "l"))
    along_rod = (joint_force(pendulum, "phi").T * sp.Matrix([0, -sp.sin(phi), sp.cos(phi)]))[0]
    right = Claim("(t7)", "parameter", m * g * sp.cos(phi) + m * l * phi_dot**2, reference=along_rod)
    wrong = Claim("(t8)", "parameter", m * g * sp.cos(phi) - m * l * phi_dot**2, reference=along_rod)
    assert classify(pendulum, right, examples=20).classification == "confirmed"
    assert classify(pendulum, wrong, examples=20).classification == "erratum"


def test_a_parameter_draw_is_an_example_when_one_of_its_states_lies_in_the_domain():
    """The claims draw their states as the conformance run does, a parameter draw at a time: a state outside the
    printed expression's domain is skipped (not an example), a draw with no state inside is rejected."""
    import pytest
    from hypothesis.errors import UnsatisfiedAssumption

    from harness.compare.claims import _each_state

    seen = []

    def check(state):
        if state < 0:
            raise UnsatisfiedAssumption
        seen.append(state)

    each = _each_state(check)
    each([-1.0, 2.0])
    assert seen == [2.0]
    with pytest.raises(UnsatisfiedAssumption):
        each(state=[-1.0, -2.0])  # by the name of check's argument, as hypothesis passes it
    assert seen == [2.0]


def test_a_holding_claim_is_evaluated_and_decided_again_without_deriving_it(tmp_path, monkeypatch):
    """A claim's compiled derived expression and its symbolic decision are found by what decides them
    (``derivation_of``: the model's fingerprint and the claim's quantity, index and ``at``; the printed expression's
    ``srepr``): the next run neither derives nor reduces it, with the same errors and the same decision. Another
    quantity is another identity; a parameter claim (its reference a function of the model module) has none."""
    from harness.compare import claims, errata, strategies

    monkeypatch.setenv("HARNESS_CACHE_DIR", str(tmp_path / "derivations"))   # compiled/, decisions/ here
    system = models.get("pendulum")
    claim = next(c for c in models.claims("pendulum") if c.quantity == "v:bob")
    state = strategies.system_states(system, 20)[0][0]

    def run():
        claims._COMPILED_CLAIMS.clear()
        claims._DERIVED.clear()
        return claims.evaluate_claim(system, claim, state, engines=()), errata.decide(system, claim, None)

    first = run()
    assert first[1] == "symbolic" and first[0]["derivation"] <= 1
    assert len(list((tmp_path / "decisions").iterdir())) == 1
    monkeypatch.setattr(claims, "_derive_claimed", lambda *a: pytest.fail("derived again"))
    monkeypatch.setattr(errata, "_decide", lambda *a: pytest.fail("decided again"))
    assert run() == first

    other = next(c for c in models.claims("pendulum") if c.quantity == "a:bob")
    assert claims.derivation_of(system, other) != claims.derivation_of(system, claim)
    assert claims.derivation_of(system, next(c for c in models.claims("pendulum") if c.quantity == "parameter")) is None


def test_a_claim_with_its_arguments_swapped_says_what_it_takes():
    """``Claim("M", "Lynch (2.1)", …)`` (the quantity where the equation goes) said only "unknown quantity"; it names
    the signature and the quantities."""
    import pytest

    from harness.modeling import Claim

    with pytest.raises(ValueError, match=r"claim M: unknown quantity 'Lynch \(2.1\)': Claim\(equation, quantity, "
                                         r"printed, \.\.\.\) takes one of C, Cqd, .* position:<name>"):
        Claim("M", "Lynch (2.1)", 1)
