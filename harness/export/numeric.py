"""A system's kinematic tree with numbers in place of parameters: what the exporters write and what the
round-trip check expects the engines to load."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

from harness.errors import ModelError
from harness.modeling.system import Damper, JointDamper, JointInput, JointSpring, Point, Spring, System
from harness.modeling.system import check_inertia  # noqa: F401  (re-exported: the physical-inertia check lives with the model)

# MuJoCo refuses moving bodies whose mass or a principal inertia is below mjMINVAL = 1e-15 (its compiler
# tests ``inertia < mjMINVAL``). A point mass (zero inertia tensor about its centre of mass) is exported to MJCF
# with the smallest isotropic inertia it accepts, mjMINVAL itself, as principal moments (``diaginertia``:
# a ``fullinertia`` passes an eigenvalue test that refuses values up to ~5e-15). This is not round-off but a
# stated model difference: each point mass adds ``ε J_ωᵀ J_ω`` to M (ε this value, J_ω its body's angular
# Jacobian), i.e. ``2ε`` on a diagonal of M of the governor (two arms) and ``ε`` of the spherical pendulum, and
# changes q̈ by up to ``k ε / λ_min(M)`` relative (k point masses turning with a coordinate). Against the
# tolerance 1e-12 κ(M) of q̈ that is ``k ε / (1e-12 λ_max(M))``: below 0.1 of it wherever λ_max(M) ≥
# k·0.01 kg m² (the catalogue's smallest, the governor's 2 m l² ≥ 0.125 kg m²: 0.016). With the former 1e-14
# it was 10x that: 0.15 of the tolerance of the governor's q̈ and (A.66a), (A.67a) against MuJoCo.
MUJOCO_POINT_MASS_INERTIA = 1e-15


@dataclass(frozen=True)
class NumericLink:
    name: str
    mass: float
    com: np.ndarray            # centre of mass in the link frame
    inertia: np.ndarray        # 3x3 about the centre of mass, link frame


@dataclass(frozen=True)
class NumericJoint:
    name: str
    type: str
    parent: str
    child: str
    axis: np.ndarray
    origin: np.ndarray
    rpy: np.ndarray
    armature: float = 0.0


@dataclass(frozen=True)
class NumericPoint:
    name: str
    link: str
    position: np.ndarray


@dataclass(frozen=True)
class NumericTree:
    system: str
    links: tuple[NumericLink, ...]
    joints: tuple[NumericJoint, ...]
    points: tuple[NumericPoint, ...]
    gravity: np.ndarray
    joint_stiffness: dict      # joint -> (stiffness, rest)
    joint_damping: dict        # joint -> damping
    tendons: tuple             # (name, point a, point b, stiffness, rest length, damping)
    actuators: tuple           # (input name, joint)


def _value(expr, subs) -> float:
    value = sp.sympify(expr).xreplace(subs)
    if not value.is_number:
        raise ModelError(f"cannot evaluate {expr} numerically (free symbols {value.free_symbols})")
    return float(value)


def lump(parts) -> tuple[float, np.ndarray, np.ndarray]:
    """Steiner's theorem (3.133): one rigid body from ``(m, c, I_c)`` parts given in common axes — its mass,
    centre of mass and (symmetric) inertia tensor about it. Parts without mass or inertia are left out; one
    part is returned as it is."""
    parts = [(float(m), np.asarray(c, dtype=float), np.asarray(I, dtype=float)) for m, c, I in parts
             if m > 0 or np.any(I)]
    if not parts:
        return 0.0, np.zeros(3), np.zeros((3, 3))
    if len(parts) == 1:
        return parts[0]
    mass = sum(m for m, _, _ in parts)
    com = sum(m * c for m, c, _ in parts) / mass if mass > 0 else np.zeros(3)
    inertia = np.zeros((3, 3))
    for m, c, I in parts:
        d = c - com
        inertia += I + m * (d @ d * np.eye(3) - np.outer(d, d))
    return mass, com, 0.5 * (inertia + inertia.T)


def point_name(point: Point) -> str:
    return point.name or f"{point.link}_point"


class _Values:
    """The numbers of a system's expressions at parameter values ``subs``, each as :func:`_value` (and the inertia
    matrix as ``Matrix.evalf``) gives it — bit for bit: a parameter is its value (``float(Float(v)) == v``),
    anything else is substituted and evaluated as before. The model's vectors and matrices (SymPy matrices built
    at every access: most of the time of an instantiation) are read once per model object."""

    _entries: dict = {}

    def __init__(self, subs: dict):
        self.subs = subs

    def __call__(self, expr) -> float:
        if isinstance(expr, sp.Symbol) and expr in self.subs:
            return float(self.subs[expr])
        return _value(expr, self.subs)

    @classmethod
    def entries(cls, owner, attribute: str) -> tuple:
        """The entries of ``owner.<attribute>`` (a vector or matrix property of a frozen model object), once."""
        key = (id(owner), attribute)
        kept = cls._entries.get(key)
        if kept is None or kept[0] is not owner:  # the owner is kept alive with its entries: its id is not reused
            value = getattr(owner, attribute)
            kept = cls._entries[key] = (owner, tuple(sp.sympify(v) for v in value))
        return kept[1]


_TREES: dict = {}
_TREES_KEPT = 1024


def instantiate(system: System, params: dict[str, float]) -> NumericTree:
    """Substitute parameter values into the tree; checks that the inertia tensors are physical. Once per system
    and parameter values (2 ms of SymPy each: the claims of a system draw the same parameters, and a claim at
    rest or at an equilibrium instantiates the drawn ones again)."""
    key = (id(system), tuple((k, float(v)) for k, v in params.items()))
    kept = _TREES.get(key)
    if kept is not None and kept[0] is system:  # the system is kept alive with its tree: its id is not reused
        return kept[1]
    tree = _instantiate(system, params)
    if len(_TREES) >= _TREES_KEPT:
        _TREES.clear()
    _TREES[key] = (system, tree)
    return tree


def _instantiate(system: System, params: dict[str, float]) -> NumericTree:
    subs = {system.parameter(k).symbol: sp.Float(v) for k, v in params.items()}
    value = _Values(subs)
    links = []
    for link in system.links:
        mass = value(link.mass)
        com = np.array([value(v) for v in _Values.entries(link, "com_vector")])
        inertia = np.array([value(v) for v in _Values.entries(link.inertia, "matrix")], dtype=float).reshape(3, 3)
        check_inertia(f"{system.name}: link {link.name}", mass, inertia)
        links.append(NumericLink(link.name, mass, com, inertia))
    joints = tuple(NumericJoint(j.name, j.type, j.parent, j.child, np.array(j.axis, dtype=float),
                                np.array([value(v) for v in _Values.entries(j, "origin_vector")]),
                                np.array([value(v) for v in _Values.entries(j, "rpy")]), value(j.armature))
                   for j in system.joints)
    points: dict[str, NumericPoint] = {}
    tendons: dict[tuple, list] = {}
    joint_stiffness, joint_damping, actuators = {}, {}, []
    for f in system.forces:
        for pt in (getattr(f, "a", None), getattr(f, "b", None), getattr(f, "point", None)):
            if pt is not None:
                points[point_name(pt)] = NumericPoint(point_name(pt), pt.link,
                                                      np.array([value(v) for v in _Values.entries(pt, "vector")]))
        if isinstance(f, (Spring, Damper)):
            key = (point_name(f.a), point_name(f.b))
            entry = tendons.setdefault(key, [f.name, key[0], key[1], 0.0, 0.0, 0.0])
            if isinstance(f, Spring):
                entry[3], entry[4] = _value(f.stiffness, subs), _value(f.rest_length, subs)
            else:
                entry[5] = _value(f.damping, subs)
        elif isinstance(f, JointSpring):
            joint_stiffness[f.joint] = (_value(f.stiffness, subs), _value(f.rest, subs))
        elif isinstance(f, JointDamper):
            joint_damping[f.joint] = _value(f.damping, subs)
        elif isinstance(f, JointInput):
            actuators.append((f.input, f.joint))
    for closure in system.closures:  # the guided point: a site/frame the engines constrain
        pt = closure.point
        points[point_name(pt)] = NumericPoint(point_name(pt), pt.link,
                                              np.array([value(v) for v in _Values.entries(pt, "vector")]))
    gravity = np.zeros(3)
    if system.gravity is not None:
        gravity = _value(system.gravity.g, subs) * np.array(system.gravity.direction, dtype=float)
    return NumericTree(system.name, tuple(links), joints, tuple(points.values()), gravity, joint_stiffness,
                       joint_damping, tuple(tuple(t) for t in tendons.values()), tuple(actuators))
