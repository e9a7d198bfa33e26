"""Effects found, not declared: from a scene (its parameter values, inputs u(t), initial state and horizon) which
effects of :data:`harness.modeling.scenes.EFFECTS` can act at all, each one that cannot with its reason.

A scene still lists its effects by hand (``Scene.effects``, what :func:`harness.modeling.scenes.pruned` keeps);
:func:`infer` derives the set beside it, and a disagreement — a declared effect that cannot act, or an effect
that can act but is not declared — is reported (:mod:`harness.scenes.phenomena.pruning`), never silently fixed.

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
  first, then proved by simplification);
* **friction, contact**: they act only with their structural change (a :class:`StickSlip`, a :class:`RollSlip`
  event of the scene).

Not inferred (left as declared): contact the geometry cannot reach over the horizon, a friction that never
switches, an inactive closure.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from harness.modeling.events import RollSlip, StickSlip
from harness.modeling.scenes import _EFFECT_OF, EFFECTS, Bump, Constant, Scene, Sine, Step, effects_of
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


@dataclass(frozen=True)
class Inferred:
    """The effects of one scene: ``declared`` (by hand), ``acting`` (inferred to be able to act), ``idle`` (an
    effect of the system or the scene that cannot act: its reason) and ``idle_elements`` (force elements that
    cannot act inside an effect that can: their reasons)."""

    declared: frozenset
    acting: frozenset
    idle: dict = field(default_factory=dict)
    idle_elements: dict = field(default_factory=dict)

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

    def notes(self) -> dict:
        """The record's notes: the inferred set beside the declared one, the reasons, the disagreement."""
        out = {"effects declared": ", ".join(sorted(self.declared)) or "none",
               "effects inferred to act": ", ".join(sorted(self.acting)) or "none"}
        if self.idle:
            out["effects inferred idle"] = "; ".join(f"{k}: {v}" for k, v in sorted(self.idle.items()))
        if self.idle_elements:
            out["force elements inferred idle"] = "; ".join(f"{k}: {v}" for k, v in sorted(self.idle_elements.items()))
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


def _element_idle(f, params: dict, zero_inputs: set, scene: Scene) -> str | None:
    """Why the force element ``f`` cannot act in the scene (None: it can)."""
    if isinstance(f, (Spring, JointSpring)):
        return _shown(f.stiffness, params) if _is_zero(_substituted(f.stiffness, params, set())) else None
    if isinstance(f, (Damper, JointDamper)):
        return _shown(f.damping, params) if _is_zero(_substituted(f.damping, params, set())) else None
    if isinstance(f, JointInput):
        return f"input {f.input} ≡ 0 over [0, {scene.horizon:g}] s" if f.input in zero_inputs else None
    parts = f.force if isinstance(f, PointForce) else f.torque
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
    from harness.derivation.derive import derive

    gq = derive(system).g_gravity
    gq = sp.Matrix([_substituted(e, params, set()) for e in gq])
    free = sorted(gq.free_symbols, key=lambda s: s.name)
    rng = np.random.default_rng(seed)
    fn = sp.lambdify(free, list(gq), modules="numpy", cse=True)
    for _ in range(samples):
        value = np.asarray(fn(*rng.uniform(-1.0, 1.0, len(free))), dtype=float)
        if np.any(np.abs(value) > 1e-12):
            return None
    if all(_is_zero(e) for e in gq):
        return "∂V_gravity/∂q ≡ 0: gravity is orthogonal to every motion the coordinates allow"
    return None


def infer(system: System, scene: Scene) -> Inferred:
    """The effects that can act in ``scene`` (see the module docstring), beside those it declares."""
    params = _values(system, scene)
    zero_inputs = {i.name for i in system.inputs if zero_over(scene.inputs.get(i.name), scene.horizon)}
    elements: dict[str, dict] = {}
    for f in system.forces:
        elements.setdefault(_EFFECT_OF[type(f)], {})[f.name] = _element_idle(f, params, zero_inputs, scene)
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
    return Inferred(frozenset(scene.effects), frozenset(acting), idle, idle_elements)


def inferred_scene(system: System, scene: Scene) -> Scene:
    """``scene`` with the effects :func:`infer` finds able to act in place of the declared ones."""
    return dataclasses.replace(scene, effects=infer(system, scene).acting)


__all__ = ["EFFECTS", "Inferred", "gravity_idle", "infer", "inferred_scene", "zero_over"]
