"""The third oracle: equations *printed in the lecture*, transcribed per system ("claims"), checked against
our derivation and both engines on hypothesis states.

A model module lists ``CLAIMS = [Claim(...), ...]``. Each claim is the printed expression, transcribed
faithfully (typos included) in the model's symbols, and names the quantity it claims to equal:

* ``"M"``, ``"C"``, ``"Cqd"``, ``"g"``, ``"f_np"``, ``"T"``, ``"V"`` (up to a constant: its zero level is a
  choice) – compared with the derivation and, where an
  engine gives the quantity (M, C, Cqd, g), with Pinocchio and MuJoCo;
* ``"eom"`` – printed equations of motion, one residual ``lhs − rhs`` per row in ``q, q̇, q̈`` (symbols
  ``Coordinate.accel``), which must vanish at ``q̈`` from the forward dynamics of the derivation and of each
  engine;
* ``"equilibrium"`` – a printed equilibrium ``q*`` (all coordinates, in parameters): at ``(q*, q̇ = 0, u = 0)``
  the forward dynamics of the derivation and of each engine must give ``q̈ = 0``;
* ``"position:<point>"``, ``"v:<point>"``, ``"J_v:<point>"``, ``"J_omega:<link>"`` / ``"parameter"`` – kinematics (a
  position, a velocity, the Jacobians (4.64), (4.62) in the inertial frame) or a parameter relation, checked against our kinematics
  (derivation only: ``reference`` gives the derived expression);
* ``"holding:<input>"`` – the printed value of one input that holds the system at rest at any ``q`` (a static
  balance, e.g. a rope force): at ``(q, q̇ = 0)`` with that input (the others 0) the forward dynamics of the
  derivation and of each engine must give ``q̈ = 0``;
* ``"force:<element>"``, ``"f_np:<element>"`` – the force vector of a spring or damper on its point ``b`` (along
  its line) and that element's generalized force ``J_rᵀ f`` (5.73) (of an external force or torque ``J_vᵀ f^e``,
  ``J_ωᵀ τ^e``; of a joint's input or viscous friction ``J_φᵀ`` of its row (5.111)), derivation only;
* cut forces (3.104): a ``parameter`` claim may compare a printed cutting force with
  :func:`harness.derivation.bodies.joint_force` (a tree joint's force on what it carries), e.g. the pendulum's (3.112);
* ``"a:<point>"`` – a point's acceleration ``J_v q̈ + J̇_v q̇`` at the q̈ of each source's forward dynamics,
  derivation only;
* per body (:mod:`harness.derivation.bodies`), derivation only: ``"R:<link>"``, ``"R:<frame>/<link>"`` (rotation
  matrices (4.9)–(4.21)), ``"S:…"`` (``Ṙ Rᵀ`` (4.44)), ``"omega:<link>"`` (4.57), ``"I_0:<link>"`` (5.15),
  ``"T_t:<link>"``, ``"T_r:<link>"`` (5.6), (5.12), ``"V:<link>"`` (5.20); ``"v_squared:<point>"`` (``ṗᵀ ṗ``);
* ``"L"`` (the Lagrange function, up to a constant) and ``"dL_dqd:<q>"``, ``"ddt_dL_dqd:<q>"``, ``"dL_dq:<q>"``
  (the terms of the Euler–Lagrange equation (5.69) of one coordinate), derivation only;
* ``"steady:<coordinate>"`` – the printed value of one coordinate in a steady state (relative equilibrium): with
  that coordinate at rest and no input, the forward dynamics of the derivation and of each engine must give
  ``q̈ = 0``; states where the printed value is not real lie outside its stated domain and are not examples.

Classification (computed, never typed in):

* **confirmed** – agrees with the derivation and every engine that gives the quantity;
* **C differs, C·q̇ agrees** – a printed C that is not the Christoffel C but gives the same C·q̇ (C is not
  unique): not wrong as an equation of motion;
* **convention-dependent** – fails as printed but holds under one of the claim's declared alternative
  conventions (a substitution only the figure can decide): the report names it;
* **erratum** – disagrees with the derivation *and* with every engine that gives the quantity, while those
  agree with each other; reported with the printed and the corrected expression and a minimal
  counterexample state shrunk by hypothesis;
* **engines disagree** – the derivation and an engine disagree with each other: a finding of its own.
"""

from __future__ import annotations

import functools
from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np
import sympy as sp
from hypothesis.errors import UnsatisfiedAssumption

from harness import profiling
from harness.checks import Bound, Check, relative_error
from harness.derivation.compile import compiled
from harness.derivation.lambdified import lambdify, lambdify_built
from harness.derivation.derive import SIMPLIFY_MAX_OPS
from harness.compare import evaluations as at_state
from harness.compare.conformance import FLOAT64_RTOL, scales
from harness.engines import ENGINES, models_kept, symbolic
from harness.engines import model as engine_model
from harness.engines.base import State
from harness.errors import HarnessError
from harness.kept import keep, read_kept
from harness.derivation import bodies
from harness.derivation.bodies import element_force, element_generalized_force, point_in_q, rotational_jacobian
from harness.modeling.claims import ENGINE_QUANTITIES, Claim, as_matrix as _as_matrix, coordinate_change, select
from harness.modeling.claims import symbols as _symbols
from harness.modeling.system import WORLD, System
from harness.compare.strategies import (draws, hypothesis_examples, kept_path, state_from,
                                        state_record, states_seed, system_states)
from harness.settings import property_test

CLAIM_TOLERANCE = Bound("printed equation", 1.0, "the printed expression's relative error against a source over "
                        "the float64 tolerance (FLOAT64_RTOL, times κ(M) for an equation of motion or an "
                        "equilibrium): at most 1 agrees")


@dataclass
class Classification:
    """A printed equation classified: ``checks`` holds, per source, the largest error over tolerance seen (one
    :class:`harness.checks.Check` each, bound :data:`CLAIM_TOLERANCE`)."""

    claim: Claim
    system: str
    classification: str
    checks: list[Check]
    counterexample: str | None = None
    corrected: str | None = None
    convention: str | None = None
    examples: int = 0
    renaming: dict | None = None        # printed symbol -> model symbol under which a notation typo holds
    blame: list | None = None           # ingredient equations a "follows from erratum" claim fails through
    decided_by: str | None = None       # "symbolic", "numeric only", "identity at random values", "counterexample"
    state: object = None                # the counterexample as a State
    substitution: dict | None = None    # what the verdict was reached with (ingredients, renaming)

    @property
    def errors(self) -> dict[str, float]:
        """Source → largest relative error over tolerance seen (``errors_over_tolerance`` of claims.json)."""
        return {c.source: c.value for c in self.checks}


_DERIVED: dict = {}


def _derived(system: System, claim: Claim):
    """The derived symbolic quantity the claim is compared with (also the 'corrected' expression)."""
    key = (id(system), id(claim))
    if key not in _DERIVED:
        derived = _derive_claimed(system, claim)
        if claim.at:  # at rest: the equilibrium substituted leaves fractions that cancel (f_S = m_B g), shown so
            derived = derived.xreplace(at_rest(system, claim)).applyfunc(
                lambda e: sp.factor_terms(sp.cancel(e)) if sp.count_ops(e) <= SIMPLIFY_MAX_OPS else e)
        _DERIVED[key] = derived
    return _DERIVED[key]


def _holding_value(system: System, name: str) -> sp.Expr:
    """The input ``name`` that holds the system at rest at ``q``: ``g(q) − f_np(q, 0, u) = 0`` solved for it, the
    other inputs 0."""
    d = compiled(system).derivation
    u = sp.Symbol(name, real=True)
    rest = {x: 0 for x in [*system.qd, *system.u] if x != u}
    row = next((e for e in (d.g - d.f_np).xreplace(rest) if e.has(u)), None)
    if row is None:
        raise ValueError(f"{system.name}: the input {u} does not act on the system (holding claim)")
    return sp.solve(row, u)[0]


def on_motion(system: System, largest: int = 3) -> dict | None:
    """``q̈ = M⁻¹ (f_np − C q̇ − g)`` (5.99) as a substitution of the coordinates' accelerations, for a symbolic
    decision of a statement that holds on the motion only (None above ``largest`` coordinates)."""
    if len(system.coordinates) > largest:
        return None
    d = compiled(system).derivation
    qdd = d.M.LUsolve(d.f_np - d.C * sp.Matrix(system.qd) - d.g)
    return {c.accel: e for c, e in zip(system.coordinates, qdd)}


_AT_REST: dict = {}


def at_rest(system: System, claim: Claim) -> dict:
    """The substitution that puts a claim's state at rest (``Claim.at``): ``q̇ = q̈ = 0`` and either the inputs 0
    and ``q`` the system's one equilibrium (``g(q) − f_np(q, 0, 0) = 0`` solved), or the named input at its holding
    value and the others 0."""
    key = (id(system), claim.at)
    kept = _AT_REST.get(key)
    if kept is not None and kept[0] is system:  # the system is kept alive with it: its id is not reused
        return kept[1]
    rest = {**{x: 0 for x in system.qd}, **{c.accel: 0 for c in system.coordinates}}
    if claim.at == "equilibrium":
        d = compiled(system).derivation
        zero = {**rest, **{u: 0 for u in system.u}}
        solutions = sp.solve(list((d.g - d.f_np).xreplace(zero)), system.q, dict=True)
        if len(solutions) != 1 or set(solutions[0]) != set(system.q):
            raise ValueError(f"{system.name}: a claim at the equilibrium needs one equilibrium in closed form; "
                             f"found {len(solutions)}")
        rest.update(zero)
        rest.update(solutions[0])
    else:
        name = claim.at.split(":", 1)[1]
        rest.update({u: 0 for u in system.u})
        rest[sp.Symbol(name, real=True)] = _holding_value(system, name)
    _AT_REST[key] = (system, rest)
    return rest


def _derive_claimed(system: System, claim: Claim):
    c = compiled(system)
    d = c.derivation
    kind = claim.quantity.split(":")[0]
    if kind == "equilibrium":  # the equation an equilibrium solves: g(q*) - f_np(q*, 0, 0) = 0
        rest = {x: 0 for x in [*system.qd, *system.u]}
        return sp.Matrix(d.g - d.f_np.xreplace(rest))
    if kind == "holding":  # the input that holds the system at rest at q: g(q) − f_np(q, 0, u) = 0 solved for it
        return sp.Matrix([_holding_value(system, claim.quantity.split(":", 1)[1])])
    if kind == "eom":
        qdd = sp.Matrix([co.accel for co in system.coordinates])
        expr = d.M * qdd + d.C * sp.Matrix(system.qd) + d.g - d.f_np
    elif kind == "position":
        name = claim.quantity.split(":", 1)[1]
        expr = _point(system, name)
    elif kind == "force":
        expr = element_force(system, claim.quantity.split(":", 1)[1])
    elif kind == "constraint":  # a rope's, a contact's ... force: the map's constraint force (3.104)
        name = claim.quantity.split(":", 1)[1]
        forces = bodies.constraint_forces(system)
        if name not in forces:
            raise ValueError(f"{system.name}: no constraint force named {name!r} (declared: {sorted(forces)})")
        expr = forces[name]
    elif kind == "f_np" and ":" in claim.quantity:
        expr = element_generalized_force(system, claim.quantity.split(":", 1)[1])
    elif kind == "v":  # (4.64): the point's velocity J_v q̇ in the inertial frame
        expr = _point(system, claim.quantity.split(":", 1)[1]).jacobian(system.q) * sp.Matrix(system.qd)
    elif kind == "a":  # (4.64) differentiated: the point's acceleration J_v q̈ + J̇_v q̇ in the inertial frame
        expr = bodies.acceleration(system, _point(system, claim.quantity.split(":", 1)[1]))
    elif kind == "v_squared":  # (ṗ)ᵀ ṗ of the point, with ṗ = J_v q̇ (4.64)
        v = _point(system, claim.quantity.split(":", 1)[1]).jacobian(system.q) * sp.Matrix(system.qd)
        expr = v.T * v
    elif kind == "J_v":  # (4.64): the point's translational Jacobian ∂p/∂q in the inertial frame
        expr = _point(system, claim.quantity.split(":", 1)[1]).jacobian(system.q)
    elif kind == "J_omega":  # (4.62): the link's rotational Jacobian in the inertial frame, in lecture coordinates
        expr = rotational_jacobian(system, claim.quantity.split(":", 1)[1])
    elif kind in BODY_KINDS and ":" in claim.quantity:
        expr = _body_quantity(system, kind, claim.quantity.split(":", 1)[1])
    elif kind == "steady":  # the equation a steady state solves: C q̇ + g − f_np = 0 with the coordinate at rest
        rest = _steady_rest(system, claim)
        return sp.Matrix(d.C * sp.Matrix(system.qd) + d.g - d.f_np).xreplace(rest)
    elif kind in LAGRANGIAN_KINDS:
        expr = _lagrangian_term(system, d, kind, claim.quantity.partition(":")[2])
    elif kind == "parameter":
        expr = sp.sympify(claim.derived_reference())
    elif kind == "Cqd":
        expr = d.C * sp.Matrix(system.qd)
    elif kind == "K":  # the stiffness matrix ∂g/∂q (3.74)
        expr = d.g.jacobian(system.q)
    else:
        expr = getattr(d, kind)
    return select(sp.Matrix(expr) if isinstance(expr, sp.MatrixBase) else sp.Matrix([expr]), claim.index)


BODY_KINDS = {"R", "S", "omega", "I_0", "T_t", "T_r", "V"}
"""Per-body kinds (:mod:`harness.derivation.bodies`); ``R:`` and ``S:`` take ``<link>`` or ``<frame>/<link>``."""


def _body_quantity(system: System, kind: str, argument: str):
    frame, _, link = argument.rpartition("/")
    frame = frame or WORLD
    if kind == "R":
        return bodies.rotation_matrix(system, link, frame)
    if kind == "S":
        return bodies.angular_velocity_matrix(system, link, frame)
    return {"omega": bodies.angular_velocity, "I_0": bodies.inertia_in_inertial_frame,
            "T_t": bodies.translational_energy, "T_r": bodies.rotational_energy,
            "V": bodies.gravity_potential}[kind](system, link)


LAGRANGIAN_KINDS = {"L", "dL_dqd", "ddt_dL_dqd", "dL_dq"}
"""The Lagrange function L = T − V (5.67) (up to a constant, as V) and the terms of the Euler–Lagrange equation
(5.69) of one coordinate: ``dL_dqd:<q>`` = ∂L/∂q̇, ``ddt_dL_dqd:<q>`` = d/dt ∂L/∂q̇, ``dL_dq:<q>`` = ∂L/∂q."""


def _lagrangian_term(system: System, d, kind: str, coordinate: str):
    L = d.T - d.V
    if kind == "L":
        return L
    k = _coordinate_index(system, coordinate)
    if kind == "dL_dq":
        return sp.diff(L, system.q[k])
    p = sp.diff(L, system.qd[k])
    return p if kind == "dL_dqd" else bodies.rate(system, p)


def _coordinate_index(system: System, name: str) -> int:
    for k, c in enumerate(system.coordinates):
        if c.name == name:
            return k
    raise ValueError(f"{system.name}: no coordinate named {name!r}")


def _steady_coordinate(system: System, claim: Claim) -> int:
    return _coordinate_index(system, claim.quantity.split(":", 1)[1])


def _steady_rest(system: System, claim: Claim) -> dict:
    """A steady state (relative equilibrium) of ``steady:<coordinate>``: that coordinate at rest, no input."""
    k = _steady_coordinate(system, claim)
    return {system.qd[k]: 0, **{u: 0 for u in system.u}}


def _point(system: System, name: str) -> sp.Matrix:
    return point_in_q(system, system.point(name))


def _selected(values, index) -> np.ndarray:
    """The entries of :func:`~harness.modeling.claims.select` taken from an engine's numbers, without building a
    SymPy matrix of them (280 µs a state): a vector is a column, a single index counts row by row."""
    m = np.asarray(values, dtype=float)
    m = m.reshape(-1, 1) if m.ndim == 1 else m
    if index is None:
        return m
    if len(index) == 2:
        return m[index].reshape(1, 1)
    return m[index[0], :].reshape(1, -1) if m.shape[0] > 1 and m.shape[1] > 1 else m.reshape(-1)[index[0]].reshape(1, 1)


_COMPILED_CLAIMS: dict = {}


def _accel_coefficients(system: System, printed: sp.Matrix, key, text):
    """``∂R/∂q̈`` of a printed residual ``R`` (its 'mass matrix' rows; ``text()`` its ``srepr``), compiled
    (differentiated once per key, and not at all where the compiled function is kept: :func:`_lambdify`'s
    ``recipe``)."""
    accels = [c.accel for c in system.coordinates]
    return _lambdify(system, lambda: printed.jacobian(accels), key=("accel",) + key,
                     recipe=lambda: ("claims: ∂R/∂q̈", text(), sp.srepr(accels)))


def _once(table: dict, owners: tuple, compute):
    """``compute()`` once per the objects ``owners`` (by identity; kept alive in ``table`` with the value, so their
    ids are not reused)."""
    key = tuple(map(id, owners))
    hit = table.get(key)
    if hit is None or any(a is not b for a, b in zip(hit[0], owners)):
        hit = table[key] = (owners, compute())
    return hit[1]


_PRINTED: dict = {}
_PRINTED_TEXT: dict = {}
_SYMBOLS_TEXT: dict = {}


def _printed(system: System, claim: Claim, substitution: dict | None) -> sp.Matrix:
    """The printed expression as a matrix with ``substitution`` made, once per claim and substitution; under a
    convention that counts coordinates otherwise (:func:`~harness.modeling.claims.coordinate_change`), the quantity
    taken to the model's coordinates as its kind changes with them (``Jᵀ M J``, ``Jᵀ g``, …): substituting the
    coordinates alone would keep, e.g., ``cos(−φ) = cos φ`` in an entry of ``M`` whose sign the change flips."""
    def make():
        printed = _as_matrix(claim.printed)
        if not substitution:
            return printed
        change = coordinate_change(system, substitution, f"claim {claim.equation}")
        if change is None:
            return printed.xreplace(substitution)
        return change.quantity(claim.quantity.split(":")[0], printed.xreplace(change.substitution), claim.index)
    return _once(_PRINTED, (system, claim, substitution), make)


def printed_text(system: System, claim: Claim, substitution: dict | None) -> str:
    """``srepr`` of :func:`_printed` (what decides every function built from it), once per claim and substitution."""
    return _once(_PRINTED_TEXT, (system, claim, substitution), lambda: sp.srepr(_printed(system, claim, substitution)))


def derivation_of(system: System, claim: Claim) -> tuple[str, ...] | None:
    """What decides the derived expression of ``claim`` (:func:`_derived`) beside our code: the model (its
    :meth:`~harness.modeling.system.System.fingerprint`: every expression and default) and what the claim asks of it
    (its quantity, index and ``at``), the only fields of a claim :func:`_derive_claimed` and :func:`_derived` read.
    A function compiled from the derived expression, or a decision about it, is found by these texts without
    deriving it again (a confirmed claim's warm run derives nothing). None for a ``parameter`` claim: its reference
    is a function of the model module, whose text does not say what it computes."""
    if claim.quantity.split(":")[0] == "parameter":
        return None
    return "claims: derived", system.fingerprint(), repr((claim.quantity, claim.index, claim.at))


def _lambdify(system: System, expr, key=None, recipe=None):
    """Compiled once per ``key`` (classification evaluates the same claim hundreds of times). ``expr`` may be a
    function of no arguments building the expression, called only when ``key`` is not compiled yet (a derivative or
    the terms' sizes: SymPy work that cost 19 CPU s per claims run when built at every evaluation); with ``recipe``
    (a function giving the texts that decide what ``expr`` builds, beside our code), not even then where the compiled
    function is kept (:func:`harness.derivation.lambdified.lambdify_built`)."""
    build = expr if callable(expr) and not isinstance(expr, (sp.Basic, sp.MatrixBase)) else lambda: expr
    if key is not None and key in _COMPILED_CLAIMS:
        return _COMPILED_CLAIMS[key]
    with profiling.phase("lambdify claims"):
        args = _symbols(system)
        if recipe is not None:
            fn = lambdify_built((_symbols_text(system), *recipe()), args, lambda: _as_matrix(build()), modules="numpy")
        else:
            fn = lambdify(args, _as_matrix(build()), modules="numpy")
    if key is not None:
        _COMPILED_CLAIMS[key] = fn
    return fn


def _symbols_text(system: System) -> str:
    """``srepr`` of the compiled claims' arguments (:func:`_symbols`), once per system."""
    return _once(_SYMBOLS_TEXT, (system,), lambda: sp.srepr(_symbols(system)))


class _Disagrees(AssertionError):
    pass


CLAIM_ENGINES = ("pinocchio", "mujoco")
"""The engines a claim is checked against (besides the derivation)."""


@contextmanager
def shared_evaluations():
    """Within the block, the evaluations at a state (derivation and engines) are kept and shared by the claims
    classified and by a conformance run of the system in the same block (:mod:`harness.compare.evaluations`), and
    the engines' models are kept (:func:`harness.engines.models_kept`). The engines must not change within the
    block."""
    with at_state.sharing(), models_kept():
        yield


def _engine_values(claim: Claim, state: State, engines):
    """The claimed quantity from each source, with the scale and tolerance it is compared at."""
    kept = at_state.at(state)
    if "derivation" not in kept:
        with profiling.phase("symbolic"):
            ref = symbolic.evaluate(state)
            ref.extra["qd"] = state.qd
            kept["derivation"] = ref, scales(ref), float(np.linalg.cond(ref.M))
    ref, s, kappa = kept["derivation"]
    kind = claim.quantity.split(":")[0]
    evaluations = {"derivation": ref}
    if kind in ENGINE_QUANTITIES | {"eom", "equilibrium", "holding", "steady"}:
        for name in engines:
            if name not in kept:
                with profiling.phase(f"engine {name}"):
                    with profiling.phase("model"):
                        model = engine_model(name, state.tree)
                    with profiling.phase("evaluate"):
                        kept[name] = model.evaluate(state)
            evaluations[name] = kept[name]
    return evaluations, s, kappa


def _value_of(claim: Claim, ev):
    return {"M": ev.M, "C": ev.C, "Cqd": ev.Cqd, "g": ev.g}[claim.quantity]


def _derived_recipe(system: System, claim: Claim):
    """The recipe of a function built from the derived expression: :func:`derivation_of` where it decides it, else
    the expression's ``srepr`` (built to print it)."""
    identity = derivation_of(system, claim)
    return (lambda: identity) if identity is not None else (lambda: (sp.srepr(_derived(system, claim)),))


def _terms_size(system: System, expr, key, args, decided_by) -> float:
    """``max Σ |t|`` over the entries of ``expr()``, ``t`` the terms of each entry's sum: the scale its round-off is
    relative to. ``decided_by()``: the texts that decide ``expr()`` (:func:`_lambdify`'s recipe)."""
    size = _lambdify(system, lambda: _as_matrix(expr()).applyfunc(lambda e: sum(map(abs, sp.Add.make_args(e)))),
                     key=key, recipe=lambda: ("claims: the terms' sizes", *decided_by()))
    return float(np.max(np.abs(np.asarray(size(*args), dtype=float)), initial=0.0))


def _state_at_rest(system: System, claim: Claim, state: State) -> State:
    """The drawn state put at rest as :func:`at_rest` says: the drawn parameters (and ``q``, when the system is held
    there by an input)."""
    rest = at_rest(system, claim)
    n = len(system.coordinates)
    args = (state.q, np.zeros(n), np.zeros(n), state.p, np.zeros(len(system.u)))
    values = [rest.get(x, x) for x in (*system.q, *system.u)]
    at = np.asarray(_lambdify(system, values, key=("at rest", id(system), claim.at))(*args), dtype=float).ravel()
    inputs = {i.name: float(v) for i, v in zip(system.inputs, at[n:])}
    return State.make(system, at[:n], np.zeros(n), state.params, inputs)


def evaluate_claim(system: System, claim: Claim, state: State, engines=CLAIM_ENGINES,
                   substitution: dict | None = None) -> dict[str, float]:
    """Relative error of the printed expression against each source at one state (relative to tolerance:
    a value ≤ 1 means 'agrees')."""
    printed = _printed(system, claim, substitution)
    fn = _lambdify(system, printed, key=("printed", id(system), id(claim), id(substitution)),
                   recipe=lambda: ("claims: printed", printed_text(system, claim, substitution)))
    kind = claim.quantity.split(":")[0]
    if kind == "equilibrium":
        n = len(system.coordinates)
        q_star = np.asarray(fn(state.q, state.qd, np.zeros(n), state.p, state.u_vec), dtype=float).ravel()
        state = State.make(system, q_star, np.zeros(n), state.params, {})
        evaluations, s, kappa = _engine_values(claim, state, engines)
        return {source: relative_error(ev.qdd, np.zeros(n), s["qdd"]) / (FLOAT64_RTOL * kappa)
                for source, ev in evaluations.items()}
    if kind == "holding":  # the printed input at q, at rest: every source's q̈ must vanish
        n = len(system.coordinates)
        value = float(np.asarray(fn(state.q, np.zeros(n), np.zeros(n), state.p, np.zeros(len(system.u))),
                                 dtype=float).ravel()[0])
        inputs = {**{i.name: 0.0 for i in system.inputs}, claim.quantity.split(":", 1)[1]: value}
        state = State.make(system, state.q, np.zeros(n), state.params, inputs)
        evaluations, s, kappa = _engine_values(claim, state, engines)
        return {source: relative_error(ev.qdd, np.zeros(n), s["qdd"]) / (FLOAT64_RTOL * kappa)
                for source, ev in evaluations.items()}
    if kind == "steady":  # the printed steady value of one coordinate, that coordinate at rest, no input
        k = _steady_coordinate(system, claim)
        n = len(system.coordinates)
        qd = np.array(state.qd, dtype=float)
        qd[k] = 0.0
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            value = float(np.asarray(fn(state.q, qd, np.zeros(n), state.p, np.zeros(len(system.u))),
                                     dtype=float).ravel()[0])
        if not np.isfinite(value):  # outside the printed expression's domain (its stated condition)
            return None
        q = np.array(state.q, dtype=float)
        q[k] = value
        state = State.make(system, q, qd, state.params, {i.name: 0.0 for i in system.inputs})
        evaluations, s, kappa = _engine_values(claim, state, engines)
        return {source: relative_error(ev.qdd, np.zeros(n), s["qdd"]) / (FLOAT64_RTOL * kappa)
                for source, ev in evaluations.items()}
    if claim.at:
        state = _state_at_rest(system, claim, state)
    evaluations, s, kappa = _engine_values(claim, state, engines)
    out = {}
    for source, ev in evaluations.items():
        qdd = ev.qdd
        args = (state.q, state.qd, qdd, state.p, state.u_vec)
        value = np.asarray(fn(*args), dtype=float)
        if kind == "eom":
            # the residual's own q̈ coefficients ∂R/∂q̈ give its unit: M (a force row) or 1 (solved for q̈)
            key = (id(system), id(claim), id(substitution))
            accel = _accel_coefficients(system, printed, key, lambda: printed_text(system, claim, substitution))
            coefficients = np.abs(np.asarray(accel(*args), dtype=float))
            terms = s["qdd"] * float(np.max(coefficients)) if np.any(coefficients) else \
                max(s["qdd"] * float(np.max(np.abs(ev.M))), s["g"])
            # and at least the size of its own terms: a residual whose q̈ terms cancel (a balance its printed
            # ingredients satisfy identically) is round-off of those terms, not of its vanished coefficient
            terms = max(terms, _terms_size(system, lambda: printed, ("terms",) + key, args,
                                           lambda: (printed_text(system, claim, substitution),)))
            residual = value
            out[source] = relative_error(residual, np.zeros_like(residual), terms) / (FLOAT64_RTOL * kappa)
            continue
        if kind in ENGINE_QUANTITIES:
            reference = _selected(_value_of(claim, ev), claim.index)
            scale = s[kind]
        elif source == "derivation":
            derived_fn = _lambdify(system, lambda: _derived(system, claim), key=("derived", id(system), id(claim)),
                                   recipe=_derived_recipe(system, claim))
            reference = np.asarray(derived_fn(*args), dtype=float)
            if kind in ("V", "L"):  # a potential is defined up to a constant: compare V(q) - V(0)
                at_zero = (np.zeros_like(state.q), np.zeros_like(state.qd) if kind == "L" else state.qd, qdd,
                           state.p, state.u_vec)
                value = value - np.asarray(fn(*at_zero), dtype=float)
                reference = reference - np.asarray(derived_fn(*at_zero), dtype=float)
            energy = s["M"] * max(1.0, float(np.max(np.abs(state.qd)))) ** 2
            momentum = s["M"] * max(1.0, float(np.max(np.abs(state.qd))))
            scale = {"f_np": s["g"], "T": energy, "T_t": energy, "T_r": energy, "V": s["g"], "L": energy,
                     "I_0": s["M"], "dL_dqd": momentum, "ddt_dL_dqd": max(s["g"], energy),
                     "dL_dq": max(s["g"], energy),
                     "v_squared": max(1.0, float(np.max(np.abs(state.qd)))) ** 2}.get(kind, 1.0)
            # at least the size of the terms either side is the sum of: a value that cancels to 0 (a bearing
            # force's component) is compared at the round-off of its terms
            scale = max(scale, _terms_size(system, lambda: printed, ("terms", id(system), id(claim), id(substitution)),
                                           args, lambda: (printed_text(system, claim, substitution),)),
                        _terms_size(system, lambda: _derived(system, claim), ("terms derived", id(system), id(claim)),
                                    args, _derived_recipe(system, claim)))
        else:
            continue
        reference = np.asarray(reference, dtype=float).reshape(value.shape)
        out[source] = relative_error(value, reference, scale) / FLOAT64_RTOL
    if kind == "C":  # C is not unique: does the printed C give the same C q̇?
        ref = evaluations["derivation"]
        printed_cqd = value.reshape(-1, len(state.qd)) @ state.qd if claim.index is None else None
        if printed_cqd is not None:
            out["Cqd (from printed C)"] = relative_error(printed_cqd, ref.Cqd, s["Cqd"]) / FLOAT64_RTOL
    return out


def classify(system: System, claim: Claim, engines=CLAIM_ENGINES, examples: int | None = None,
             claims=None) -> Classification:
    """Classify a claim on hypothesis states; a failing claim is shrunk to a minimal counterexample. ``claims``
    (the system's printed equations) resolves the claim's ingredients: a claim that fails only through a wrong
    ingredient follows from that erratum; a printed symbol the model lacks is searched for a renaming
    (:mod:`harness.compare.errata`)."""
    from harness.compare import errata

    return errata.classify(system, claim, tuple(e for e in engines if not ENGINES[e].applies(system)), examples,
                           claims)


def classify_as_printed(system: System, claim: Claim, engines, examples, base: dict | None = None) -> Classification:
    """The classification of one claim with ``base`` substituted into the printed expression (its ingredients,
    a renaming): confirmed, C differs but C·q̇ agrees, convention-dependent, erratum or engines disagree."""
    base = _kept(base or None)
    worst: dict[str, float] = {}
    count = [0]
    shrinking: list = []  # the engines a failing state is shrunk against (_shrunk_against), set by the first failure

    def check(state: State):
        errors = _in_domain(evaluate_claim(system, claim, state, shrinking[0] if shrinking else engines, base))
        count[0] += 1
        for k, v in errors.items():
            worst[k] = max(worst.get(k, 0.0), v)
        failing = [k for k, v in errors.items() if v > 1 and not k.startswith("Cqd (from")]
        if failing:
            if not shrinking:
                shrinking.append(_shrunk_against(failing, engines))
            raise _Disagrees(_state_text(state), state)

    failure = _run(system, check, examples, kept_as=_identity("as printed", system, claim, base, engines))
    verdict = Classification(claim, system.name, "confirmed",
                             [CLAIM_TOLERANCE.check(claim.equation, source, v) for source, v in worst.items()],
                             examples=count[0], substitution=base)
    if failure is None:
        return verdict
    verdict.counterexample, verdict.state = failure
    derived = _derived(system, claim)   # a scalar where the printed one is: Matrix([[…]]) had stood beside it
    scalar = derived.shape == (1, 1) and not isinstance(claim.printed, sp.MatrixBase)
    verdict.corrected = str(derived[0] if scalar else derived)
    if claim.quantity == "C":  # C is not unique: search separately for a state where C·q̇ differs
        def cqd_check(state: State):
            if evaluate_claim(system, claim, state, engines, base).get("Cqd (from printed C)", 0.0) > 1:
                raise _Disagrees(_state_text(state), state)

        cqd_failure = _run(system, cqd_check, examples,
                           kept_as=_identity("C q̇ of the printed C", system, claim, base, engines))
        if cqd_failure is None:
            verdict.classification = "C differs, C·q̇ agrees"
            return verdict
        verdict.counterexample, verdict.state = cqd_failure
    for name, substitution in claim.conventions.items():  # a yes/no question: nothing to shrink
        substitution = _kept({**(base or {}), **substitution})
        ok = _run(system, _holds_with(system, claim, engines, substitution), examples, shrink=False)
        if ok is None:
            verdict.classification, verdict.convention = "convention-dependent", name
            return verdict
    sources = [k for k in worst if not k.startswith("Cqd (from")]
    if all(worst[k] > 1 for k in sources):
        verdict.classification = "erratum"
    else:
        verdict.classification = "engines disagree"
    return verdict


def _identity(check: str, system: System, claim: Claim, substitution: dict | None, engines):
    """What a check of ``claim`` evaluates, in words and texts (the printed expression with ``substitution`` made,
    :func:`printed_text`; what decides the derived one, :func:`_derived_recipe`): a function giving the key of its
    kept counterexample (:func:`_minimal`) beside the code, the packages, the settings and the seed, called only
    where one is kept."""
    return lambda: (check, claim.equation, claim.quantity, repr(claim.index), claim.at,
                    printed_text(system, claim, substitution), *_derived_recipe(system, claim)(), repr(tuple(engines)))


def _shrunk_against(failing: list[str], engines) -> tuple:
    """The engines the candidates of a failing claim's shrink are evaluated by: none when the derivation is among
    the sources the first failing state disagrees with (every source is evaluated at that state, and the verdict
    counts them all there); the derivation and the engines agree to round-off (the conformance run), so the printed
    equation fails against them at the same states, and a candidate then needs no engine model of its parameter
    draw. A failure against engines only is shrunk against all of them. (An engine's largest error in the verdict is
    then the largest over the states it was evaluated at: the system's states and the first failing one.)"""
    return () if "derivation" in failing else tuple(engines)


_KEPT: dict = {}


def _kept(substitution: dict | None) -> dict | None:
    """One dict object per distinct substitution, kept alive: the compiled functions are cached by its id."""
    if not substitution:
        return None
    key = tuple(sorted((str(k), sp.srepr(v)) for k, v in substitution.items()))
    return _KEPT.setdefault(key, substitution)


def _in_domain(errors):
    """The errors at a state, or the state is rejected: it lies outside the printed expression's domain (a steady
    state that exists only under the condition the lecture states beside it). A rejected state is not an example;
    a parameter draw none of whose states lie inside is rejected as a whole (:func:`_each_state`), and hypothesis
    draws until the claim's parameter draws have states inside."""
    if errors is None:
        from hypothesis import reject
        from hypothesis.control import currently_in_test_context

        if currently_in_test_context():
            reject()
        raise UnsatisfiedAssumption  # a kept state replayed (see _run): skipped as hypothesis skipped it
    return errors


def _holds_with(system, claim, engines, substitution):
    def check(state: State):
        errors = _in_domain(evaluate_claim(system, claim, state, engines, substitution))
        if any(v > 1 for k, v in errors.items() if not k.startswith("Cqd (from")):
            raise _Disagrees(_state_text(state), state)
    return check


def holds(system: System, claim: Claim, engines, examples, substitution: dict | None = None,
          shrink: bool = True) -> bool:
    """Whether the claim (with ``substitution``) agrees with every source on the drawn states."""
    return _run(system, _holds_with(system, claim, engines, _kept(substitution)), examples, shrink) is None


def _run(system: System, check, examples, shrink: bool = True, kept_as=None):
    """None when ``check`` passes on every state, else (counterexample text, State).

    Every printed equation of a system is checked first on the system's states, in order
    (:func:`~harness.compare.strategies.system_states`, the states of its conformance run, whose numbers are kept:
    :mod:`harness.compare.evaluations`); a state outside the printed expression's domain is skipped. Where one of
    them fails, that failure decides (:func:`_minimal`). Where some lie outside the domain and none fails, what the
    check recorded is undone (:func:`_undo`) and hypothesis runs it from the same seed, drawing until each parameter
    draw has a state inside (as many examples as asked), and shrinks a failure it meets."""
    undo = _undo(check)
    failed, skipped = None, 0
    with profiling.phase("replay"):
        for batch in system_states(system, examples):
            for state in batch:
                try:
                    check(state)
                except UnsatisfiedAssumption:  # outside the printed expression's domain: not an example
                    skipped += 1
                except _Disagrees as failure:
                    failed = failure
                    break
            if failed is not None:
                break
    if failed is not None:
        return _minimal(system, check, examples, failed, shrink, kept_as)
    if not skipped:
        return None
    undo()
    return _hypothesis_run(system, check, examples, shrink)


def _hypothesis_run(system: System, check, examples, shrink: bool):
    """``check`` run by hypothesis from the system's seed: None, or its (shrunk) failure ``(text, State)``."""
    test = property_test(draws(system), _each_state(check), hypothesis_examples(examples), shrink=shrink,
                         seed=states_seed(system))
    try:
        test()
    except _Disagrees as failure:
        return str(failure.args[0]), (failure.args[1] if len(failure.args) > 1 else None)
    return None


def _minimal(system: System, check, examples, failed: _Disagrees, shrink: bool, kept_as):
    """The counterexample of a check that ``failed`` at one of the system's states: that state itself for a
    yes/no question (``shrink`` false), else the minimal one hypothesis shrinks to, running the check from the
    same seed: it meets the failure at the same state (should it not, a draw rejected before it moves the
    sequence, the failing state is the counterexample). What the check recorded is what it recorded on the
    system's states up to the failing one, and at the counterexample: the shrink's candidates are its search,
    not examples.

    The shrink's result is kept on disk (:func:`~harness.compare.strategies.kept_path`; ``kept_as()`` names what
    the check evaluates, :func:`_identity`) and read back by the next run with the same code, packages, settings
    and seed, where it is checked again: the check must fail there now, else hypothesis shrinks again. Measured in a
    warm main job (2 CPUs): the claims took 32.7 CPU s shrinking, 17.8 s reading the counterexamples back."""
    if not shrink:  # a yes/no question: the failing state answers it
        return str(failed.args[0]), failed.args[1]
    replayed = _undo(check)   # what the check recorded on the system's states, up to the failing one
    path = kept_path("counterexamples", system, examples, True, *kept_as()) if kept_as is not None else None
    doc = read_kept(path) if path is not None else None
    if doc is not None:
        try:
            check(state_from(system, doc))
        except _Disagrees as failure:
            profiling.count("counterexamples read back and failing again")
            return str(failure.args[0]), failure.args[1]
        except (UnsatisfiedAssumption, ValueError, KeyError, TypeError, HarnessError):
            pass
        replayed()
    found = _hypothesis_run(system, check, examples, shrink=True)
    text, state = found if found is not None and found[1] is not None else (str(failed.args[0]), failed.args[1])
    replayed()
    try:
        check(state)   # the counterexample's errors recorded
    except _Disagrees as failure:
        text = str(failure.args[0])
    if path is not None:
        keep(path, state_record(state))
    return text, state


def _each_state(check):
    """``check`` of one state as a check of a parameter draw's states (:func:`~harness.compare.strategies.draws`, as
    the conformance run draws them): a state outside the printed expression's domain is skipped, not an example; a
    draw without any state inside it is rejected (hypothesis draws another)."""
    @functools.wraps(check)  # check's signature: hypothesis passes the batch by the name of its argument
    def each(*args, **kwargs):
        (batch,) = (*args, *kwargs.values())  # hypothesis passes it by the name in ``check``'s signature
        inside = 0
        for state in batch:
            try:
                check(state)
            except UnsatisfiedAssumption:
                continue
            inside += 1
        if not inside:
            raise UnsatisfiedAssumption  # what hypothesis's reject() raises: not an example
    return each


def _undo(check):
    """A function restoring the lists and dicts ``check`` closes over (what it recorded) to their contents now."""
    saved = []
    for cell in check.__closure__ or ():
        value = cell.cell_contents
        if isinstance(value, (list, dict)):
            saved.append((value, value.copy()))

    def undo():
        for value, copy in saved:
            value.clear()
            value.update(copy) if isinstance(value, dict) else value.extend(copy)
    return undo


def record_fields(system: System, verdict: Classification, claims) -> dict:
    """What a verdict adds to its JSON record: how it was decided, the renaming or blame, and for a finding the
    errata-sheet fields (:mod:`harness.report.errata`)."""
    from harness.report.errata import finding

    out = {"decided_by": verdict.decided_by, "renaming": verdict.renaming, "blame": verdict.blame,
           "ingredients": list(verdict.claim.ingredients), "where": verdict.claim.where}
    if verdict.classification not in ("confirmed", "C differs, C·q̇ agrees"):
        with profiling.phase("errata sheet"):
            out.update(finding(system, verdict, claims))
    return out


def _state_text(state: State) -> str:
    from harness.compare.conformance import _fmt

    return f"q={_fmt(state.q)}, qd={_fmt(state.qd)}, u={_fmt(state.u)}, params={_fmt(state.params)}"
