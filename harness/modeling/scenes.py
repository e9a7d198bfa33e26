"""Scenes: a system + parameter values + initial state + inputs u(t) + horizon + the effects it calls for.

Only the effects a scene names are simulated: :func:`pruned` removes every other force element (and gravity)
from the system *before* it is derived and exported, so the symbolic right-hand side contains only those
terms and the exported MJCF has the other effects switched off by its flags.

Effects: ``gravity``; ``springs`` (Spring, JointSpring); ``dampers`` (Damper, JointDamper); ``inputs``
(JointInput); ``external`` (PointForce, BodyTorque: follower forces, drag, thrust, dry sliding friction);
``friction`` (dry friction with sticking, switched on in MuJoCo as ``frictionloss``) and ``contact`` (MuJoCo
contact with friction) come with a scene's structural change (``Scene.events``, :mod:`harness.scenes.phenomena`).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from harness.errors import HarnessError, InputError, ModelError
from harness.modeling.system import (BodyTorque, Damper, JointDamper, JointInput, JointSpring, Parameter, PointForce,
                                     Spring, System, name_of)

EFFECTS = ("gravity", "springs", "dampers", "inputs", "external", "friction", "contact")
_EFFECT_OF = {Spring: "springs", JointSpring: "springs", Damper: "dampers", JointDamper: "dampers",
              JointInput: "inputs", PointForce: "external", BodyTorque: "external"}


# --------------------------------------------------------------------------- input signals u(t)
@dataclass(frozen=True)
class Constant:
    value: float
    piecewise_constant = True

    def __call__(self, t: float) -> float:
        return self.value


@dataclass(frozen=True)
class Step:
    """``before`` until ``time``, then ``after``."""

    time: float
    after: float
    before: float = 0.0
    piecewise_constant = True

    def __call__(self, t: float) -> float:
        return self.after if t >= self.time else self.before

    @property
    def breakpoints(self) -> tuple:
        return (self.time,)


@dataclass(frozen=True)
class Sine:
    amplitude: float
    frequency: float          # Hz
    offset: float = 0.0
    phase: float = 0.0
    piecewise_constant = False

    def __call__(self, t: float) -> float:
        return self.offset + self.amplitude * math.sin(2 * math.pi * self.frequency * t + self.phase)


@dataclass(frozen=True)
class Bump:
    """A smooth road bump ``height (1 - cos(2π (t - start)/duration))/2`` on ``[start, start + duration]``;
    ``rate=True`` gives its time derivative (the road velocity)."""

    height: float
    start: float
    duration: float
    rate: bool = False
    piecewise_constant = False

    @property
    def breakpoints(self) -> tuple:
        return (self.start, self.start + self.duration)

    def __call__(self, t: float) -> float:
        if not self.start <= t <= self.start + self.duration:
            return 0.0
        w = 2 * math.pi / self.duration
        if self.rate:
            return self.height * w * math.sin(w * (t - self.start)) / 2
        return self.height * (1 - math.cos(w * (t - self.start))) / 2


# --------------------------------------------------------------------------- scenes
@dataclass(frozen=True)
class Scene:
    """One simulation taken from the lecture text. ``effects`` any collection of effect names; ``inputs`` and
    ``params`` keyed by name or by the model's :class:`Input` / :class:`Parameter`."""

    name: str
    description: str
    q0: tuple
    qd0: tuple
    horizon: float
    effects: frozenset
    inputs: dict = field(default_factory=dict)      # input name -> signal
    params: dict = field(default_factory=dict)      # parameter overrides
    events: tuple = ()                              # structural changes (harness/scenes/phenomena/)

    def __post_init__(self):
        object.__setattr__(self, "effects", frozenset(self.effects))
        for name in ("inputs", "params"):
            object.__setattr__(self, name, {name_of(k): v for k, v in getattr(self, name).items()})
        object.__setattr__(self, "inputs", {k: self._signal(k, v) for k, v in self.inputs.items()})
        unknown = set(self.effects) - set(EFFECTS)
        if unknown:
            raise InputError(f"scene {self.name}: unknown effect(s) {sorted(unknown)}; effects are {EFFECTS}")
        from harness.limits import SCENE_HORIZON

        try:
            horizon = float(self.horizon)
        except (TypeError, ValueError):
            raise InputError(f"scene {self.name}: horizon={self.horizon!r} is not a number") from None
        if not 0 < horizon <= SCENE_HORIZON:
            raise InputError(f"scene {self.name}: horizon={self.horizon!r} s must be positive and at most "
                             f"{SCENE_HORIZON:g} s (harness.limits.SCENE_HORIZON)")

    def _signal(self, name: str, value):
        """An input's signal u(t): a number is a :class:`Constant` (``inputs={"f": 0.2}`` had failed deep in a
        simulation with "'float' object is not callable"); anything else must be a signal of this module."""
        if isinstance(value, (int, float, np.number)) and not isinstance(value, bool):
            if not math.isfinite(float(value)):
                raise InputError(f"scene {self.name}: input {name}={value!r} must be finite")
            return Constant(float(value))
        if not callable(value):
            raise InputError(f"scene {self.name}: input {name}={value!r} is not a signal: give a number (a constant) "
                             "or Constant, Step, Sine, Bump (harness.modeling)")
        return value

    def u(self, t: float, system: System) -> np.ndarray:
        return np.array([self.inputs[i.name](t) if i.name in self.inputs else 0.0 for i in system.inputs])

    @property
    def breakpoints(self) -> list[float]:
        """Times where an input is not smooth: integration restarts there, so that an adaptive integrator
        cannot step over a short input (a road bump) or smear a jump."""
        times = {t for signal in self.inputs.values() for t in getattr(signal, "breakpoints", ())}
        return sorted(t for t in times if 0.0 < t < self.horizon)

    @property
    def inputs_vary_within_steps(self) -> bool:
        """True when an input changes continuously: MuJoCo holds ``ctrl`` over a step (zero-order hold)."""
        return any(not getattr(signal, "piecewise_constant", False) for signal in self.inputs.values())

    @property
    def conservative(self) -> bool:
        return not ({"dampers", "inputs", "external", "friction", "contact"} & set(self.effects))


def validate_scenes(system: System, scenes) -> None:
    """What a scene states of its system, checked when the module loads (not deep inside a simulation): a name of
    its own, ``q0`` and ``q̇0`` one finite number per coordinate, inputs that are the system's, parameter values
    for the system's parameters within their assumptions (or 0: an element the scene leaves idle). Raises
    :class:`~harness.errors.ModelError` naming the scene, the field and the fix."""
    coordinates = [c.name for c in system.coordinates]
    inputs = {i.name for i in system.inputs}
    parameters = {p.name: p for p in system.parameters}
    seen = set()
    for scene in scenes:
        if not isinstance(scene, Scene):
            raise ModelError(f"SCENES holds {type(scene).__name__}, not Scene")
        if scene.name in seen:
            raise ModelError(f"scene {scene.name}: the name is used twice; give each scene of {system.name} its own")
        seen.add(scene.name)
        for field_name in ("q0", "qd0"):
            values = getattr(scene, field_name)
            try:
                numbers = [float(v) for v in values]
            except (TypeError, ValueError):
                raise ModelError(f"scene {scene.name}: {field_name}={values!r} is not a sequence of numbers, one per "
                                 f"coordinate ({', '.join(coordinates)})") from None
            if len(numbers) != len(coordinates):
                raise ModelError(f"scene {scene.name}: {field_name} has {len(numbers)} value(s); {system.name} has "
                                 f"{len(coordinates)} coordinate(s) ({', '.join(coordinates)})")
            if not all(map(math.isfinite, numbers)):
                raise ModelError(f"scene {scene.name}: {field_name}={values!r} must be finite numbers")
        unknown = sorted(set(scene.inputs) - inputs)
        if unknown:
            raise ModelError(f"scene {scene.name}: {', '.join(unknown)} is not an input of {system.name} "
                             f"(inputs: {', '.join(sorted(inputs)) or 'none'})")
        for name, value in scene.params.items():
            if name not in parameters:
                raise ModelError(f"scene {scene.name}: {name} is not a parameter of {system.name} "
                                 f"(parameters: {', '.join(parameters)})")
            try:
                number = float(value)
            except (TypeError, ValueError):
                raise ModelError(f"scene {scene.name}: parameter {name}={value!r} is not a number") from None
            try:
                if number != 0:  # 0 of a positive coefficient: the scene's element is there, idle (pruning)
                    parameters[name].check(number)
            except HarnessError as exc:
                raise ModelError(f"scene {scene.name}: {exc}") from None
        for event in scene.events:
            _validate_event(system, scene, event)


def _validate_event(system: System, scene: "Scene", event) -> None:
    """The names an event of ``scene`` holds (:mod:`harness.modeling.events`) are the system's: a coordinate, a
    joint, a link, parameters."""
    from harness.modeling.events import RollSlip, StickSlip

    kinds = {"coordinate": [c.name for c in system.coordinates], "parameter": [p.name for p in system.parameters],
             "link": [link.name for link in system.links], "joint": [j.name for j in system.joints]}
    named = {StickSlip: {"coordinate": "coordinate", "mu_H": "parameter", "mu_C": "parameter"},
             RollSlip: {"link": "link", "radius": "parameter", "slide_joint": "joint", "roll_joint": "joint"}}
    for field_name, kind in named.get(type(event), {}).items():
        value = getattr(event, field_name)
        if value not in kinds[kind]:
            raise ModelError(f"scene {scene.name}: {type(event).__name__}.{field_name}={value!r} is not a {kind} of "
                             f"{system.name} ({kind}s: {', '.join(kinds[kind])})")


def effects_of(system: System) -> frozenset:
    """Every effect the system has."""
    found = {_EFFECT_OF[type(f)] for f in system.forces}
    if system.gravity is not None:
        found.add("gravity")
    return frozenset(found)


def pruned(system: System, effects, without=()) -> System:
    """The system with only ``effects``: other force elements and gravity removed, and the force elements named
    in ``without`` (those found idle, :func:`harness.scenes.effects.infer`) removed inside the kept effects."""
    effects, without = frozenset(effects), frozenset(without)
    forces = tuple(f for f in system.forces if _EFFECT_OF[type(f)] in effects and f.name not in without)
    gravity = system.gravity if "gravity" in effects else None
    if len(forces) == len(system.forces) and gravity is system.gravity:
        return system   # nothing left out: the system itself (a copy is built and validated again, 7 ms)
    return dataclasses.replace(system, forces=forces, gravity=gravity)


IDLE = Parameter("idle", 0.0, "1", "factor of every effect a scene does not call for (0: present but idle)",
                 assumption="nonnegative", range=(0.0, 1.0))


def idle(system: System, effects) -> System:
    """The system with *every* effect present, those not in ``effects`` multiplied by the parameter ``idle``
    (set to 0): the same motion as :func:`pruned`, at the cost of evaluating the idle terms. The pruning
    measurement compares the two."""
    effects, k = frozenset(effects), IDLE.symbol

    def scaled(f):
        if _EFFECT_OF[type(f)] in effects or isinstance(f, JointInput):  # an input not driven is already 0
            return f
        if isinstance(f, (Spring, JointSpring)):
            return dataclasses.replace(f, stiffness=k * f.stiffness)
        if isinstance(f, (Damper, JointDamper)):
            return dataclasses.replace(f, damping=k * f.damping)
        if isinstance(f, PointForce):
            return dataclasses.replace(f, force=tuple(k * c for c in f.force))
        return dataclasses.replace(f, torque=tuple(k * c for c in f.torque))

    gravity = system.gravity
    if gravity is not None and "gravity" not in effects:
        gravity = dataclasses.replace(gravity, g=k * gravity.g)
    return dataclasses.replace(system, forces=tuple(scaled(f) for f in system.forces), gravity=gravity,
                               parameters=system.parameters + (IDLE,))


def with_idle_effects(system: System, scene: "Scene") -> tuple[System, "Scene"]:
    """The idle-but-present counterpart of ``scene`` (see :func:`idle`); the scene itself when it calls for
    every effect the system has (nothing to prune)."""
    every = effects_of(system) | set(scene.effects)
    if every == set(scene.effects):
        return system, scene
    return idle(system, scene.effects), dataclasses.replace(scene, effects=frozenset(every),
                                                            params={**scene.params, IDLE.name: 0.0})
