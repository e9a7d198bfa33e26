"""A system's kinematic tree with numbers in place of parameters: what the exporters write and what the
round-trip check expects the engines to load."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

from harness.derivation.lambdified import lambdify
from harness.errors import ModelError
from harness.modeling.solids import Box, Cylinder
from harness.modeling.system import (Damper, JointDamper, JointInput, JointSpring, Point, Spring, System,
                                     drawn_parameters)
from harness.modeling.system import check_inertia  # noqa: F401  (re-exported: the physical-inertia check lives with the model)

# MuJoCo refuses moving bodies whose mass or a principal inertia is below mjMINVAL = 1e-15 (its compiler
# tests ``inertia < mjMINVAL``). A point mass (zero inertia tensor about its centre of mass) is exported to MJCF
# with the smallest isotropic inertia it accepts, mjMINVAL itself, as principal moments (``diaginertia``:
# a ``fullinertia`` passes an eigenvalue test that refuses values up to ~5e-15); a slender rod (a singular tensor)
# its tensor plus that (mjcf.exported_inertia). This is not round-off but a model difference: each such body adds
# ``ε J_ωᵀ J_ω`` to M (ε this value, J_ω its body's angular Jacobian) and ``ε J_ωᵀ J̇_ω q̇`` to the bias, which on a
# small body exceeds the tolerance 1e-12 of M (a pendulum of 1 g on 2 cm: 2500 times). The MuJoCo adapter takes
# them out of the quantities it reports (MujocoModel.stand_in), so that they are compared with our model; what
# remains is in MuJoCo's own stepping, ``k ε / λ_min(M)`` relative in q̈ (k such bodies turning with a
# coordinate), far below any trajectory tolerance. Before the adapter took them out, the governor's q̈ against
# MuJoCo was at 0.014 of its tolerance (0.15 with the former ε = 1e-14), 0.0009 after.
MUJOCO_POINT_MASS_INERTIA = 1e-15


@dataclass(frozen=True)
class NumericSolid:
    """A solid of a link's body (:attr:`Link.solids`), for the pictures: ``kind`` box, cylinder or ball, its
    ``centre`` in the link frame and ``size`` (half edges; radius and half length along z; radius)."""

    kind: str
    centre: np.ndarray
    size: np.ndarray


@dataclass(frozen=True)
class NumericLink:
    name: str
    mass: float
    com: np.ndarray            # centre of mass in the link frame
    inertia: np.ndarray        # 3x3 about the centre of mass, link frame
    solids: tuple = ()         # NumericSolid: what the body is made of, where the model says so
    shape: str = ""            # the solid its inertia is built from (Inertia.shape): how it is drawn


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
    tendons: tuple             # (name, point a, point b, stiffness, rest length, damping); None: no such element
    actuators: tuple           # (input name, joint)


def lump(parts) -> tuple[float, np.ndarray, np.ndarray]:
    """Steiner's theorem (3.133): one rigid body from ``(m, c, I_c)`` parts given in common axes — its mass,
    centre of mass and (symmetric) inertia tensor about it. Parts without mass or inertia are left out; one
    part is returned as it is."""
    return lump_each([parts])[0]


def lump_each(groups) -> list[tuple[float, np.ndarray, np.ndarray]]:
    """:func:`lump` of each group of parts (a part may be in several groups: the subtrees of a tree's joints),
    computed for all groups at once in arrays: every sum taken in the parts' order from 0 (``np.add.accumulate``,
    sequential), so each group's numbers are those of one Python loop over its parts, to the bit."""
    index: dict[int, int] = {}
    unique, rows = [], []
    for parts in groups:
        row = []
        for part in parts:
            k = index.get(id(part))   # the parts outlive this call: an id is not reused meanwhile
            if k is None:
                k = index[id(part)] = len(unique)
                unique.append(part)
            row.append(k)
        rows.append(row)
    n = len(unique)
    raw = [(m, np.asarray(c, dtype=float), np.asarray(I, dtype=float)) for m, c, I in unique]
    masses = np.array([float(m) for m, _, _ in raw]).reshape(n)
    coms = np.array([c for _, c, _ in raw]).reshape(n, 3)
    tensors = np.array([I for _, _, I in raw]).reshape(n, 3, 3)
    kept = (np.array([m > 0 for m, _, _ in raw], dtype=bool) | np.any(tensors != 0, axis=(1, 2))).tolist()
    rows = [[k for k in row if kept[k]] for row in rows]
    out: list = [None] * len(rows)
    many = []
    for g, row in enumerate(rows):
        if not row:
            out[g] = (0.0, np.zeros(3), np.zeros((3, 3)))
        elif len(row) == 1:
            out[g] = (float(raw[row[0]][0]), raw[row[0]][1], raw[row[0]][2])
        else:
            many.append(g)
    if not many:
        return out
    width = max(len(rows[g]) for g in many)
    count = np.array([len(rows[g]) for g in many])
    at = np.array([rows[g] + [rows[g][0]] * (width - len(rows[g])) for g in many])   # padding is never summed
    pick = (np.arange(len(many)), count)   # the sum of a group's parts, after the 0 it starts from

    def total(x):   # 0 + x₀ + x₁ + … along the parts, in that order
        return np.add.accumulate(np.concatenate([np.zeros_like(x[:, :1]), x], axis=1), axis=1)[pick]

    m, c = masses[at], coms[at]
    mass = total(m)
    moment = total(m[..., None] * c)
    heavy = mass > 0
    com = np.zeros((len(many), 3))
    com[heavy] = moment[heavy] / mass[heavy, None]
    d = c - com[:, None, :]
    square = d[..., 0] * d[..., 0] + d[..., 1] * d[..., 1] + d[..., 2] * d[..., 2]
    steiner = tensors[at] + m[..., None, None] * (square[..., None, None] * np.eye(3)
                                                   - d[..., :, None] * d[..., None, :])
    inertia = total(steiner)
    inertia = 0.5 * (inertia + inertia.transpose(0, 2, 1))
    for i, g in enumerate(many):
        out[g] = (float(mass[i]), com[i], inertia[i])
    return out


def point_name(point: Point) -> str:
    return point.name or f"{point.link}_point"


class _Values:
    """The numbers of a system's expressions at parameter values ``params``: each scalar, vector and matrix of the
    model compiled once (per expression, or per model object and attribute) into one Python function of the
    parameters it contains (``lambdify`` with ``math``, shared subexpressions computed once), so an instantiation
    calls a few functions instead of substituting into SymPy trees (a lumped body's Steiner terms: 43 ms for the
    tower crane). A parameter is its value, a number its float."""

    _scalars: dict = {}
    _entries: dict = {}

    def __init__(self, system: System, params: dict[str, float]):
        self.system = system
        self.values = {system.parameter(k).symbol: float(v) for k, v in params.items()}

    def __call__(self, expr) -> float:
        expr = sp.sympify(expr)
        if expr.is_Number:
            return float(expr)
        if expr in self.values:
            return self.values[expr]
        kept = self._scalars.get(expr)
        if kept is None:
            kept = self._scalars[expr] = _compiled(self.system, (expr,))
        return self._call(kept, (expr,))[0]

    def entries(self, owner, attribute: str) -> np.ndarray:
        """The entries of ``owner.<attribute>`` (a vector or matrix property of a frozen model object), as floats
        (the SymPy matrix is built and compiled once per owner: it is built at every access)."""
        key = (id(owner), attribute)
        kept = self._entries.get(key)
        if kept is None or kept[0] is not owner:  # the owner is kept alive with its function: its id is not reused
            exprs = tuple(sp.sympify(v) for v in getattr(owner, attribute))
            kept = self._entries[key] = (owner, exprs, _compiled(self.system, exprs))
        return np.array(self._call(kept[2], kept[1]), dtype=float)

    def _call(self, compiled, exprs) -> list[float]:
        symbols, fn = compiled
        try:
            args = [self.values[s] for s in symbols]
        except KeyError:
            missing = {s for s in symbols if s not in self.values}
            expr = next(e for e in exprs if e.free_symbols & missing)
            raise ModelError(f"cannot evaluate {expr} numerically (free symbols {missing})") from None
        try:
            return [float(v) for v in fn(*args)]
        except (ArithmeticError, ValueError) as exc:
            raise ModelError(f"{self.system.name}: cannot evaluate the model at these parameter values "
                             f"({type(exc).__name__}: {exc})") from None


def _solid(value: "_Values", solid) -> NumericSolid:
    if isinstance(solid, Box):
        low, high = (np.array([value(b[k]) for b in (solid.x, solid.y, solid.z)]) for k in (0, 1))
        return NumericSolid("box", (low + high) / 2.0, np.abs(high - low) / 2.0)
    if isinstance(solid, Cylinder):
        length = value(solid.length)
        return NumericSolid("cylinder", np.array([0.0, 0.0, length / 2.0]),
                            np.array([value(solid.radius), length / 2.0]))
    return NumericSolid("ball", np.zeros(3), np.array([value(solid.radius)]))


def _compiled(system: System, exprs: tuple) -> tuple[list, object]:
    """``(parameter symbols, function of their values returning the values of exprs)``; an expression in other
    symbols than the system's parameters is refused here."""
    parameters = [p.symbol for p in system.parameters]
    free = set().union(*(e.free_symbols for e in exprs))
    if free - set(parameters):
        expr = next(e for e in exprs if e.free_symbols - set(parameters))
        raise ModelError(f"cannot evaluate {expr} numerically (free symbols {expr.free_symbols - set(parameters)})")
    symbols = [s for s in parameters if s in free]
    return symbols, lambdify(symbols, list(exprs), modules="math", cse=True, docstring_limit=0)


_TREES: dict = {}
_TREES_KEPT = 4096


def exact_key(values: dict) -> tuple:
    """``(name, float.hex())`` pairs of ``values``: their exact bits as a key (``-0.0`` is not ``0.0``)."""
    return tuple((k, float(v).hex()) for k, v in values.items())


def instantiate(system: System, params: dict[str, float]) -> NumericTree:
    """Substitute parameter values into the tree; checks that the inertia tensors are physical. Once per system
    and parameter values (0.2-0.7 ms each, compiled: the claims of a system draw the same parameters, and a claim
    at rest or at an equilibrium instantiates the drawn ones again)."""
    key = (id(system), exact_key(params))
    kept = _TREES.get(key)
    if kept is not None and kept[0] is system:  # the system is kept alive with its tree: its id is not reused
        return kept[1]
    tree = _instantiate(system, params)
    if len(_TREES) >= _TREES_KEPT:
        _TREES.clear()
    _TREES[key] = (system, tree)
    return tree


def _instantiate(system: System, params: dict[str, float]) -> NumericTree:
    value = _Values(system, params)
    links = []
    for link in system.links:
        mass = value(link.mass)
        com = value.entries(link, "com_vector")
        inertia = value.entries(link.inertia, "matrix").reshape(3, 3)
        try:
            check_inertia(f"{system.name}: link {link.name}", mass, inertia)
        except ModelError as exc:
            drawn = drawn_parameters(system, params)
            if not drawn:
                raise
            raise ModelError(f"{exc}, with the parameters {drawn} (drawn by the checks): an inertia "
                             "built from parameters must be valid over their spans; build it from a solid's "
                             "dimensions (Inertia.cuboid, Inertia.cylinder: valid for any positive ones), give its "
                             "six entries as parameters (drawn as one valid tensor) or the parameters a range"
                             ) from None
        solids = tuple(_solid(value, solid) for solid, _ in link.solids)
        links.append(NumericLink(link.name, mass, com, inertia, solids, link.inertia.shape))
    joints = tuple(NumericJoint(j.name, j.type, j.parent, j.child, np.array(j.axis, dtype=float),
                                value.entries(j, "origin_vector"),
                                value.entries(j, "rpy"), value(j.armature))
                   for j in system.joints)
    points: dict[str, NumericPoint] = {}
    tendons: dict[tuple, list] = {}
    joint_stiffness, joint_damping, actuators = {}, {}, []
    for f in system.forces:
        for pt in (getattr(f, "a", None), getattr(f, "b", None), getattr(f, "point", None)):
            if pt is not None:
                points[point_name(pt)] = NumericPoint(point_name(pt), pt.link,
                                                      value.entries(pt, "vector"))
        if isinstance(f, (Spring, Damper)):
            key = (point_name(f.a), point_name(f.b))
            entry = tendons.setdefault(key, [f.name, key[0], key[1], None, None, None])  # a spring, a damper or both
            if isinstance(f, Spring):
                entry[3], entry[4] = value(f.stiffness), value(f.rest_length)
            else:
                entry[5] = value(f.damping)
        elif isinstance(f, JointSpring):
            joint_stiffness[f.joint] = (value(f.stiffness), value(f.rest))
        elif isinstance(f, JointDamper):
            joint_damping[f.joint] = value(f.damping)
        elif isinstance(f, JointInput):
            actuators.append((f.input, f.joint))
    for closure in system.closures:  # the guided point: a site/frame the engines constrain
        pt = closure.point
        points[point_name(pt)] = NumericPoint(point_name(pt), pt.link,
                                              value.entries(pt, "vector"))
    gravity = np.zeros(3)
    if system.gravity is not None:
        gravity = value(system.gravity.g) * np.array(system.gravity.direction, dtype=float)
    return NumericTree(system.name, tuple(links), joints, tuple(points.values()), gravity, joint_stiffness,
                       joint_damping, tuple(tuple(t) for t in tendons.values()), tuple(actuators))
