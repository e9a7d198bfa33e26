"""Effects found, not declared: from a scene (its parameter values, inputs u(t), initial state and horizon) which
effects of :data:`harness.modeling.scenes.EFFECTS` can act at all, each one that cannot with its reason.

A scene still lists its effects by hand (``Scene.effects``, what :func:`harness.modeling.scenes.pruned` keeps);
:func:`infer` derives the set beside it, and a disagreement — a declared effect that cannot act, or an effect
that can act but is not declared — is reported (:mod:`harness.scenes.phenomena.pruning`), never silently fixed.
What is found idle — an effect type or a single force element inside an effect that acts (the quarter car's tyre
damper at ``d_R = 0`` beside its acting suspension damper) — is what the pruning measurement leaves out
(:meth:`Inferred.pruned`), and the pruned run equal to the idle one checks the inference.

What is inferred, each a proof on the model's expressions, not a sample of the motion:

* **springs, dampers**: a force element whose coefficient (stiffness, damping) is 0 with the scene's parameter
  values substituted; the effect is idle when every element of it is;
* **inputs**: a :class:`JointInput` whose signal is identically 0 over ``[0, horizon]`` (:func:`zero_over`: a
  constant 0, a step between zeros or after the horizon, a sine of amplitude and offset 0, a bump of height 0 or
  after the horizon; an input the scene does not drive is 0);
* **external**: a point force or body torque whose components are 0 with the scene's parameter values and its
  identically-zero inputs substituted (the quarter car's road force ``c_R x_U + d_R v_U`` on a smooth road);
* **gravity**: ``g = 0``, or gravity orthogonal to every motion the coordinates allow: ``∂V_gravity/∂q ≡ 0``
  (:attr:`Derivation.g_gravity` with the parameters substituted is the zero vector: checked at random states
  first, then proved by simplification), and where the map constrains the tree, to every motion of the tree too
  (no constraint row carries a weight: the engines simulate the constrained tree);
* **friction, contact**: they act only with their structural change (a :class:`StickSlip`, a :class:`RollSlip`
  event of the scene);
* **a friction that never switches** (:func:`sticks_throughout`): from rest, the force sticking needs,
  ``f_np(q_0, 0, u(t)) − g(q_0)`` (affine in the inputs), bounded over the horizon by ``|a| + Σ |b_i| sup |u_i|``
  (:func:`bound_over`: the exact supremum of each signal), stays within ``mu_H f_N``: the mass sticks over the
  whole horizon (3.80a), friction acts without switching, and the force elements that vanish at ``q̇ = 0`` (the
  sliding friction, dampers) cannot act; the pruned scene holds the friction (:attr:`StickSlip.held`): its run
  looks for no breakaway.

* **constraint rows** of a closed chain or coupling (the tree's, :mod:`harness.scenes.phenomena.closures`) that no
  state needs (:func:`constraint_rows_idle`): the tree's balance (3.104) at the motion's ``q̈`` proved 0 at every
  state, so the open tree keeps the constraints by itself (the governor's mirrored arms); a random state where it
  is not is the counterexample that the rows are needed (the toggle press, the trebuchet, every rope and gear).

Not inferred here (left as declared): contact the geometry cannot reach, which needs the
motion: the lecture's systems carry no collision geometry, and for the robot's real meshes it is proved along the
pruned run (:func:`harness.bench.contact_pruning.certified_contact_free`, a clearance bound at every step).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from harness.derivation.identities import identically_zero
from harness.modeling.events import RollSlip, StickSlip
from harness.modeling.scenes import _EFFECT_OF, EFFECTS, Bump, Constant, Scene, Sine, Step, effects_of, pruned
from harness.modeling.system import Damper, JointDamper, JointInput, JointSpring, PointForce, Spring, System

_EVENT_EFFECT = {StickSlip: "friction", RollSlip: "contact"}


def zero_over(signal, horizon: float) -> bool:
    """Whether ``signal`` is identically 0 on ``[0, horizon]`` (None: an input the scene does not drive, 0). A
    signal of a kind not known here is taken to act (a bound, not a guess)."""
    if signal is None:
        return True
    if isinstance(signal, Constant):
        return signal.value == 0
    if isinstance(signal, Step):
        return signal.before == 0 and (signal.after == 0 or signal.time > horizon)
    if isinstance(signal, Sine):
        return signal.offset == 0 and signal.amplitude == 0
    if isinstance(signal, Bump):
        return signal.height == 0 or signal.start >= horizon
    return False


def bound_over(signal, horizon: float) -> float | None:
    """``sup |signal(t)|`` over ``[0, horizon]``, or an upper bound of it (None: a signal of a kind not known
    here; 0 for an input the scene does not drive)."""
    if signal is None:
        return 0.0
    if isinstance(signal, Constant):
        return abs(signal.value)
    if isinstance(signal, Step):
        return max(abs(signal.before), abs(signal.after) if signal.time <= horizon else 0.0)
    if isinstance(signal, Sine):
        return abs(signal.offset) + abs(signal.amplitude)
    if isinstance(signal, Bump):
        if signal.start >= horizon:
            return 0.0
        return abs(signal.height) * (math.pi / signal.duration if signal.rate else 1.0)
    return None


def affine_bound(a: float, b, names, scene: Scene) -> float | None:
    """A bound of ``sup |a + Σ b_i u_i(t)|`` over the scene's horizon: ``|a| + Σ |b_i| sup |u_i|`` with each
    input's supremum (:func:`bound_over`, ``names`` the inputs of ``b``); None where a signal has no known bound."""
    sups = [bound_over(scene.inputs.get(name), scene.horizon) for name in names]
    if any(v is None for v in sups):
        return None
    return abs(float(a)) + sum(abs(float(x)) * v for x, v in zip(b, sups))


def sticks_throughout(system: System, scene: Scene, event: StickSlip) -> str | None:
    """Why the friction of ``event`` never switches over the scene's horizon (None: it may): the scene starts at
    rest and the force sticking needs at ``q_0`` (``M q̈`` with ``q̇ = 0``: ``f_np − g`` of the simulated model,
    affine in the inputs ``a + b u(t)``) is bounded by ``|a| + Σ |b_i| sup |u_i|`` within ``mu_H f_N`` (3.80a)."""
    from harness.derivation.derive import derive

    if any(scene.qd0) or len(system.coordinates) != 1:
        return None
    params = _values(system, scene)
    model = pruned(system, scene.effects)
    d = derive(model)
    at = {**{q: sp.Float(v) for q, v in zip(model.q, scene.q0)}, **{qd: sp.Integer(0) for qd in model.qd}}
    force = sp.expand(_substituted((d.f_np - d.g)[0].xreplace(at), params, set()))
    u = {i.symbol: i.name for i in model.inputs}
    if force.free_symbols - set(u):
        return None
    b = {x: sp.diff(force, x) for x in u}
    if any(sp.sympify(c).free_symbols for c in b.values()):
        return None
    bound = affine_bound(force.xreplace({x: 0 for x in u}), [b[x] for x in u], list(u.values()), scene)
    mu_H, _, f_N = event.values(params)
    if bound is None or bound > mu_H * f_N:
        return None
    return (f"sticks over [0, {scene.horizon:g}] s, never switches: from rest the force sticking needs is at most "
            f"{bound:.6g} N ≤ mu_H f_N = {mu_H * f_N:.6g} N (3.80a)")


@dataclass(frozen=True)
class Inferred:
    """The effects of one scene: ``declared`` (by hand), ``acting`` (inferred to be able to act), ``idle`` (an
    effect of the system or the scene that cannot act: its reason), ``idle_elements`` (force elements that
    cannot act inside an effect that can: their reasons), ``never_switches`` (an acting friction or contact
    whose structural change cannot happen over the horizon: the proof) and ``rows`` (a constrained tree's
    constraint rows: ``(inactive, the proof or the counterexample)``, :func:`constraint_rows_idle`; None without)."""

    declared: frozenset
    acting: frozenset
    idle: dict = field(default_factory=dict)
    idle_elements: dict = field(default_factory=dict)
    never_switches: dict = field(default_factory=dict)
    rows: tuple | None = None   # a constrained tree's rows: (inactive, why) (constraint_rows_idle); None: no rows

    @property
    def declared_idle(self) -> frozenset:
        """Declared, but cannot act in this scene (simulated for nothing)."""
        return frozenset(self.declared - self.acting)

    @property
    def undeclared_acting(self) -> frozenset:
        """Can act in this scene, but the scene leaves it out (the scene's choice: a modeling assumption)."""
        return frozenset(self.acting - self.declared)

    @property
    def agrees(self) -> bool:
        return self.declared == self.acting

    @property
    def simulated(self) -> frozenset:
        """The declared effects that can act: what a pruned run simulates (without :attr:`idle_elements`)."""
        return frozenset(self.declared - set(self.idle))

    def pruned(self, system: System, scene: Scene) -> tuple[System, Scene]:
        """``scene`` pruned by what is found idle: the system without the idle force elements
        (:func:`harness.modeling.scenes.pruned`), the scene with only :attr:`simulated`, and a friction that never
        switches held (its :class:`StickSlip` ``held``: the stick branch is not left, so no guard of its breakaway is
        evaluated); the two themselves when nothing the scene declares is idle."""
        held = "friction" in self.never_switches
        if not self.idle_elements and self.simulated == self.declared and not held:
            return system, scene
        events = tuple(dataclasses.replace(e, held=True) if held and isinstance(e, StickSlip) else e
                       for e in scene.events)
        return (pruned(system, EFFECTS, without=self.idle_elements),
                dataclasses.replace(scene, effects=self.simulated, events=events))

    def notes(self) -> dict:
        """The record's notes: the inferred set beside the declared one, the reasons, the disagreement."""
        out = {"effects declared": ", ".join(sorted(self.declared)) or "none",
               "effects inferred to act": ", ".join(sorted(self.acting)) or "none"}
        if self.idle:
            out["effects inferred idle"] = "; ".join(f"{k}: {v}" for k, v in sorted(self.idle.items()))
        if self.idle_elements:
            out["force elements inferred idle"] = "; ".join(f"{k}: {v}" for k, v in sorted(self.idle_elements.items()))
        if self.never_switches:
            out["never switches"] = "; ".join(f"{k}: {v}" for k, v in sorted(self.never_switches.items()))
        if self.rows is not None:
            out["constraint rows inferred inactive" if self.rows[0] else "constraint rows needed"] = self.rows[1]
        if self.declared_idle:
            out["effects disagreement: declared but cannot act"] = ", ".join(
                f"{e} ({self.idle.get(e, 'not in the system')})" for e in sorted(self.declared_idle))
        if self.undeclared_acting:
            out["effects disagreement: can act but not declared"] = ", ".join(sorted(self.undeclared_acting))
        return out


def _values(system: System, scene: Scene) -> dict:
    return {**system.default_parameters(), **scene.params}


def _substituted(expr, params: dict, zero_inputs: set):
    expr = sp.sympify(expr)
    subs = {}
    for x in expr.free_symbols:
        if x.name in params:
            subs[x] = sp.Float(params[x.name])
        elif x.name in zero_inputs:
            subs[x] = sp.Integer(0)
    return expr.xreplace(subs)


def _is_zero(expr) -> bool:
    expr = sp.sympify(expr)
    if expr.is_zero:
        return True
    return sp.simplify(expr) == 0


def _shown(expr, params: dict) -> str:
    if isinstance(sp.sympify(expr), sp.Symbol):
        return f"{expr} = 0"
    names = sorted(x.name for x in sp.sympify(expr).free_symbols if x.name in params)
    given = ", ".join(f"{n} = {params[n]:g}" for n in names)
    return f"{sp.sstr(expr)} = 0" + (f" at {given}" if given else "")


def _element_idle(f, params: dict, zero_inputs: set, scene: Scene, at_rest: set = frozenset()) -> str | None:
    """Why the force element ``f`` cannot act in the scene (None: it can); ``at_rest``: the velocity symbols
    proved 0 over the horizon (a friction that never switches)."""
    if isinstance(f, (Spring, JointSpring)):
        return _shown(f.stiffness, params) if _is_zero(_substituted(f.stiffness, params, set())) else None
    if isinstance(f, (Damper, JointDamper)):
        if at_rest:
            return "no motion: q̇ ≡ 0 over the horizon (the friction never switches)"
        return _shown(f.damping, params) if _is_zero(_substituted(f.damping, params, set())) else None
    if isinstance(f, JointInput):
        return f"input {f.input} ≡ 0 over [0, {scene.horizon:g}] s" if f.input in zero_inputs else None
    parts = f.force if isinstance(f, PointForce) else f.torque
    if at_rest and all(_is_zero(_substituted(sp.sympify(c).xreplace({v: 0 for v in at_rest}), params, zero_inputs))
                       for c in parts):
        return "0 at q̇ = 0, and q̇ ≡ 0 over the horizon (the friction never switches)"
    if all(_is_zero(_substituted(c, params, zero_inputs)) for c in parts):
        zeros = sorted({x.name for c in parts for x in sp.sympify(c).free_symbols} & zero_inputs)
        return "0" + (f": {', '.join(zeros)} ≡ 0 over [0, {scene.horizon:g}] s" if zeros else
                      " at the scene's parameters")
    return None


def gravity_idle(system: System, params: dict, samples: int = 3, seed: int = 0) -> str | None:
    """Why gravity cannot act (None: it can): ``g = 0``, or ``∂V_gravity/∂q ≡ 0`` with the parameters substituted
    (every motion the coordinates allow is orthogonal to gravity). Random states first (one nonzero value proves
    it acts), then the symbolic proof."""
    if system.gravity is None:
        return None
    if _is_zero(_substituted(system.gravity.g, params, set())):
        return _shown(system.gravity.g, params)
    from harness.derivation.compile import compiled
    from harness.derivation.derive import derive

    c, n = compiled(system), len(system.coordinates)   # compiled once per system: the check's, the scenes'
    p = [params[x.name] for x in system.parameters]
    rng = np.random.default_rng(seed)
    for _ in range(samples):
        value = c("g_gravity", rng.uniform(-1.0, 1.0, n), np.zeros(n), p, np.zeros(len(system.inputs)))
        if np.any(np.abs(value) > 1e-12):
            return None
    gq = sp.Matrix([_substituted(e, params, set()) for e in derive(system).g_gravity])
    if not all(_is_zero(e) for e in gq):
        return None
    if len(system.joints) > len(system.coordinates) and not _weights_load_no_row(system, params):
        return None   # the engines' constrained trees: the weights load the rows (a soft row yields to them)
    return "∂V_gravity/∂q ≡ 0: gravity is orthogonal to every motion the coordinates allow" + (
        ", and to every motion of the tree (no constraint row carries a weight)"
        if len(system.joints) > len(system.coordinates) else "")


def _weights_load_no_row(system: System, params: dict) -> bool:
    """Whether the weights' generalized forces on the tree joints (:func:`~harness.derivation.bodies.gravity_in_theta`)
    vanish at every state, proved (:func:`~harness.derivation.identities.identically_zero`, the parameters as exact
    rationals). Where a closed chain's rows carry a weight that does no work on the lecture coordinates (a piston's
    on its guide), gravity still acts in an engine that simulates the constrained tree: MuJoCo's soft equality rows
    yield to the load, its motion moves by the rows' compliance (6e-6 on a slider-crank, against the pruning check's
    1e-6). Not proved: it acts."""
    from harness.derivation.bodies import gravity_in_theta

    rows = gravity_in_theta(system)
    exact = {x: sp.Rational(repr(float(params[x.name]))) for x in rows.free_symbols if x.name in params}
    return all(identically_zero(e.xreplace(exact)) is True for e in rows)


_ROWS: dict = {}


def constraint_rows_idle(system: System, params: dict, samples: int = 3, seed: int = 0) -> tuple[bool, str]:
    """Whether the constraint rows of a constrained tree (more tree joints than lecture coordinates: the map's
    couplings and closures, :mod:`harness.scenes.phenomena.closures`) can act: ``(False, why they are needed)`` or
    ``(True, the proof that none can)``. The tree's balance :func:`~harness.derivation.bodies.joint_space_balance`
    at the motion's ``q̈ = M⁻¹ (f_np − C q̇ − g)`` is what the constraints must supply, ``Φᵀ λ`` (3.104). Where it is
    0 at every state ``(q, q̇, u)``, the constrained motion solves the open tree's equations with ``λ = 0``: the
    open tree's vector field is tangent to the constraint manifold ``{c = 0, ċ = 0}``, and by uniqueness the open
    tree started on it stays on it (the governor's two arms, mirror images, stay mirrored without the coupling).
    Random states first (a balance far above round-off is a counterexample: the rows are needed), then the proof
    with the parameters' values as exact rationals (:func:`~harness.derivation.identities.identically_zero`); not
    proved is needed (a bound, not a guess)."""
    from harness.derivation.bodies import joint_space_balance
    from harness.derivation.compile import compiled
    from harness.derivation.derive import derive

    if len(system.joints) <= len(system.coordinates):
        return False, "the map does not constrain the tree: no constraint rows"
    key = (system.fingerprint(), tuple(sorted((k, float(v)) for k, v in params.items())))
    if key in _ROWS:
        return _ROWS[key]
    balance = joint_space_balance(system)
    names = {x.name: x for x in balance.free_symbols}
    accels = [c.accel for c in system.coordinates]
    args = [*system.q, *system.qd, *accels, *(names.get(p.name, sp.Dummy()) for p in system.parameters),
            *(names.get(i.name, sp.Dummy()) for i in system.inputs)]
    f = sp.lambdify(args, list(balance), modules="numpy")
    c, p = compiled(system), [float(params[x.name]) for x in system.parameters]
    rng = np.random.default_rng(seed)
    for _ in range(samples):
        q = np.array([rng.uniform(*(float(v) for v in x.range)) if x.range is not None else rng.uniform(-1.0, 1.0)
                      for x in system.coordinates])
        qd, u = rng.uniform(-1.0, 1.0, len(q)), rng.uniform(-1.0, 1.0, len(system.inputs))
        qdd = c.forward_dynamics(q, qd, p, u)
        M, Cqd, g, f_np = c.terms(q, qd, p, u)
        needed = np.abs(np.asarray(f(*q, *qd, *qdd, *p, *u), dtype=float))
        scale = 1.0 + max(np.abs(M @ qdd).max(), np.abs(Cqd).max(), np.abs(g).max(), np.abs(f_np).max())
        if needed.max() > 1e-6 * scale:
            k = int(np.argmax(needed))
            unit = "N m" if system.joints[k].type == "revolute" else "N"
            _ROWS[key] = out = (False, (
                f"at q = {np.round(q, 4).tolist()}, q̇ = {np.round(qd, 4).tolist()}"
                + (f", u = {np.round(u, 4).tolist()}" if len(u) else "")
                + f" the tree's balance (3.104) asks the constraints for {needed[k]:.4g} {unit} in joint "
                  f"{system.joints[k].name}"))
            return out
    d = derive(system)
    qdd = d.M.LUsolve(d.f_np - d.C * sp.Matrix(system.qd) - d.g)
    exact = {x: sp.Rational(repr(float(params[x.name]))) for x in balance.free_symbols | set(qdd.free_symbols)
             if x.name in params}
    proved = all(identically_zero(e.xreplace(dict(zip(accels, qdd))).xreplace(exact)) is True for e in balance)
    _ROWS[key] = out = (proved, "the tree's balance (3.104) at the motion's q̈ is 0 at every state (proved), so "
                                "the open tree's motion keeps the constraints without a force" if proved
                        else "not proved inactive: the tree's balance at the motion's q̈ is small at random states "
                             "but not proved 0")
    return out


def infer(system: System, scene: Scene) -> Inferred:
    """The effects that can act in ``scene`` (see the module docstring), beside those it declares."""
    params = _values(system, scene)
    zero_inputs = {i.name for i in system.inputs if zero_over(scene.inputs.get(i.name), scene.horizon)}
    never = {"friction": why for e in scene.events if isinstance(e, StickSlip)
             for why in [sticks_throughout(system, scene, e)] if why is not None}
    at_rest = {c.rate for c in system.coordinates} if never else set()
    elements: dict[str, dict] = {}
    for f in system.forces:
        elements.setdefault(_EFFECT_OF[type(f)], {})[f.name] = _element_idle(f, params, zero_inputs, scene, at_rest)
    acting, idle, idle_elements = set(), {}, {}
    for effect, reasons in elements.items():
        if all(r is not None for r in reasons.values()):
            idle[effect] = "; ".join(f"{name}: {why}" for name, why in reasons.items())
        else:
            acting.add(effect)
            idle_elements.update({name: why for name, why in reasons.items() if why is not None})
    if system.gravity is not None:
        why = gravity_idle(system, params)
        if why is None:
            acting.add("gravity")
        else:
            idle["gravity"] = why
    events = {_EVENT_EFFECT[type(e)] for e in scene.events if type(e) in _EVENT_EFFECT}
    acting |= events
    for effect in set(scene.effects) - effects_of(system) - events:
        if effect in ("friction", "contact"):
            idle[effect] = f"acts only with its event ({'StickSlip' if effect == 'friction' else 'RollSlip'}), " \
                           "which the scene does not have"
        elif effect not in idle:
            idle[effect] = "the system has no such effect"
    return Inferred(frozenset(scene.effects), frozenset(acting), idle, idle_elements, never, scene_rows(system, scene))


def scene_rows(system: System, scene: Scene) -> tuple | None:
    """:func:`constraint_rows_idle` of the tree the scene simulates (its effects only, its parameter values); None
    where that tree has no constraint rows."""
    model = pruned(system, scene.effects)
    if len(model.joints) <= len(model.coordinates):
        return None
    return constraint_rows_idle(model, _values(system, scene))


def inferred_scene(system: System, scene: Scene) -> Scene:
    """``scene`` with the effects :func:`infer` finds able to act in place of the declared ones."""
    return dataclasses.replace(scene, effects=infer(system, scene).acting)


__all__ = ["EFFECTS", "Inferred", "affine_bound", "bound_over", "constraint_rows_idle", "gravity_idle", "infer",
           "inferred_scene", "scene_rows", "sticks_throughout",
           "zero_over"]
