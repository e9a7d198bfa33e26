"""The modeling vocabulary: a lecture system described once, symbolically.

A :class:`System` is composed of small value objects, in the lecture's words:

* :class:`Parameter` – a lecture symbol with default value, unit and physical assumption;
* :class:`Coordinate` – a lecture (generalized) coordinate ``q_j``;
* :class:`Input` – an input ``u`` (motor torque, driving force) of the equations of motion;
* :class:`Link` – a body-fixed coordinate system ``(0_k x_k y_k z_k)`` carrying an optional
  rigid body (mass ``m``, centre of mass ``p_k^{s}``, inertia tensor ``I_k^{s}`` about the centre
  of mass in the body frame, (5.13)); a point mass is a body with zero inertia tensor;
* :class:`Joint` – an elementary joint of chapter 4: a fixed offset (homogeneous transformation
  ``d``, ``R`` (4.21)) followed by a rotation about / translation along a body axis by the tree
  joint coordinate ``theta``;
* force elements – :class:`Spring`, :class:`Damper` (between two points), :class:`JointSpring`,
  :class:`JointDamper`, :class:`JointInput` (acting on a tree joint), :class:`PointForce` and
  :class:`BodyTorque` (external force / torque turned into generalized forces by (5.73));
* the map ``theta = phi(q)`` from lecture coordinates to tree joint coordinates (``Joint.phi``).

Nothing here derives anything: :mod:`harness.derivation.derive` does, following chapter 5.
"""

from __future__ import annotations

import dataclasses
import hashlib
import cmath
import itertools
import math
from dataclasses import dataclass, field, fields
from typing import Iterable

import numpy as np
import sympy as sp

from harness.errors import ModelError
from harness.modeling.solids import SOLIDS

WORLD = "world"

Expr = sp.Expr | float | int


def _sym(value) -> sp.Expr:
    return sp.sympify(value)


def _vec3(value, what: str) -> sp.Matrix:
    m = sp.Matrix(value) if not isinstance(value, sp.MatrixBase) else sp.Matrix(value)
    if m.shape not in ((3, 1), (1, 3)):
        raise ModelError(f"{what} must have 3 components, got shape {m.shape}")
    return m.reshape(3, 1)


def value_at(expr, params: dict[str, float]) -> float:
    """An expression in the parameters at the values ``params`` (given by parameter name)."""
    expr = sp.sympify(expr)
    value = expr.xreplace({x: sp.Float(params[x.name]) for x in expr.free_symbols})
    if not value.is_number:
        raise ModelError(f"cannot evaluate {expr} numerically (free symbols {value.free_symbols})")
    return float(value)


# --------------------------------------------------------------------------- symbols and values
ASSUMPTIONS = ("positive", "nonnegative", "real")
_declarations = itertools.count()  # declaration order: the order a System lists what it collects


class Declared(sp.Symbol):
    """A symbol a model declares — :class:`Parameter`, :class:`Coordinate`, :class:`Input` — usable in
    expressions as it is (``m * l**2``) and carrying its meaning (default, unit, description, ...).

    SymPy caches symbols and compares them by name and assumptions; a declaration is constructed uncached and
    compares by its metadata *and* its declaration, so that two modules' ``Parameter("l", 1.0, ...)`` and
    ``Parameter("l", 0.5, ...)`` are never conflated, and a :class:`System` can list what it collects in the
    order it was declared. What a System, Claim, Scene or event holds is normalised to plain
    ``sp.Symbol(name, **assumptions)`` (:func:`plain`, :attr:`symbol`): the derivation, its cache, the compiled
    functions and every printed string see plain symbols only."""

    _meta: tuple = ()           # the metadata fields, in the order of the constructor

    def __new__(cls, name, *args, **kwargs):
        raise TypeError("construct a Parameter, Coordinate or Input")

    @classmethod
    def _declare(cls, name: str, sympy_assumption: str, **meta) -> "Declared":
        obj = sp.Symbol.__xnew__(cls, name, **{sympy_assumption: True})  # uncached
        obj.__dict__.update(meta, _serial=next(_declarations))
        return obj

    def _hashable_content(self):
        return super()._hashable_content() + tuple(getattr(self, k) for k in self._meta) + (self._serial,)

    def __reduce_ex__(self, protocol):
        return _redeclare, (type(self), {k: getattr(self, k) for k in self._meta}, self._serial)

    def __setattr__(self, key, value):
        if key in self._meta and "_serial" in self.__dict__:
            raise AttributeError(f"{type(self).__name__} {self.name}: {key} is fixed when it is declared")
        super().__setattr__(key, value)

    @property
    def symbol(self) -> sp.Symbol:
        """The plain SymPy symbol (same name and assumptions) the derivation sees."""
        return sp.Symbol(self.name, **self._assumptions_orig)

    _optional: tuple = ()      # metadata left out of the fingerprint where not given (added later: every model's
                               # fingerprint, and the caches keyed by it, stay what they were)

    def canonical(self) -> str:
        """The declaration as the model fingerprint hashes it."""
        inner = ",".join(f"{k}={_canonical(getattr(self, k))}" for k in self._meta
                         if not (k in self._optional and getattr(self, k) is None))
        return f"{type(self).__name__}({inner})"


def _redeclare(cls, meta, serial):
    obj = cls(**meta)
    obj.__dict__["_serial"] = serial
    return obj


class Parameter(Declared):
    """A model parameter named as in the lecture (``m_1``, ``l_s1``, ``I_zz2``, ``c_e``): a SymPy symbol
    with its default value (SI), unit, description and physical assumption (``positive``, ``nonnegative``,
    ``real``): ``m = Parameter("m", 1.0, "kg", "point mass")``, then ``m * l**2`` in expressions. ``range``: the
    values the conformance checks draw it from, where the default span would leave the model undefined
    (:func:`_parameter_range`)."""

    _meta = ("name", "default", "unit", "description", "assumption", "range")
    _optional = ("range",)

    def __new__(cls, name: str, default: float | None = None, unit: str = "", description: str = "",
                assumption: str = "positive", range: tuple | None = None):  # noqa: A002
        if assumption not in ASSUMPTIONS:
            raise ModelError(f"parameter {name}: assumption must be one of {ASSUMPTIONS}")
        if default is None:
            raise ModelError(f"parameter {name}: give a default value in SI units, "
                             f"e.g. Parameter({name!r}, 1.0, 'kg', 'what it is')")
        if not unit:
            raise ModelError(f"parameter {name}: give a unit (use '1' for dimensionless)")
        if range is not None:
            range = _parameter_range(name, default, range)
        elif assumption == "nonnegative" and default == 0:
            raise ModelError(f"parameter {name}: non-negative with default 0, it would be drawn at 0 only (from "
                             "[0, 2 default]) and no check would test the terms it enters; give the span to draw "
                             "from, e.g. range=(0, 1.0)")
        obj = cls._declare(name, assumption, default=default, unit=unit, description=description,
                           assumption=assumption, range=range)
        obj.check(default)
        if range is not None:
            for bound in range:
                obj.check(bound)
        return obj

    def check(self, value: float) -> None:
        """Raise :class:`ModelError` when ``value`` violates this parameter's assumption."""
        if not isinstance(value, (int, float)) or not math.isfinite(value):
            raise ModelError(f"parameter {self.name}={value!r}: must be a finite number")
        if self.assumption == "positive" and not value > 0:
            raise ModelError(f"parameter {self.name}={value}: must be positive ({self.description})")
        if self.assumption == "nonnegative" and not value >= 0:
            raise ModelError(f"parameter {self.name}={value}: must be non-negative ({self.description})")


def _parameter_range(name: str, default: float, span) -> tuple[float, float]:
    """``range`` of a :class:`Parameter`: the values the conformance checks draw it from (by default
    ``[default/2, 2 default]`` for a positive one), a pair of finite numbers around the default: a linkage that must
    close (a four-bar's lengths), a map defined only near the default."""
    try:
        lo, hi = (float(x) for x in span)
    except (TypeError, ValueError):
        raise ModelError(f"parameter {name}: range={span!r} is not a pair of numbers (low, high)") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and lo <= float(default) <= hi and lo < hi):
        raise ModelError(f"parameter {name}: range={span!r} must be finite, low < high, and hold the default "
                         f"{default}")
    return lo, hi


def drawn_parameters(system, values) -> str:
    """The parameters of ``values`` (by name, or in the order of ``system.parameters``) that are not their defaults,
    ``name = value, …``, as an error at drawn parameters names them ("" when all are the defaults)."""
    if not isinstance(values, dict):
        values = {x.name: v for x, v in zip(system.parameters, values)}
    return ", ".join(f"{x.name} = {float(values[x.name]):.6g}" for x in system.parameters
                     if x.name in values and float(values[x.name]) != float(x.default))


def standard_gravity() -> Parameter:
    """The acceleration due to gravity ``g`` of every model: 9.81 m/s². A new declaration at each call, so that
    ``g`` takes its place in the order where the model declares it."""
    return Parameter("g", 9.81, "m/s^2", "acceleration due to gravity")


class Coordinate(Declared):
    """A lecture (generalized) coordinate ``q_j`` (a real symbol) and its unit (``rad`` or ``m``); ``.rate``
    and ``.accel`` are ``q̇_j`` and ``q̈_j``. ``range`` bounds the states the conformance checks draw (e.g.
    away from a coordinate singularity; a rope length kept positive); ``None`` means the default range (angles
    in [-π, π], lengths in [-1, 1] m)."""

    _meta = ("name", "unit", "description", "range")

    def __new__(cls, name: str, unit: str, description: str, range: tuple | None = None):  # noqa: A002
        return cls._declare(name, "real", unit=unit, description=description, range=range)

    @property
    def rate(self) -> sp.Symbol:
        """The symbol of the generalized velocity ``q̇_j``."""
        return sp.Symbol(f"{self.name}_dot", real=True)

    @property
    def accel(self) -> sp.Symbol:
        """The symbol of the generalized acceleration ``q̈_j`` (for printed equations of motion)."""
        return sp.Symbol(f"{self.name}_ddot", real=True)


class Input(Declared):
    """An input of the equations of motion (motor torque ``tau_1``, driving force ``f_e``), a real symbol."""

    _meta = ("name", "unit", "description")

    def __new__(cls, name: str, unit: str, description: str):
        return cls._declare(name, "real", unit=unit, description=description)


def name_of(value):
    """A declared symbol's name; anything else as it is (fields that name a parameter, input or coordinate)."""
    return value.name if isinstance(value, Declared) else value


def plain(value, found: list | None = None):
    """``value`` with every declared symbol replaced by its plain SymPy symbol — in expressions, matrices,
    tuples, lists, dicts and value objects (dataclasses, rebuilt only where something changed). The declared
    symbols met are appended to ``found``."""
    if isinstance(value, Declared):
        if found is not None:
            found.append(value)
        return value.symbol
    if isinstance(value, (sp.Basic, sp.MatrixBase)):
        declared = sorted((s for s in value.free_symbols if isinstance(s, Declared)), key=lambda s: s._serial)
        if not declared:
            return value
        if found is not None:
            found.extend(declared)
        return value.xreplace({s: s.symbol for s in declared})
    if isinstance(value, (tuple, list)):
        new = [plain(v, found) for v in value]
        return value if all(a is b for a, b in zip(new, value)) else type(value)(new)
    if isinstance(value, dict):
        items = [(plain(k, found), plain(v, found)) for k, v in value.items()]
        same = all(k is k0 and v is v0 for (k, v), (k0, v0) in zip(items, value.items()))
        return value if same else dict(items)
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        if isinstance(value, JointInput) and isinstance(value.input, Input):
            if found is not None:
                found.append(value.input)
            value = dataclasses.replace(value, input=value.input.name)
        changes = {}
        for f in fields(value):
            old = getattr(value, f.name)
            new = plain(old, found)
            if new is not old:
                changes[f.name] = new
        return dataclasses.replace(value, **changes) if changes else value
    return value


# --------------------------------------------------------------------------- bodies and joints
# A field that only says how a body is drawn: not part of the model's fingerprint (no derivation depends on it, so
# an edit of it derives nothing again); the exported MJCF, which draws it, is keyed by the numeric tree.
DRAWING = {"drawing": True}


@dataclass(frozen=True)
class Inertia:
    """Inertia tensor about the centre of mass, in the body-fixed frame (5.13), symmetric. ``shape`` is the solid
    :meth:`cuboid` and :meth:`cylinder` build it from ("cuboid", "cylinder"): the pictures draw that, where the
    tensor alone could not tell a square cuboid from a cylinder."""

    xx: Expr
    yy: Expr
    zz: Expr
    xy: Expr = 0
    xz: Expr = 0
    yz: Expr = 0
    shape: str = field(default="", compare=False, metadata=DRAWING)

    @property
    def matrix(self) -> sp.Matrix:
        s = [_sym(v) for v in (self.xx, self.yy, self.zz, self.xy, self.xz, self.yz)]
        return sp.Matrix([[s[0], s[3], s[4]], [s[3], s[1], s[5]], [s[4], s[5], s[2]]])

    @staticmethod
    def zero() -> "Inertia":
        return Inertia(0, 0, 0)

    @staticmethod
    def cuboid(m: Expr, a: Expr, b: Expr, c: Expr) -> "Inertia":
        """Homogeneous cuboid of mass ``m`` with edges ``a``, ``b``, ``c`` along x, y, z (3.128)."""
        m, a, b, c = map(_sym, (m, a, b, c))
        return Inertia(m * (b**2 + c**2) / 12, m * (a**2 + c**2) / 12, m * (a**2 + b**2) / 12, shape="cuboid")

    @staticmethod
    def cylinder(m: Expr, r: Expr, h: Expr, axis: str = "z") -> "Inertia":
        """Homogeneous solid cylinder (a disc where ``h`` is small) of mass ``m``, radius ``r`` and length ``h``
        along ``axis``: ``m r²/2`` about it (3.122), ``m (3 r² + h²)/12`` about a diameter. Valid for any positive
        ``m``, ``r``, ``h`` (the two diameters' sum exceeds the axle's by ``m h²/6``), drawn independently too."""
        m, r, h = map(_sym, (m, r, h))
        axle, diameter = m * r**2 / 2, m * (3 * r**2 + h**2) / 12
        moments = {"x": (axle, diameter, diameter), "y": (diameter, axle, diameter), "z": (diameter, diameter, axle)}
        if axis not in moments:
            raise ModelError(f"Inertia.cylinder: axis {axis!r}; give 'x', 'y' or 'z'")
        return Inertia(*moments[axis], shape="cylinder")


def steiner(mass: Expr, r: sp.Matrix) -> sp.Matrix:
    """Steiner's term (3.126), (3.133): the inertia tensor of a mass ``mass`` at the offset ``r`` from the
    reference point, ``mass (rᵀ r E − r rᵀ)``."""
    return mass * ((r.T * r)[0] * sp.eye(3) - r * r.T)


@dataclass(frozen=True)
class Link:
    """A body-fixed frame; with ``mass`` it carries a rigid body (or a point mass at ``com``)."""

    name: str
    mass: Expr = 0
    com: tuple = (0, 0, 0)
    inertia: Inertia = field(default_factory=Inertia.zero)
    description: str = ""
    solids: tuple = field(default=(), metadata=DRAWING)
    """The homogeneous solids the body is made of, as ``(solid, density)`` pairs in the link frame
    (:mod:`harness.modeling.solids`): what the pictures show of it (else the solid equivalent to its inertia
    tensor); a test finds the link's mass, centre of mass and inertia tensor by their volume integrals."""
    drawn_at: tuple = field(default=(0, 0, 0), metadata=DRAWING)
    """How far from where the model puts it the pictures draw the link, with all it carries (in its parent's frame,
    in metres): for coordinates that put bodies at one point which a reader sees apart (the quarter car's heights
    are counted from the unstretched springs: at rest its body sits below its wheel). The dynamics, the exported
    files and every check see the model as it is; the picture's caption names the link drawn elsewhere."""

    def __post_init__(self):
        if not (isinstance(self.drawn_at, tuple) and len(self.drawn_at) == 3
                and all(isinstance(v, (int, float)) for v in self.drawn_at)):
            raise ModelError(f"link {self.name}: drawn_at: give three numbers in metres, got {self.drawn_at!r}")
        for pair in self.solids:
            if not (isinstance(pair, tuple) and len(pair) == 2 and isinstance(pair[0], SOLIDS)):
                raise ModelError(f"link {self.name}: solids: give (solid, density) pairs, e.g. "
                                 f"(Cylinder(r, h), rho); got {pair!r}")

    @property
    def com_vector(self) -> sp.Matrix:
        return _vec3(self.com, f"link {self.name}: com")

    @property
    def has_mass(self) -> bool:
        return _sym(self.mass) != 0

    @property
    def is_point_mass(self) -> bool:
        return self.has_mass and self.inertia.matrix.is_zero_matrix


JOINT_TYPES = ("revolute", "prismatic")
_AXES = {"x": (1, 0, 0), "y": (0, 1, 0), "z": (0, 0, 1)}


@dataclass(frozen=True)
class Joint:
    """An elementary joint: ``H_parent^child = H(origin, rpy) · H_axis(theta)`` (4.21), (4.9).

    ``phi`` is this tree joint's coordinate as a function of the lecture coordinates,
    ``theta = phi(q)``; by default the lecture coordinate with the joint's name (identity map).
    """

    name: str
    type: str
    parent: str
    child: str
    axis: tuple = (0, 0, 1)
    origin: tuple = (0, 0, 0)
    rpy: tuple = (0, 0, 0)
    phi: Expr | None = None
    armature: Expr = 0     # rotor inertia reflected onto this joint (MuJoCo armature), adds to M_theta[k, k]

    def __post_init__(self):
        if self.type not in JOINT_TYPES:
            raise ModelError(f"joint {self.name}: type must be one of {JOINT_TYPES}, got {self.type!r}")
        if isinstance(self.axis, str):
            object.__setattr__(self, "axis", _AXES[self.axis])
        a = [float(v) for v in self.axis]
        if abs(sum(v * v for v in a) - 1.0) > 1e-12:
            raise ModelError(f"joint {self.name}: axis {self.axis} must be a unit vector")

    @property
    def theta(self) -> sp.Symbol:
        """The tree joint coordinate ``theta`` (the engines' coordinate)."""
        return sp.Symbol(f"theta_{self.name}", real=True)

    @property
    def axis_vector(self) -> sp.Matrix:
        return sp.Matrix([sp.nsimplify(v) for v in self.axis])

    @property
    def origin_vector(self) -> sp.Matrix:
        return _vec3(self.origin, f"joint {self.name}: origin")


# --------------------------------------------------------------------------- force elements
@dataclass(frozen=True)
class Point:
    """A point fixed in a link frame (``WORLD`` for the inertial frame), e.g. ``p_2^{e2}``."""

    link: str
    position: tuple = (0, 0, 0)
    name: str = ""

    @property
    def vector(self) -> sp.Matrix:
        return _vec3(self.position, f"point {self.name or self.link}")


@dataclass(frozen=True)
class Closure:
    """A point held on a line or plane by a massless guide — the closed chain a nonlinear map θ = φ(q) solves
    (the toggle press's slide (A.99), the trebuchet's ground (A.177)): ``normalᵀ p_0(point) = value``.
    The engines impose it themselves in constrained simulations (:mod:`harness.scenes.phenomena.closures`)."""

    name: str
    point: Point
    normal: tuple
    value: Expr = 0


@dataclass(frozen=True)
class ConstraintForce:
    """A force (or torque) a constraint of the map ``θ = φ(q)`` stands for — a rope, a rolling contact, a rigid
    connection — of unknown magnitude ``λ`` (a cutting force of Section 3.x's free-body diagrams):
    ``λ · direction`` on the material point of ``link`` that is at ``at`` (a :class:`Point` of any frame) for each
    ``(link, at, direction)`` of ``forces``, ``λ · axis`` on ``link`` for each ``(link, axis)`` of ``torques``;
    directions and axes in the inertial frame, expressions in ``q`` allowed. It does no work on the motions the
    map allows; :func:`harness.derivation.bodies.constraint_forces` solves ``λ`` from the tree's balance. A
    system with a map declares one per constraint (``len(θ) − len(q)`` of them) or none; the engines never see
    them."""

    name: str
    forces: tuple = ()
    torques: tuple = ()


@dataclass(frozen=True)
class Gravity:
    """Gravity ``g`` along the unit vector ``e_g`` (5.20): ``V = -m g e_g^T p_0^S``."""

    g: Expr
    direction: tuple = (0, 0, -1)


@dataclass(frozen=True)
class Spring:
    """Linear spring between two points, ``V = c/2 (|r| - s_0)^2`` (3.84)."""

    name: str
    a: Point
    b: Point
    stiffness: Expr
    rest_length: Expr = 0


@dataclass(frozen=True)
class Damper:
    """Linear damper between two points acting along their connecting line:
    ``f = -d (d|r|/dt) r/|r|`` on ``b`` (and its reaction on ``a``), (3.88)."""

    name: str
    a: Point
    b: Point
    damping: Expr


@dataclass(frozen=True)
class JointSpring:
    """Torsion/linear spring on a tree joint, ``V = c/2 (theta - theta_0)^2``."""

    name: str
    joint: str
    stiffness: Expr
    rest: Expr = 0


@dataclass(frozen=True)
class JointDamper:
    """Viscous friction in a tree joint, generalized force ``-d theta_dot`` on that joint."""

    name: str
    joint: str
    damping: Expr


@dataclass(frozen=True)
class JointInput:
    """An input acting on a tree joint (motor torque between the two links, or axial force)."""

    name: str
    joint: str
    input: str


@dataclass(frozen=True)
class PointForce:
    """External force ``f^e`` at a point; components in ``frame`` (world or a link: follower force).
    Generalized force by (5.73): ``f_q = J_v^T f^e``."""

    name: str
    point: Point
    force: tuple
    frame: str = WORLD


@dataclass(frozen=True)
class BodyTorque:
    """External torque ``tau^e`` on a link, components in ``frame``; ``f_q = J_omega^T tau^e`` (5.73)."""

    name: str
    link: str
    torque: tuple
    frame: str = WORLD


ForceElement = Spring | Damper | JointSpring | JointDamper | JointInput | PointForce | BodyTorque


# --------------------------------------------------------------------------- the system
@dataclass(frozen=True)
class System:
    """One lecture system, modeled once.

    Its parameters are collected from its expressions (links, joints, gravity, forces, closures, constraint
    forces) in the order
    they were declared; ``parameters`` names those it has without using them in its expressions (a friction
    coefficient only its scenes use). A ``parameters`` tuple that lists every parameter the expressions use is
    kept in its own order (``dataclasses.replace`` passes the complete tuple). Inputs likewise (an
    :class:`Input` used in a force's expression or by a :class:`JointInput`). Every expression is stored with
    plain SymPy symbols (:func:`plain`)."""

    name: str
    title: str
    lecture: str
    parameters: tuple[Parameter, ...] = ()
    coordinates: tuple[Coordinate, ...] = ()
    links: tuple[Link, ...] = ()
    joints: tuple[Joint, ...] = ()
    gravity: Gravity | None = None
    forces: tuple = ()
    inputs: tuple[Input, ...] = ()
    doc: str = ""
    status: str = "modeled"
    # engines that do not apply to this system, with the reason the report gives: (("mujoco", "…"), …)
    not_in_engines: tuple = ()
    closures: tuple = ()      # Closure: the closed chain behind a nonlinear map, for the engines' constraints
    constraint_forces: tuple = ()  # ConstraintForce: the forces of the map's constraints (cutting forces), derived

    def engine_note(self, engine: str) -> str | None:
        """Why ``engine`` does not apply to this system (None when it does)."""
        return dict(self.not_in_engines).get(engine)

    def __post_init__(self):
        found: list = []
        for name in ("links", "joints", "gravity", "forces", "closures", "constraint_forces"):
            object.__setattr__(self, name, plain(getattr(self, name), found))
        object.__setattr__(self, "parameters", _collected(self.parameters, found, Parameter))
        object.__setattr__(self, "inputs", _collected(self.inputs, found, Input))
        validate(self)

    # ----- lookups
    @property
    def q(self) -> list[sp.Symbol]:
        return [c.symbol for c in self.coordinates]

    @property
    def qd(self) -> list[sp.Symbol]:
        return [c.rate for c in self.coordinates]

    @property
    def p(self) -> list[sp.Symbol]:
        return [p.symbol for p in self.parameters]

    @property
    def u(self) -> list[sp.Symbol]:
        return [i.symbol for i in self.inputs]

    @property
    def theta(self) -> list[sp.Symbol]:
        return [j.theta for j in self.joints]

    @property
    def phi(self) -> sp.Matrix:
        """``theta = phi(q)``, one row per tree joint."""
        return sp.Matrix([sp.sympify(j.phi) if j.phi is not None else sp.Symbol(j.name, real=True)
                          for j in self.joints])

    @property
    def identity_map(self) -> bool:
        """Whether ``θ = q``: the lecture coordinates are the engines' joint coordinates, in their order."""
        return list(self.phi) == list(self.q)

    def link(self, name: str) -> Link:
        for link in self.links:
            if link.name == name:
                return link
        raise ModelError(f"{self.name}: no link named {name!r}")

    def point(self, name: str) -> "Point":
        """The point ``name``: one a force element or a closure names, else a link's centre of mass (a link's name)."""
        named = [pt for f in self.forces for pt in (getattr(f, "a", None), getattr(f, "b", None),
                                                     getattr(f, "point", None)) if isinstance(pt, Point)]
        named += [c.point for c in self.closures]
        for pt in named:
            if pt.name == name:
                return pt
        for link in self.links:
            if link.name == name:
                return Point(link.name, link.com)
        known = sorted({pt.name for pt in named} | {link.name for link in self.links})
        raise ModelError(f"{self.name}: no point or link named {name!r} (known: {', '.join(known)})")

    def joint(self, name: str) -> Joint:
        for joint in self.joints:
            if joint.name == name:
                return joint
        raise ModelError(f"{self.name}: no joint named {name!r}")

    def parameter(self, name: str) -> Parameter:
        for p in self.parameters:
            if p.name == name:
                return p
        known = ", ".join(p.name for p in self.parameters)
        raise ModelError(f"{self.name}: unknown parameter {name!r} (known: {known})")

    def joint_of_link(self, link: str) -> Joint | None:
        for joint in self.joints:
            if joint.child == link:
                return joint
        return None

    def chain(self, link: str) -> list[Joint]:
        """Joints from the world to ``link`` (root first)."""
        out = []
        while link != WORLD:
            joint = self.joint_of_link(link)
            if joint is None:
                raise ModelError(f"{self.name}: link {link!r} is attached to nothing")
            if joint in out:
                raise ModelError(f"{self.name}: the joints form a loop through link {link!r}")
            out.append(joint)
            link = joint.parent
        return out[::-1]

    def default_parameters(self) -> dict[str, float]:
        return {p.name: float(p.default) for p in self.parameters}

    def fingerprint(self) -> str:
        """A hash of everything that defines the model (keys the derivation cache); computed once."""
        cached = self.__dict__.get("_fingerprint")
        if cached is None:
            cached = hashlib.sha256(_canonical(self).encode()).hexdigest()[:20]
            object.__setattr__(self, "_fingerprint", cached)  # frozen: a cache, not state
        return cached


def _collected(given, found: list, kind: type) -> tuple:
    """``given`` as it is when it holds every declaration of ``kind`` in ``found``; else both, as declared."""
    given = tuple(given)
    extra = [d for d in dict.fromkeys(found) if isinstance(d, kind) and d not in given]
    if not extra:
        return given
    return tuple(sorted(dict.fromkeys((*given, *extra)), key=lambda d: getattr(d, "_serial", -1)))


def _canonical(obj) -> str:
    if isinstance(obj, Declared):
        return obj.canonical()
    if isinstance(obj, (sp.Basic, sp.MatrixBase)):
        return sp.srepr(obj)
    if isinstance(obj, (list, tuple)):
        return "(" + ",".join(_canonical(o) for o in obj) + ")"
    if hasattr(obj, "__dataclass_fields__"):
        inner = ",".join(f"{f.name}={_canonical(getattr(obj, f.name))}" for f in fields(obj)
                         if not f.metadata.get("drawing"))
        return f"{type(obj).__name__}({inner})"
    return repr(obj)


# --------------------------------------------------------------------------- validation
def _undeclared(exprs: Iterable, declared: set) -> list[str]:
    """Names of symbols in ``exprs`` that are not the declared symbols (same name *and* assumptions)."""
    used: set = set()
    for e in exprs:
        used |= sp.sympify(e).free_symbols
    return sorted(s.name for s in used - declared)


def validate(system: System) -> None:
    """Catch modeling mistakes when the model is loaded; each message names the field and the fix."""
    where = f"model {system.name}"
    pnames = [p.name for p in system.parameters]
    qnames = [c.name for c in system.coordinates]
    unames = [i.name for i in system.inputs]
    for kind, names in (("parameter", pnames), ("coordinate", qnames), ("input", unames)):
        dup = {n for n in names if names.count(n) > 1}
        if dup:
            raise ModelError(f"{where}: duplicate {kind} name(s) {sorted(dup)}")
    link_names = [link.name for link in system.links]
    if WORLD in link_names:
        raise ModelError(f"{where}: do not declare a link named {WORLD!r}; it is the inertial frame")
    children = [j.child for j in system.joints]
    for link in link_names:
        if children.count(link) != 1:
            raise ModelError(f"{where}: link {link!r} must be the child of exactly one joint "
                             f"(found {children.count(link)}); attach it with a Joint")
    known_links = set(link_names) | {WORLD}
    for j in system.joints:
        if j.parent not in known_links or j.child not in known_links:
            unknown = " and ".join(repr(n) for n in (j.parent, j.child) if n not in known_links)
            raise ModelError(f"{where}: joint {j.name} connects unknown link {unknown} ({j.parent!r} -> {j.child!r}); "
                             f"links are {', '.join(map(repr, [WORLD, *link_names]))}")
    for link in link_names:
        system.chain(link)  # raises when the chain does not reach the world or loops
    static = set(system.p)
    for link in system.links:
        bad = _undeclared([link.mass, *link.com, *link.inertia.matrix], static)
        if bad:
            raise ModelError(f"{where}: link {link.name} uses undeclared symbol(s) {bad}; "
                             f"declare them as Parameter")
    for j in system.joints:
        bad = _undeclared([*j.origin, *j.rpy, j.armature], static)
        if bad:
            raise ModelError(f"{where}: joint {j.name} origin uses undeclared symbol(s) {bad}")
    for what, values in ([("gravity", [system.gravity.g])] if system.gravity is not None else []) + [
            (f"closure {c.name}", [*c.point.position, *c.normal, c.value]) for c in system.closures]:
        bad = _undeclared(values, static)
        if bad:
            raise ModelError(f"{where}: {what} uses undeclared symbol(s) {bad}; declare them as Parameter")
    for j in system.joints:
        if j.phi is not None and not isinstance(sp.sympify(j.phi), sp.Expr):
            raise ModelError(f"{where}: joint {j.name}: phi must be one scalar expression theta_{j.name} = phi(q) "
                             f"(got {type(j.phi).__name__}); a joint has one coordinate")
    for c in system.coordinates:
        if c.range is not None and (len(c.range) != 2 or not float(c.range[0]) < float(c.range[1])):
            raise ModelError(f"{where}: coordinate {c.name}: range must be (low, high) with low < high, "
                             f"got {c.range}")
    phi = system.phi
    bad = _undeclared(list(phi), static | set(system.q))
    if bad:
        raise ModelError(f"{where}: theta = phi(q) uses {bad}, which are neither coordinates "
                         f"nor parameters; set Joint.phi for every joint whose name is not a coordinate")
    for f in system.forces:
        values = [getattr(f, a) for a in ("stiffness", "rest_length", "damping", "rest") if hasattr(f, a)]
        values += list(getattr(f, "force", ())) + list(getattr(f, "torque", ()))
        values += [*getattr(getattr(f, "a", None), "position", ()), *getattr(getattr(f, "b", None), "position", ()),
                   *getattr(getattr(f, "point", None), "position", ())]
        bad = _undeclared(values, static | set(system.q) | set(system.qd) | set(system.u))
        if bad:
            raise ModelError(f"{where}: force {f.name} uses undeclared symbol(s) {bad}")
    jac = phi.jacobian(system.q)
    if jac.shape != (len(system.joints), len(system.coordinates)):
        raise ModelError(f"{where}: map Jacobian has shape {jac.shape}")
    _check_map(system, phi, jac, where)
    _check_inertias(system, where)
    _check_closures(system, phi, where)
    for f in system.forces:
        for attr in ("a", "b", "point"):
            pt = getattr(f, attr, None)
            if pt is not None and pt.link not in known_links:
                raise ModelError(f"{where}: force {f.name} is attached to unknown link {pt.link!r}")
        if isinstance(f, (JointSpring, JointDamper, JointInput)):
            system.joint(f.joint)
        if isinstance(f, JointInput) and f.input not in unames:
            raise ModelError(f"{where}: force {f.name} uses undeclared input {f.input!r}: declare it, "
                             f"{f.input} = Input({f.input!r}, UNIT, DESCRIPTION) (harness.modeling), and pass "
                             f"that symbol: JointInput({f.name!r}, {f.joint!r}, {f.input})")
    for cf in system.constraint_forces:
        links = [a[0] for a in cf.forces] + [a[1].link for a in cf.forces] + [t[0] for t in cf.torques]
        if any(link not in known_links for link in links):
            raise ModelError(f"{where}: constraint force {cf.name} acts on unknown link(s) "
                             f"{sorted(set(links) - known_links)}")
        if any(len(a) != 3 for a in cf.forces) or any(len(t) != 2 for t in cf.torques):
            raise ModelError(f"{where}: constraint force {cf.name}: forces are (link, Point, direction), "
                             f"torques (link, axis)")
        values = [v for a in cf.forces for v in (*a[1].position, *a[2])] + [v for t in cf.torques for v in t[1]]
        bad = _undeclared(values, static | set(system.q))
        if bad:
            raise ModelError(f"{where}: constraint force {cf.name} uses undeclared symbol(s) {bad}")
    if system.gravity is not None:
        d = [float(v) for v in system.gravity.direction]
        if abs(sum(v * v for v in d) - 1.0) > 1e-12:
            raise ModelError(f"{where}: gravity direction e_g must be a unit vector")
    if not any(link.has_mass for link in system.links):
        raise ModelError(f"{where}: no link has mass")


def _generic_state(system: System, at: float = 0.37) -> dict:
    """Default parameters and a generic configuration inside each coordinate's range (no special angle): the
    fraction ``at`` of the first coordinate's range, shifted by 0.11 for each next one."""
    subs = {p.symbol: p.default for p in system.parameters}
    for k, c in enumerate(system.coordinates):
        lo, hi = (float(v) for v in c.range) if c.range is not None else (-1.0, 1.0)
        subs[c.symbol] = lo + (at + 0.11 * k) % 1.0 * (hi - lo)
    return subs


CLOSURE_TOL = 1e-9   # relative to the point's distance from the origin (at least 1 m): round-off is ~1e-16


def _check_closures(system: System, phi: sp.Matrix, where: str) -> None:
    """Each :class:`Closure` holds on the map: ``nᵀ p_0(θ = φ(q)) = value`` at two generic configurations with the
    default parameters. Else the engines' constrained trees, which impose the closure, simulate another chain than
    the map describes, and the scenes fail on constraint drift alone."""
    known = {WORLD, *(link.name for link in system.links)}
    for c in system.closures:
        if c.point.link not in known:
            raise ModelError(f"{where}: closure {c.name} holds a point of unknown link {c.point.link!r}")
    if not system.closures:
        return
    from harness.derivation.kinematics import link_poses, point_position   # derivation builds on modeling
    poses, defaults = link_poses(system), system.default_parameters()
    for at in (0.37, 0.71):
        subs = {k: sp.Float(v) for k, v in _generic_state(system, at).items()}
        try:
            values = [complex(e.xreplace(subs).evalf()) for e in phi]
        except (TypeError, ValueError):
            continue
        if not all(cmath.isfinite(v) and abs(v.imag) <= 1e-12 * max(1.0, abs(v.real)) for v in values):
            continue   # the map is not real here (defined on part of the range only)
        theta = {j.theta: sp.Float(v.real) for j, v in zip(system.joints, values)}
        for c in system.closures:
            p = [float(v) for v in point_position(poses, c.point).xreplace(theta).xreplace(subs)]
            value = value_at(c.value, defaults)
            residual = sum(value_at(n, defaults) * v for n, v in zip(c.normal, p)) - value
            if abs(residual) > CLOSURE_TOL * max(1.0, abs(value), *map(abs, p)):
                state = ", ".join(f"{x.name} = {float(subs[x.symbol]):.6g}" for x in system.coordinates)
                raise ModelError(f"{where}: closure {c.name} does not hold on the map theta = phi(q): n^T p - value = "
                                 f"{residual:.3g} at {state} with the default parameters, p the point "
                                 f"{c.point.name or c.point.link} of {c.point.link}; the map and the closure describe "
                                 "different chains: check Joint.phi and the closure's point, normal and value")


def _check_map(system: System, phi: sp.Matrix, jac: sp.Matrix, where: str) -> None:
    """``theta = phi(q)`` must determine every lecture coordinate: each appears in the map, and ``J = ∂φ/∂q``
    has full column rank n at a generic configuration (else ``M_q = Jᵀ M_θ J`` (5.58) is singular)."""
    n = len(system.coordinates)
    used = set().union(*(sp.sympify(e).free_symbols for e in phi)) if len(phi) else set()
    for c in system.coordinates:
        if c.symbol not in used:
            raise ModelError(f"{where}: coordinate {c.name} moves no joint; give the joint it drives that name or "
                             f"set Joint.phi so that theta = phi(q) depends on {c.name}")
    if len(system.joints) < n:
        raise ModelError(f"{where}: {n} coordinates but only {len(system.joints)} tree joints; theta = phi(q) "
                         f"cannot determine q (remove a coordinate or add its joint)")
    try:
        J = jac.xreplace({k: sp.Float(v) for k, v in _generic_state(system).items()}).evalf()
        rank = sp.Matrix(J).rank(iszerofunc=lambda x: abs(complex(x)) < 1e-12)
    except (TypeError, ValueError):
        return  # not numeric at the generic state (e.g. a map defined only on part of the range)
    if rank < n:
        raise ModelError(f"{where}: the map theta = phi(q) has Jacobian rank {rank} < {n} coordinates at a generic "
                         f"configuration: two coordinates move the same joints; check Joint.phi")


def _check_inertias(system: System, where: str) -> None:
    """Each body's mass and inertia tensor at the default parameters: positive (semi-)definite, symmetric,
    principal moments satisfying the triangle inequality A + B >= C."""
    subs = {p.symbol: p.default for p in system.parameters}
    for link in system.links:
        try:
            mass = float(sp.sympify(link.mass).xreplace(subs))
            inertia = np.array(link.inertia.matrix.xreplace(subs).evalf(), dtype=float)
        except (TypeError, ValueError):
            continue
        try:
            check_inertia(f"link {link.name}", mass, inertia)
        except ModelError as exc:
            raise ModelError(f"{where}: {exc} at the default parameters; fix Link({link.name!r}, inertia=...): "
                             f"give the inertia about the centre of mass with principal moments A, B, C > 0 and "
                             f"A + B >= C (Inertia.cuboid builds a valid one)") from None


def check_inertia(where: str, mass: float, inertia: np.ndarray, atol: float = 1e-12) -> None:
    """Mass non-negative; inertia symmetric, positive semi-definite, principal moments satisfying the
    triangle inequality ``A + B >= C``."""
    if not np.all(np.isfinite(inertia)) or not np.isfinite(mass):
        raise ModelError(f"{where}: mass/inertia must be finite")
    if mass < 0:
        raise ModelError(f"{where}: mass {mass} must be non-negative")
    if not np.allclose(inertia, inertia.T, atol=atol):
        raise ModelError(f"{where}: inertia tensor must be symmetric")
    moments = np.linalg.eigvalsh(inertia)
    scale = max(abs(moments).max(), 1e-300)
    if moments.min() < -atol * scale:
        raise ModelError(f"{where}: inertia tensor is not positive (semi-)definite, principal moments {moments}")
    a, b, c = sorted(moments)
    if a + b < c * (1 - 1e-12) - atol * scale:
        raise ModelError(f"{where}: principal moments {moments} violate the triangle inequality A + B >= C")
    if mass == 0 and scale > 1e-300 and moments.max() > 0:
        raise ModelError(f"{where}: a massless link cannot have rotational inertia")
