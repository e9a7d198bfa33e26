"""Structural changes a scene declares (``Scene.events``): value objects naming what switches and by which
parameters. How each is simulated with every source: its plug-in in :mod:`harness.scenes.phenomena`."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import sympy as sp

from harness.modeling.system import name_of, plain, value_at


def _normalised(event) -> None:
    """Fields naming a parameter/coordinate/link hold its name; expressions hold plain symbols."""
    for f in dataclasses.fields(event):
        if f.type == "bool":
            continue
        value = getattr(event, f.name)
        object.__setattr__(event, f.name, name_of(value) if f.type == "str" else plain(value))


@dataclass(frozen=True)
class StickSlip:
    """Coulomb friction on ``coordinate`` with static ``mu_H`` and sliding ``mu_C`` (parameters, held by name)
    and the normal force ``normal_force`` (an expression in the parameters, (3.76b)). ``held``: proved to stick
    from rest over the scene's whole horizon (:func:`harness.scenes.effects.sticks_throughout`; set by the
    pruning, :meth:`harness.scenes.effects.Inferred.pruned`, never by a model): the stick branch is never left."""

    coordinate: str
    mu_H: str
    mu_C: str
    normal_force: sp.Expr
    held: bool = False

    def __post_init__(self):
        _normalised(self)

    def values(self, params: dict) -> tuple[float, float, float]:
        return params[self.mu_H], params[self.mu_C], value_at(self.normal_force, params)


@dataclass(frozen=True)
class RollSlip:
    """A sphere (``link``, radius parameter ``radius``) on a plane with roll-pitch-yaw ``plane_rpy`` through
    the sphere's centre's start minus ``radius`` along the normal; the plane's ``x`` axis is the slope.
    ``threshold`` is the predicted friction coefficient that separates rolling from slipping (an expression
    in the parameters, 2/7 tan(alpha) for Exercise 3.17); ``mu`` the coefficient of this scene."""

    link: str
    radius: str
    plane_rpy: tuple
    threshold: sp.Expr
    mu: float
    slide_joint: str
    roll_joint: str

    def __post_init__(self):
        _normalised(self)

    def predicted(self, params) -> float:
        return value_at(self.threshold, params)


@dataclass(frozen=True)
class LiftOff:
    """Phase 1 (the scene's system, a point held on the ground by a constraint) until the ground's normal force
    vanishes, then ``free_system`` (phase 2). ``to_free``: the phase-2 coordinates as expressions of phase 1's
    (and the parameters); ``height``: the constrained point's height above the ground in phase-2 coordinates
    (≥ 0; the normal force acts along its gradient)."""

    free_system: str
    to_free: tuple
    height: sp.Expr

    def __post_init__(self):
        _normalised(self)
