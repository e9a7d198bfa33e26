"""Hypothesis strategies that *build* valid physical objects instead of filtering invalid ones away.

* Positive parameters are drawn log-uniformly in ``[default/2, 2·default]``; real ones around the default; one with
  a ``range`` uniformly in it.
* Diagonal inertia tensors whose entries are parameters are drawn jointly from the second moments of
  the mass distribution ``a, b, c > 0`` (``∫x² dm`` …): ``I_xx = b + c``, ``I_yy = a + c``, ``I_zz = a + b``
  is positive definite and satisfies the triangle inequality by construction (3.128). A tensor whose six entries
  are parameters (products of inertia: a body not aligned with its frame) is that diagonal turned by a rotation
  drawn uniformly (Shoemake's quaternion), ``R diag(b + c, a + c, a + b) Rᵀ``: its products drawn one by one made
  a tensor with a negative principal moment (a user's arm: −0.48 kg m²), a failure of the draw, not of the model.
* States: angles in ``[-π, π]``, lengths within ±1 m, rates within ±5 per second, inputs within ±10.
* A conformance run and a printed equation's classification draw their states in batches (:func:`draws`): one
  parameter draw, then :data:`STATES_PER_DRAW` states ``(q, q̇, u)`` of the system with those parameters.
* Both check first the same states of a system (:func:`system_states`), drawn once per process from a seed of the
  system's name: hypothesis runs the check itself (and shrinks) only where one of them fails.
"""

from __future__ import annotations

import hashlib
import math

import numpy as np
from hypothesis import settings, strategies as st

from harness import kept, profiling
from harness.engines.base import State
from harness.errors import HarnessError
from harness.modeling.system import System

ANGLE = math.pi
LENGTH = 1.0
RATE = 5.0
INPUT = 10.0

STATES_PER_DRAW = 2
"""States a conformance run (and a claim's classification) checks per parameter draw (:func:`draws`): each engine
builds its model of a parameter draw once (from the exported text) and evaluates it at these states. 200 states per
check (the ``ci`` profile) are 100 parameter draws, 49–91 of them distinct when measured (46–93 with the states
drawn from the systems' names; hypothesis repeats some; with one state per draw, 111–171 distinct of 200). The
engines' models built from the exported text (MuJoCo 2–5 ms each) and
hypothesis's per-example machinery were most of a check: ``conformance.run(system, states_per_draw=k)`` over the
catalogue in one process took 54.2–62.8 CPU s with k = 1, 33.9–40.8 with 2, 21.7–24.2 with 4 (24–45 distinct draws),
16.5–17.4 with 8. Two keeps half the distinct draws for half of what eight saves: an export fault that shows only for
a fraction ``p`` of the parameter values (a quaternion's hemisphere, a principal axis' sign) is missed by 49 distinct
draws with probability ``(1 − p)^49``, 8 % for ``p`` = 0.05 (111 draws: 0.3 %; 24 draws: 29 %)."""


def _float(lo: float, hi: float):
    return st.floats(min_value=lo, max_value=hi, allow_nan=False, allow_infinity=False, width=64)


def _positive(default: float):
    return _float(math.log(default / 2), math.log(default * 2)).map(math.exp)




def _inertia_groups(system: System) -> list[tuple[str, ...]]:
    """Parameter names of the links whose inertia entries are plain parameters: ``(I_xx, I_yy, I_zz)`` of a diagonal
    tensor, ``(I_xx, I_yy, I_zz, I_xy, I_xz, I_yz)`` of a full one."""
    names = {p.symbol: p.name for p in system.parameters}
    groups = []
    for link in system.links:
        I = link.inertia.matrix
        diagonal = [I[0, 0], I[1, 1], I[2, 2]]
        off = [I[0, 1], I[0, 2], I[1, 2]]
        if all(d in names for d in diagonal) and all(o == 0 for o in off):
            groups.append(tuple(names[d] for d in diagonal))
        elif all(e in names for e in diagonal + off) and len(set(diagonal + off)) == 6:
            groups.append(tuple(names[e] for e in diagonal + off))
    return groups


def _rotation(u1: float, u2: float, u3: float) -> np.ndarray:
    """The rotation of the unit quaternion ``(√(1−u₁) sin 2πu₂, √(1−u₁) cos 2πu₂, √u₁ sin 2πu₃, √u₁ cos 2πu₃)``:
    uniformly distributed for ``u`` uniform in ``[0, 1]³`` (Shoemake 1992)."""
    x, y = math.sqrt(1 - u1) * math.sin(2 * math.pi * u2), math.sqrt(1 - u1) * math.cos(2 * math.pi * u2)
    z, w = math.sqrt(u1) * math.sin(2 * math.pi * u3), math.sqrt(u1) * math.cos(2 * math.pi * u3)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def _span(lo: float, hi: float) -> str:
    return f"[{lo:.4g}, {hi:.4g}]"


def _coordinate_span(c) -> tuple[float, float]:
    """The span a coordinate is drawn from: its ``range``, else ``±ANGLE`` for an angle, ``±LENGTH`` otherwise."""
    return tuple(c.range) if c.range else (-ANGLE, ANGLE) if c.unit == "rad" else (-LENGTH, LENGTH)


def _parameter_draw(p) -> tuple:
    """``(strategy, what it draws as the system page says it)`` of a parameter outside an inertia group: its
    ``range``; a positive one log-uniform in ``[default/2, 2 default]``; a real one within ``max(|default|, 0.5)`` of
    its default; a nonnegative one in ``[0, 2 default]``."""
    if p.range:
        return _float(*p.range), _span(*p.range)
    if p.assumption == "positive":
        return _positive(p.default), _span(p.default / 2, 2 * p.default) + " (log-uniform)"
    if p.assumption == "real":
        spread = max(abs(p.default), 0.5)
        return _float(p.default - spread, p.default + spread), _span(p.default - spread, p.default + spread)
    return _float(0, 2 * p.default), _span(0, 2 * p.default)


def drawn_spans(system: System) -> tuple[dict[str, str], dict[str, str], str]:
    """What the checks draw from, as the system page says it: each coordinate's span and each parameter's (those
    :class:`_Plan` draws from), and one sentence for the rates and inputs."""
    groups = _inertia_groups(system)
    p = {}
    for x in system.parameters:
        group = next((g for g in groups if x.name in g), None)
        p[x.name] = _parameter_draw(x)[1] if group is None else (
            "a valid inertia tensor: second moments in [½, 2] × the default's, each at least 1e-3 × its largest "
            "principal moment (log-uniform)" + (", principal axes turned at random" if len(group) == 6 else ""))
    inputs = f", inputs in {_span(-INPUT, INPUT)} (their units)" if system.inputs else ""
    return ({c.name: _span(*_coordinate_span(c)) for c in system.coordinates}, p,
            f"rates q̇ in {_span(-RATE, RATE)} (the coordinate's unit per second){inputs}")


class _Plan:
    """The strategies of one system's parameters and states, built once (not at every draw): building a mapped
    strategy, its validation, and the SymPy inertia matrices :func:`_inertia_groups` reads cost more than the draw.
    The draws, their order and their spans are those of building them at each draw: the same examples."""

    def __init__(self, system: System):
        self.groups = []
        for group in _inertia_groups(system):
            defaults = np.array([system.parameter(n).default for n in group])
            if len(group) == 6:  # principal moments of the default tensor
                xx, yy, zz, xy, xz, yz = defaults
                xx, yy, zz = np.linalg.eigvalsh(np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]))
            else:
                xx, yy, zz = defaults
            # second moments of the default tensor, each kept strictly positive
            a0, b0, c0 = (yy + zz - xx) / 2, (xx + zz - yy) / 2, (xx + yy - zz) / 2
            scale = max(xx, yy, zz)
            turn = [_float(0.0, 1.0)] * 3 if len(group) == 6 else []
            self.groups.append((group, [_positive(max(m, 1e-3 * scale)) for m in (a0, b0, c0)] + turn))
        grouped = {n for group, _ in self.groups for n in group}
        self.others = [(p.name, _parameter_draw(p)[0]) for p in system.parameters if p.name not in grouped]
        self.q = [_float(*_coordinate_span(c)) for c in system.coordinates]
        self.qd = [_float(-RATE, RATE) for _ in system.coordinates]
        self.u = [(i.name, _float(-INPUT, INPUT)) for i in system.inputs]
        self.parameters = _parameters(self)


_PLANS: dict[int, tuple] = {}


def _plan(system: System) -> _Plan:
    entry = _PLANS.get(id(system))
    if entry is None or entry[0] is not system:  # the system is kept alive: its id is not reused meanwhile
        entry = _PLANS[id(system)] = (system, _Plan(system))
    return entry[1]


@st.composite
def _parameters(draw, plan: _Plan) -> dict[str, float]:
    values: dict[str, float] = {}
    for group, strategies in plan.groups:
        a, b, c, *turn = (draw(s) for s in strategies)
        if turn:
            R = _rotation(*turn)
            I = R @ np.diag([b + c, a + c, a + b]) @ R.T
            values.update(dict(zip(group, map(float, (I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2])))))
        else:
            values.update(dict(zip(group, (b + c, a + c, a + b))))
    for name, strategy in plan.others:
        values[name] = draw(strategy)
    return values


def parameters(system: System):
    """Random valid parameter values of ``system`` (a strategy of dicts)."""
    return _plan(system).parameters


@st.composite
def draws(draw, system: System, states_per_draw: int = STATES_PER_DRAW, random_parameters: bool = True) -> list[State]:
    """One random parameter draw of ``system`` and ``states_per_draw`` random states ``(q, q̇, u)`` with it (a list of
    :class:`State` sharing its parameters: one model per engine evaluates them all)."""
    with profiling.phase("draw states"):
        plan = _plan(system)
        params = draw(plan.parameters) if random_parameters else system.default_parameters()
        out = []
        for _ in range(states_per_draw):
            q = [draw(s) for s in plan.q]
            qd = [draw(s) for s in plan.qd]
            u = {name: draw(s) for name, s in plan.u}
            out.append(State.make(system, q, qd, params, u))
        return out


def hypothesis_examples(examples: int | None = None, states_per_draw: int = STATES_PER_DRAW) -> int:
    """The hypothesis examples (parameter draws) of a run of ``examples`` states (default: the profile's
    ``max_examples``), ``states_per_draw`` states each, rounded up."""
    states = settings.default.max_examples if examples is None else examples
    return -(-states // states_per_draw)


def states_seed(system: System) -> int | None:
    """The seed :func:`system_states` draws from, and every oracle's hypothesis run that must meet the same states
    first: the run's ``--seed`` (:func:`harness.settings.apply_seed`); with a derandomized profile one derived from
    the system's name (the states do not change with our code: two runs of different commits check the same
    states); in a random profile a random one, drawn once per process and system."""
    import random

    import hypothesis.core

    if hypothesis.core.global_force_seed is not None:
        return hypothesis.core.global_force_seed
    if settings.default.derandomize:
        return int.from_bytes(hashlib.sha256(f"states of {system.name}".encode()).digest()[:8], "big")
    return _RANDOM_SEEDS.setdefault(system.name, random.SystemRandom().getrandbits(64))


_RANDOM_SEEDS: dict = {}


def system_states(system: System, examples: int | None = None, random_parameters: bool = True) -> list[list[State]]:
    """The states every oracle of ``system`` checks first, in order, a list per parameter draw: ``examples`` states
    (default: the profile's ``max_examples``), :data:`STATES_PER_DRAW` per draw (:func:`draws`), as hypothesis draws them from
    :func:`states_seed` for a check that never fails. Drawn once per process and settings: the conformance run and
    every printed equation of the system are checked on the same states, each source evaluated once at each
    (:mod:`harness.compare.evaluations`); where a check fails on one, hypothesis runs that check from the same seed,
    meets the failure at the same state and shrinks it. Where the settings fix the examples, they are kept on disk
    (:func:`_kept_path`) and read back by the next run with the same code and settings."""
    from harness.settings import property_test

    import hypothesis.core

    key = (id(system), examples, random_parameters, settings.default.max_examples, settings.default.derandomize,
           hypothesis.core.global_force_seed)
    hit = _STATES.get(key)
    if hit is not None and hit[0] is system:  # the system is kept alive with its states: its id is not reused
        return hit[1]
    path = _kept_path(system, examples, random_parameters)
    seen = _read_kept(path, system) if path is not None else None
    if seen is None:
        seen = []

        def record(batch):
            seen.append(batch)

        property_test(draws(system, STATES_PER_DRAW, random_parameters), record,
                      hypothesis_examples(examples, STATES_PER_DRAW), shrink=False, seed=states_seed(system))()
        if path is not None:
            _keep(path, seen)
    else:
        profiling.count("system states read back")
    if len(_STATES) >= 256:
        _STATES.clear()
    _STATES[key] = (system, seen)
    return seen


_STATES: dict = {}


# --------------------------------------------------------------------------- what a run keeps for the next on disk
def kept_path(kind: str, system: System, examples: int | None, random_parameters: bool = True, *check: str):
    """Where a run keeps what hypothesis decided from ``system``'s seed for the next run (``kind/`` beside the
    derivation cache: ``states`` of :func:`system_states`, ``counterexamples`` of
    :mod:`harness.compare.claims`), under a hash of all that decides it: our code, the installed packages and Python
    (:func:`harness.kept.installation`: hypothesis's version among them), the system's strategies (its
    parameters' defaults and assumptions, its coordinates' ranges, its inputs), the number of states, the settings,
    the seed and ``check`` (what a check evaluates, in words and SymPy's ``srepr``). None where the settings do not
    fix the examples (:func:`harness.settings.fixed_examples`: a random seed, an example database). Drawing the
    states (hypothesis's generation) took 0.18–0.20 CPU s a system, reading them back and making the states again
    0.04–0.06 s (the catalogue in one process)."""
    from harness.settings import fixed_examples

    fixed = fixed_examples()
    if fixed is None:
        return None
    plan = _plan(system)
    parts = [system.name, repr(plan.groups), repr(plan.others), repr(plan.q), repr(plan.qd),
             repr(plan.u), repr(sorted(system.default_parameters().items())),
             repr((examples, random_parameters, STATES_PER_DRAW, settings.default.max_examples, states_seed(system),
                   fixed)), *check]
    return kept.path(kind, system.name, *parts)


def _kept_path(system: System, examples: int | None, random_parameters: bool):
    return kept_path("states", system, examples, random_parameters)


def state_record(state: State) -> dict:
    """A state as JSON (Python writes each float's shortest exact text: read back, the same bits)."""
    return {"q": state.q.tolist(), "qd": state.qd.tolist(), "u": state.u, "params": state.params}


def state_from(system: System, record: dict) -> State:
    """The state of :func:`state_record`, made again (:meth:`State.make`)."""
    return State.make(system, record["q"], record["qd"], record["params"], record["u"])


def _keep(path, batches: list[list[State]]) -> None:
    kept.keep(path, [[state_record(s) for s in batch] for batch in batches])


def _read_kept(path, system: System) -> list[list[State]] | None:
    """The kept states, made again (each number's bits as drawn); None when absent, damaged or not states of
    ``system`` (then they are drawn again)."""
    doc = kept.read_kept(path)
    try:
        return None if doc is None else [[state_from(system, s) for s in batch] for batch in doc]
    except (ValueError, KeyError, TypeError, HarnessError):
        return None


