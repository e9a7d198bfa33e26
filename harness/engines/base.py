"""What every engine adapter takes (a :class:`State`) and gives (an :class:`Evaluation`), and the map of
tree-joint quantities to lecture coordinates by virtual work (5.58)-(5.60)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cache, cached_property

import numpy as np
import sympy as sp

from harness import limits
from harness.derivation.compile import compiled
from harness.errors import InputError
from harness.export.numeric import NumericTree, instantiate
from harness.modeling.system import System


@dataclass(frozen=True)
class State:
    """A system at ``(q, q̇)`` with parameter values and inputs, all in lecture coordinates and names."""

    system: System
    q: np.ndarray
    qd: np.ndarray
    params: dict
    u: dict

    @staticmethod
    def make(system: System, q, qd=None, params: dict | None = None, u: dict | None = None) -> "State":
        n = len(system.coordinates)
        qd = np.zeros(n) if qd is None else qd
        names = ", ".join(c.name for c in system.coordinates)
        for label, vec in (("q", q), ("qd", qd)):
            if len(vec) != n:
                raise InputError(f"{system.name}: --{label} needs {n} value(s) ({names}), got {len(vec)}")
            if not all(math.isfinite(float(v)) for v in vec):
                raise InputError(f"{system.name}: --{label} must be finite numbers, got {list(vec)}")
            if any(abs(float(v)) > limits.MAGNITUDE for v in vec):
                raise InputError(f"{system.name}: --{label} {list(vec)}: exceeds {limits.MAGNITUDE:g} in magnitude "
                                 "(harness.limits.MAGNITUDE: results would overflow)")
        values = system.default_parameters()
        for name, value in (params or {}).items():
            system.parameter(name).check(float(value))
            try:
                limits.check_magnitude(f"parameter {name}", float(value))
            except ValueError as exc:
                raise InputError(f"{system.name}: {exc}") from None
            values[name] = float(value)
        inputs = {i.name: 0.0 for i in system.inputs}
        for name, value in (u or {}).items():
            if name not in inputs:
                known = ", ".join(inputs) or "none"
                raise InputError(f"{system.name}: unknown input {name!r} (inputs: {known})")
            if not math.isfinite(float(value)):
                raise InputError(f"{system.name}: input {name} must be finite")
            if abs(float(value)) > limits.MAGNITUDE:
                raise InputError(f"{system.name}: input {name}={value!r}: exceeds {limits.MAGNITUDE:g} in magnitude")
            inputs[name] = float(value)
        state = State(system, np.asarray(q, dtype=float), np.asarray(qd, dtype=float), values, inputs)
        state.tree  # instantiating checks that masses and inertia tensors are physical
        return state

    @property
    def p(self) -> np.ndarray:
        return np.array([self.params[p.name] for p in self.system.parameters])

    @property
    def u_vec(self) -> np.ndarray:
        return np.array([self.u[i.name] for i in self.system.inputs])

    @cached_property
    def tree(self) -> NumericTree:
        return instantiate(self.system, self.params)

    # ----- the map theta = phi(q)
    @cached_property
    def _map(self):
        c = compiled(self.system)
        args = (self.q, self.qd, self.p, self.u_vec)
        return c("phi", *args).ravel(), c("J_phi", *args), c("J_phi_dot", *args)

    @property
    def theta(self) -> np.ndarray:
        return self._map[0]

    @property
    def J(self) -> np.ndarray:
        """``J = ∂phi/∂q``."""
        return self._map[1]

    @property
    def J_dot(self) -> np.ndarray:
        return self._map[2]

    @property
    def theta_dot(self) -> np.ndarray:
        return self.J @ self.qd

    @cached_property
    def loads(self) -> list["Load"]:
        """External forces and torques of the model (PointForce, BodyTorque) with their components
        evaluated at this state; each engine turns them into generalized forces with its own Jacobians."""
        args = (self.q, self.qd, self.p, self.u_vec)
        return [Load(kind, where, frame, np.asarray(fn(*args), dtype=float).ravel())
                for kind, where, frame, fn in load_functions(self.system)]


@cache
def load_functions(system: System) -> list:
    """``(kind, point or link, frame, compiled components)`` of each external load, compiled once."""
    from harness.export.numeric import point_name
    from harness.modeling.system import BodyTorque, PointForce

    args = [system.q, system.qd, system.p, system.u]
    out = []
    for f in system.forces:
        if isinstance(f, PointForce):
            out.append(("force", point_name(f.point), f.frame, sp.lambdify(args, sp.Matrix(f.force), "numpy")))
        elif isinstance(f, BodyTorque):
            out.append(("torque", f.link, f.frame, sp.lambdify(args, sp.Matrix(f.torque), "numpy")))
    return out


@dataclass(frozen=True)
class Load:
    """A force at a named point, or a torque on a link, components in ``frame`` (world or a link)."""

    kind: str
    where: str
    frame: str
    vector: np.ndarray


@dataclass
class Evaluation:
    """Quantities in lecture coordinates. ``C`` is the Christoffel C where the engine gives it, else None.
    ``calls`` names the engine calls that produced the numbers."""

    engine: str
    M: np.ndarray
    Cqd: np.ndarray
    g: np.ndarray
    g_gravity: np.ndarray
    g_spring: np.ndarray
    f_damper: np.ndarray
    qdd: np.ndarray
    C: np.ndarray | None = None
    extra: dict = field(default_factory=dict)
    calls: dict = field(default_factory=dict)


@dataclass
class TreeQuantities:
    """An engine's numbers in its own tree joint coordinates ``theta`` (ordered as ``System.joints``)."""

    M: np.ndarray                  # M_theta
    Cqd: np.ndarray                # (C theta_dot)_theta
    g_gravity: np.ndarray
    g_spring: np.ndarray           # = -(spring generalized forces)
    f_damper: np.ndarray
    tau_input: np.ndarray          # generalized forces of the inputs
    qdd: np.ndarray | None         # theta_ddot from the engine's forward dynamics with the inputs
    C: np.ndarray | None = None    # Christoffel C_theta, = ½ ∂(C theta_dot)/∂theta_dot
    extra: dict = field(default_factory=dict)
    calls: dict = field(default_factory=dict)


def coriolis_to_lecture(state: State, M_theta: np.ndarray, C_theta: np.ndarray) -> np.ndarray:
    """``C_q = Jᵀ (M_θ J̇ + C_θ J)``: half the q̇-derivative of the mapped ``C q̇`` (quadratic in q̇)."""
    return state.J.T @ (M_theta @ state.J_dot + C_theta @ state.J)


def to_lecture(engine: str, state: State, t: TreeQuantities) -> Evaluation:
    """Bring tree-joint quantities to lecture coordinates with ``J = ∂phi/∂q`` (5.58)-(5.60):
    ``M_q = Jᵀ M J``, ``(C q̇)_q = Jᵀ (M J̇ q̇ + C θ̇)``, ``g_q = Jᵀ g``, ``C_q = Jᵀ (M J̇ + C_θ J)``.
    Forward dynamics: ``q̈ = J⁻¹ (θ̈ − J̇ q̇)`` when the map is square, else solved from the mapped terms."""
    J, Jd, qd = state.J, state.J_dot, state.qd
    M = J.T @ t.M @ J
    Cqd = J.T @ (t.M @ (Jd @ qd) + t.Cqd)
    g_gravity, g_spring, f_damper = J.T @ t.g_gravity, J.T @ t.g_spring, J.T @ t.f_damper
    C = None if t.C is None else coriolis_to_lecture(state, t.M, t.C)
    if t.qdd is not None and J.shape[0] == J.shape[1]:
        qdd = np.linalg.solve(J, t.qdd - Jd @ qd)
    else:  # more tree joints than lecture coordinates: the map is a constraint; (5.93) in q
        qdd = np.linalg.solve(M, J.T @ t.tau_input + f_damper - Cqd - g_gravity - g_spring)
    # The map multiplies the tree's round-off: scales of the mapped terms (|J|, |J̇| times the tree terms),
    # used by the tolerance policy so that a large J (a small rolling radius) is not mistaken for an error.
    a, ad = _max_abs(J), _max_abs(Jd)
    extra = dict(t.extra)
    extra["map_scale"] = {"M": a * a * _max_abs(t.M),
                          # C_θ is made of terms of size |M_θ| |θ̇| even where they cancel (a pulley turning
                          # about its centre of mass: C_θ = 0 up to Pinocchio's round-off of m v ω terms)
                          "C": max(a * a * _max_abs(t.C) + a * ad * _max_abs(t.M),
                                   _max_abs(np.abs(J).T @ np.abs(t.M) @ np.abs(J)) * max(1.0, _max_abs(J @ qd))),
                          "Cqd": a * (_max_abs(t.M) * ad * _max_abs(qd) + _max_abs(t.Cqd)),
                          "g": a * max(_max_abs(t.g_gravity), _max_abs(t.g_spring)),
                          "g_spring": a * _max_abs(t.g_spring), "f_damper": a * _max_abs(t.f_damper)}
    return Evaluation(engine, M, Cqd, g_gravity + g_spring, g_gravity, g_spring, f_damper, qdd, C,
                      extra=extra, calls=dict(t.calls))


def _max_abs(x) -> float:
    return float(np.max(np.abs(x))) if x is not None and np.size(x) else 0.0
