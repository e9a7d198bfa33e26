"""Conformance checks of one system: our derivation against every engine of the registry (Pinocchio, MuJoCo,
Drake; :data:`harness.engines.ENGINES`) that applies to it, on hypothesis states.

Tolerance policy (the only one; never tuned per test)
-----------------------------------------------------
Every quantity is compared as ``max|X_engine − X_symbolic| / scale ≤ FLOAT64_RTOL · amplification``.

* ``FLOAT64_RTOL = 1e-12``: all three evaluate the same closed-form quantities in float64 (machine epsilon
  2.2e-16) with at most a few thousand operations for these trees; a few hundred ulps of round-off stay
  well below 1e-12 of the quantity's scale, while any modeling or export mistake (a moved centre of
  mass, a wrong axis, a missing term) shows up at 1e-6 or larger.
* ``scale`` is the magnitude of the terms that make up the quantity, not of the (possibly cancelling or
  vanishing) result. With ``v = max(1, |q̇|)`` (per second): ``M``: max|M|; ``C``: max(|C|, |Ṁ|, |M| v);
  ``C q̇``: that times ``v``; ``g`` (gravity and spring parts) and ``f``: at least ``|M| v²``, the generalized
  force that gives an acceleration of ``v²`` — so that a force which vanishes at the state (``g`` of a
  hanging pendulum) is not compared with the engine's round-off relative to zero; a spring's part at least at the
  size of the two terms its force is the difference of (``c L ∂L/∂q`` and ``c l₀ ∂L/∂q``, ``k θ`` and ``k θ₀``:
  ``Derivation.g_spring_terms``), which cancel near the rest length (found on the rotating body with 2000 states:
  MuJoCo's spring force off by 0.11 of the bound relative to the force itself); ``q̈``: the
  accelerations each term alone would cause, ``max|M⁻¹| · max|term|``, at least ``v²``.
* mapped engine quantities (``θ = φ(q)`` not the identity) are compared at least at the scale of the mapped
  tree terms (``|J|²|M_θ|``, ``|J|²|C_θ| + |J||J̇||M_θ|``, …): the map multiplies the tree's round-off, e.g. by
  ``1/r²`` for a ball of radius ``r`` rolling on a beam.
* an engine's ``C q̇`` formed as the difference of its bias forces with and without the velocity (Pinocchio's
  ``nonLinearEffects − computeGeneralizedGravity``, MuJoCo's ``qfrc_bias(v) − qfrc_bias(0)``) carries the
  round-off of the gravity it subtracts: it is compared at least at ``|J| (|C θ̇| + |g_θ|)`` (found on the toggle
  press near its stretched position, heavy and slow: MuJoCo's ``C q̇`` off by 0.12 of the bound relative to
  ``|C| v`` alone, 25 times ``|g|`` smaller than ``|g|``; Drake's ``CalcBiasTerm`` subtracts nothing); MuJoCo's
  Christoffel ``C``, polarized from ``qfrc_bias(v ± s e_j)``, carries ``ε |g_θ| / s`` per entry, summed by the map
  (``harness.engines.base._polarized_gravity``; found on the ball on the beam with 2000 states: 0.1 of the bound
  relative to ``|J|ᵀ|M||J|`` alone, with a ball of 5 cm nearly at rest).
* ``amplification`` is 1, except for ``q̈``, where solving ``M q̈ = …`` amplifies relative round-off by
  up to the condition number ``κ(M)``.
"""

from __future__ import annotations

import functools
import weakref
from dataclasses import dataclass, field

import numpy as np

from harness import profiling
from harness.compare import evaluations, roundtrip
from harness.derivation.compile import compiled
from harness.checks import Bound, Check, flag, max_abs as _max, relative_error as _relative
from harness.engines import ENGINES, models_kept, symbolic
from harness.engines import model as engine_model
from harness.engines.base import Evaluation, State
from harness.modeling.system import System
from harness.settings import property_test
from harness.compare.strategies import (STATES_PER_DRAW, draws, hypothesis_examples, states_seed,
                                        system_states)

FLOAT64_RTOL = 1e-12
ENGINE_QUANTITIES = ("M", "Cqd", "g", "g_spring", "f_damper", "qdd")
ROUND_OFF = Bound("float64 round-off", FLOAT64_RTOL,
                  "three float64 evaluations of the same closed-form quantity, relative to the scale of its terms "
                  "(harness/compare/conformance.py); for qdd times kappa(M)")
EXPORT = Bound("export round trip", roundtrip.ROUNDTRIP_RTOL,
               "masses, centres of mass, inertia tensors, joint axes and placements as loaded by the engine against "
               "the intended values, relative to each item's scale: the exporters keep float64 exactly, what remains "
               "is a few ulps of the engines' own arithmetic")


class ConformanceFailure(AssertionError):
    """A check exceeded its tolerance; the message names system, quantity, engine and the state."""

    def __init__(self, check: Check, state: State):
        self.check, self.state = check, state
        super().__init__(
            f"{state.system.name}: {check.name}{f' ({check.detail})' if check.detail else ''} from "
            f"{check.source} differs from the symbolic model by "
            f"{check.value:.3e} (relative; tolerance {check.bound:.1e}) at "
            f"q={_fmt(state.q)}, qd={_fmt(state.qd)}, u={_fmt(state.u)}, params={_fmt(state.params)}")


def _fmt(value) -> str:
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}={float(v)!r}" for k, v in value.items()) + "}"
    return "[" + ", ".join(repr(float(v)) for v in np.ravel(value)) + "]"


def scales(ref: Evaluation) -> dict[str, float]:
    """The scale of each quantity from the magnitudes of its terms (see the module docstring)."""
    v = max(1.0, _max(ref.extra["qd"]))
    M = _max(ref.M)
    force_floor = M * v * v  # the generalized force that gives an acceleration of max(1, |q̇|²) per s²
    C = max(_max(ref.C), _max(ref.extra["M_dot"]), M * v)
    spring = max(_max(ref.g_spring), _max(ref.extra.get("g_spring_terms", ())))
    terms = max(_max(ref.extra["f_np"]), _max(ref.Cqd), _max(ref.g_gravity), spring, force_floor)
    return {"M": M, "C": C, "Cqd": C * v, "skew": C,
            "g": max(_max(ref.g_gravity), spring, force_floor),
            "g_spring": max(spring, force_floor),
            "f_damper": max(_max(ref.f_damper), force_floor),
            "qdd": max(_max(np.linalg.inv(ref.M)) * terms, v * v)}


def compare(state: State, ref: Evaluation, other: Evaluation, scale: dict | None = None,
            kappa: float | None = None) -> list[Check]:
    """Engine ``other`` against the symbolic reference at one state (``scale``, ``kappa``: :func:`scales` and
    κ(M) of ``ref``, when the caller has them already)."""
    s = dict(scales(ref) if scale is None else scale)
    for name, value in other.extra.get("map_scale", {}).items():  # round-off grown by the map θ = φ(q)
        s[name] = max(s[name], value)
    kappa = float(np.linalg.cond(ref.M)) if kappa is None else kappa
    out = []
    for name in ENGINE_QUANTITIES:
        amplification = kappa if name == "qdd" else 1.0
        out.append(ROUND_OFF.check(name, other.engine, _relative(getattr(other, name), getattr(ref, name), s[name]),
                              amplification))
    if other.C is not None:
        out.append(ROUND_OFF.check("C (Christoffel)", other.engine, _relative(other.C, ref.C, s["C"])))
    if "C_coriolis_matrix" in other.extra:
        out.append(ROUND_OFF.check("C (computeCoriolisMatrix)", other.engine,
                              _relative(other.extra["C_coriolis_matrix"], ref.C, s["C"])))
    return out


def self_checks(state: State, ref: Evaluation, scale: dict | None = None) -> list[Check]:
    """Properties of the derivation itself: M symmetric and positive definite, Ṁ − 2C skew (Note 5.4)."""
    s = scales(ref) if scale is None else scale
    M = ref.M
    eig_min = float(np.linalg.eigvalsh(0.5 * (M + M.T)).min())
    N = ref.extra["M_dot"] - 2 * ref.C
    return [
        ROUND_OFF.check("M symmetric", "symbolic", _relative(M, M.T, s["M"])),
        flag("M positive definite", "symbolic", eig_min > 0),
        ROUND_OFF.check("Mdot - 2C skew", "symbolic", _relative(N, -N.T, s["skew"])),
    ]


def evaluate_all(state: State, engines=None, pin_urdf=None, mj_xml=None) -> list[Check]:
    """All checks at one state, by every engine of ``engines`` (default: the registry). ``pin_urdf``/``mj_xml``
    may replace the exported model text Pinocchio/MuJoCo load (to show that a wrong export is caught). Each
    source's numbers are kept for the printed equations checked at the same state (:mod:`.evaluations`), those of a
    replaced text not."""
    kept = evaluations.at(state)
    with profiling.phase("symbolic"):
        ref = symbolic.evaluate(state)
        ref.extra["qd"] = state.qd
        scale, kappa = scales(ref), float(np.linalg.cond(ref.M))  # once per state, for every engine
        kept.setdefault("derivation", (ref, scale, kappa))
        findings = self_checks(state, ref, scale)
    texts = {"pinocchio": pin_urdf, "mujoco": mj_xml}
    for name in ENGINES if engines is None else engines:
        text = texts.get(name)
        with profiling.phase(f"engine {name}"):
            with profiling.phase("model"):
                model = ENGINES[name](state.tree, text(state.tree)) if text else engine_model(name, state.tree)
            with profiling.phase("evaluate"):
                evaluation = model.evaluate(state)
            if not text:
                kept.setdefault(name, evaluation)
            with profiling.phase("compare"):
                findings += compare(state, ref, evaluation, scale, kappa)
            with profiling.phase("round trip"):
                worst = _worst_round_trip(model)
                findings.append(EXPORT.check("export round trip", name, worst.error, detail=worst.item))
    return findings


KEPT_MODELS = 24
"""Engine models a conformance run keeps (:func:`harness.engines.models_kept`): the last 8 parameter draws of the
three engines, where hypothesis repeats a draw (a warm check's resident memory 343 MB for three systems without
keeping, 580 MB keeping every draw's, measured)."""

_ROUND_TRIPS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _worst_round_trip(model):
    """The item of its tree the engine ``model`` loaded farthest from it: once per model (a kept model,
    :func:`harness.engines.models_kept`, is the same file read by the same engine)."""
    worst = _ROUND_TRIPS.get(model)
    if worst is None:
        worst = _ROUND_TRIPS[model] = max(roundtrip.items(model.tree, model), key=lambda item: item.error)
    return worst


@dataclass
class Summary:
    """Largest error per (check, engine) over all examples, and the shrunk counterexample of a failure."""

    system: str
    examples: int = 0
    worst: dict = field(default_factory=dict)   # (check, source) -> Check with the largest ratio
    parameter_draws: int = 0                    # distinct parameter values of the states evaluated
    failure: str | None = None
    not_applicable: dict = field(default_factory=dict)  # engine -> reason it does not apply

    @property
    def passed(self) -> bool:
        return self.failure is None and all(f.passed for f in self.worst.values())

    def record(self, checks):
        for c in checks:
            key = (c.name, c.source)
            if key not in self.worst or c.ratio > self.worst[key].ratio:
                self.worst[key] = c


def run(system: System, engines=None, examples: int | None = None,
        random_parameters: bool = True, pin_urdf=None, mj_xml=None,
        states_per_draw: int = STATES_PER_DRAW) -> Summary:
    """Run every check by ``engines`` (default: every engine of the registry that applies) on ``examples`` hypothesis
    states (default: the profile's ``max_examples``; rounded up to whole parameter draws), drawn in batches of
    ``states_per_draw`` (:data:`~harness.compare.strategies.STATES_PER_DRAW`) with one parameter draw each: first
    the system's states (:func:`~harness.compare.strategies.system_states`, which its printed equations are checked
    on too); on a failure, hypothesis runs the check from the same seed, meets it and shrinks the batch, and the
    failing state is reported (should hypothesis not meet it, the failing state of the system's states, unshrunk:
    a failure found is never dropped, as in the claims' :func:`~harness.compare.claims._run`)."""
    summary = Summary(system.name)
    engines = tuple(ENGINES) if engines is None else tuple(engines)
    summary.not_applicable = {e: ENGINES[e].applies(system) for e in engines if ENGINES[e].applies(system)}
    engines = tuple(e for e in engines if e not in summary.not_applicable)

    def check(batch: list[State]):
        for state in batch:
            findings = evaluate_all(state, engines, pin_urdf, mj_xml)
            summary.examples += 1
            summary.record(findings)
            for f in findings:
                if not f.passed:
                    raise ConformanceFailure(f, state)

    with profiling.phase("derivation and compilation"):
        compiled(system).warm()
    draws_seen: set = set()

    @functools.wraps(check)  # check's source, hence its seed: counting the draws changes no example
    def counted(batch: list[State]):
        draws_seen.add(batch[0].parameters_key)  # shared by the batch
        summary.parameter_draws = len(draws_seen)
        return check(batch)

    met = None  # the failure on the system's states, if one
    with profiling.phase("conformance"), models_kept(KEPT_MODELS):
        if states_per_draw == STATES_PER_DRAW:  # first the system's states (every oracle checks them)
            try:
                for batch in system_states(system, examples, random_parameters):
                    counted(batch)
                return summary
            except ConformanceFailure as failure:  # hypothesis meets it again from the same seed, and shrinks it
                met = failure
                summary.examples, summary.parameter_draws = 0, 0
                summary.worst.clear()
                draws_seen.clear()
        test = property_test(draws(system, states_per_draw, random_parameters), counted,
                             hypothesis_examples(examples, states_per_draw), seed=states_seed(system))
        try:
            test()
        except ConformanceFailure as failure:  # the shrunk (minimal) counterexample
            met = failure
        if met is not None:  # hypothesis did not meet it again: the failing state itself, unshrunk
            summary.failure = str(met)
            summary.record([met.check])
    return summary
