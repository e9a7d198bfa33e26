"""A :class:`~harness.modeling.system.System` built from a URDF file: links, joints and inertials become our
:class:`~harness.modeling.system.Link` / :class:`~harness.modeling.system.Joint` / :class:`~harness.modeling.system.Inertia` value objects.

What is read, and how
---------------------
* The XML is parsed by :func:`harness.files.untrusted.parse_xml` (a ``defusedxml`` gate: no DTD, entity expansion or
  external entities; bounded size and nesting): a URDF is a file from elsewhere. Only ``<robot>``, ``<link>/<inertial>`` (``origin xyz rpy``, ``mass``, ``inertia``)
  and ``<joint>`` (``type``, ``parent``, ``child``, ``origin xyz rpy``, ``axis``, ``mimic``) are read.
  ``<visual>``, ``<collision>`` (meshes, boxes), ``<limit>``, ``<dynamics>``, ``<safety_controller>``,
  ``<transmission>``, ``<gazebo>`` are ignored: the model is the rigid-body dynamics of chapter 5 with no
  joint limits, friction or damping (the conformance checks switch those off in the engines too).
* Joint types: ``revolute`` and ``continuous`` (a revolute joint without limits) and ``prismatic`` become our
  elementary joints (4.21) ``H = H(origin, rpy) · H_axis(theta)``; ``fixed`` joints and *locked* joints
  (``lock={joint: value}``, a movable joint held at ``value``) are merged away: everything rigidly attached
  to a link is lumped into that link's body. ``floating`` and ``planar`` joints raise :class:`ModelError`.
* ``<mimic joint=J multiplier=a offset=b>``: the tree joint keeps its place and gets the map
  ``theta = a · q_J + b`` (``theta = phi(q)``, see :mod:`harness.modeling.system`) when ``J`` is free; when ``J`` is
  locked at ``v`` the mimic joint is locked at ``a · v + b``.
* The root link is the inertial frame ``world``: its inertial (a base bolted to the ground) and everything
  fixed to it do not move and are dropped.

Lumping (the composite body of a link and what is fixed to it)
--------------------------------------------------------------
Each URDF link's inertial (mass ``m_i``, centre of mass ``c_i`` and inertia ``I_i`` about it, given in the
frame rotated by the inertial's ``rpy``) is expressed in the frame of the movable link ``k`` it is fixed to
(rotation ``R``, position ``p`` of the fixed chain): ``c = R c_i + p``, ``I = R R_rpy I_i R_rpyᵀ Rᵀ``. The
bodies of frame ``k`` are then one rigid body: ``m = Σ m_i``, ``c = Σ m_i c_i / m`` and, by Steiner's theorem
(3.133), ``I = Σ I_i + m_i (|d_i|² E − d_i d_iᵀ)`` with ``d_i = c_i − c``. This is float64 arithmetic on the
file's numbers; a link with a single inertial, no rotation and no offset keeps the file's numbers exactly.

Numbers: constants, with the masses as parameters
-------------------------------------------------
A URDF gives measured numbers, not the lecture's symbols. Centres of mass, inertia tensors and joint origins
enter the model as constants (``sp.Float``, the float64 the file's decimal text denotes): keeping ~10 symbols
per link would multiply the size of ``M`` and of its ``7³`` Christoffel derivatives, and random values drawn
independently for the six entries of a full inertia tensor are not physical in general (not positive
definite). The mass of each moving body is a :class:`Parameter` (``m_<link>``, unit kg, default from the file,
positive): ``M`` is linear in the masses, so this costs little, lets the conformance checks draw random
masses, and any positive mass with the file's inertia tensor is a physical body. ``masses=False`` makes the
masses constants too. Gravity is the parameter ``g`` (9.81 m/s² by default, along ``-z`` of the root link).

Roll-pitch-yaw angles within 1e-9 rad of a multiple of π/2 are taken as that exact multiple (``sp.pi/2``):
URDF files write quarter turns as decimals (``1.5707963267948966``, or truncated ``1.57079632679``, 5e-12 rad
off); taken literally, ``cos(1.5707963267948966) = 6.1e-17`` would put a spurious term into every entry of
``M`` and multiply its size. The engines load the exported float of ``pi/2``; the difference from a
truncated file value is below 1e-11 rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import sympy as sp

from harness.errors import ModelError
from harness.export.numeric import lump
from harness.modeling.system import WORLD, Coordinate, Gravity, Inertia, Joint, Link, Parameter, System

QUARTER_TURN_SNAP = 1e-9   # rad; see the module docstring
MOVABLE = ("revolute", "continuous", "prismatic")


# --------------------------------------------------------------------------- the file's content
@dataclass(frozen=True)
class UrdfInertial:
    """``<inertial>``: mass, centre of mass ``xyz`` in the link frame, inertia about it in the frame rotated
    by ``rpy`` (3x3)."""

    mass: float
    xyz: tuple
    rpy: tuple
    inertia: np.ndarray


@dataclass(frozen=True)
class UrdfLink:
    name: str
    inertial: UrdfInertial | None = None


@dataclass(frozen=True)
class UrdfMimic:
    """``<mimic>``: ``theta = multiplier · theta_joint + offset``."""

    joint: str
    multiplier: float = 1.0
    offset: float = 0.0


@dataclass(frozen=True)
class UrdfJoint:
    name: str
    type: str
    parent: str
    child: str
    xyz: tuple = (0.0, 0.0, 0.0)
    rpy: tuple = (0.0, 0.0, 0.0)
    axis: tuple = (1.0, 0.0, 0.0)   # URDF's default axis
    mimic: UrdfMimic | None = None


@dataclass(frozen=True)
class UrdfRobot:
    name: str
    links: tuple[UrdfLink, ...]
    joints: tuple[UrdfJoint, ...]
    root: str

    def link(self, name: str) -> UrdfLink:
        return next(link for link in self.links if link.name == name)

    def joint(self, name: str) -> UrdfJoint:
        for joint in self.joints:
            if joint.name == name:
                return joint
        raise ModelError(f"URDF {self.name}: no joint named {name!r}")


def _parse_xml(text: str, source: str):
    """The root element, parsed by :func:`harness.files.untrusted.parse_xml` (defusedxml gate: no DTD, entities or
    external references; bounded size and depth; one :class:`ModelError` line on refusal)."""
    from harness.files.untrusted import parse_xml

    return parse_xml(text, source)


def _floats(element, attribute: str, n: int, default, where: str) -> tuple:
    if element is None or element.get(attribute) is None:
        return tuple(default)
    text = element.get(attribute)
    try:
        values = tuple(float(v) for v in text.split())
    except ValueError:
        raise ModelError(f"URDF {where}: {attribute}={text!r} is not a list of numbers") from None
    if len(values) != n or not all(math.isfinite(v) for v in values):
        raise ModelError(f"URDF {where}: {attribute}={text!r} needs {n} finite number(s)")
    return values


def _float(element, attribute: str, where: str, default: float | None = None) -> float:
    if element is None or element.get(attribute) is None:
        if default is None:
            raise ModelError(f"URDF {where}: missing {attribute}")
        return default
    return _floats(element, attribute, 1, (), where)[0]


def parse(source: str | Path) -> UrdfRobot:
    """Read a URDF file (or its text, when ``source`` starts with ``<``)."""
    text, where = str(source), "<string>"
    if not text.lstrip().startswith("<"):
        path = where = Path(source)
        try:
            text = path.read_text()
        except OSError as error:
            raise ModelError(f"URDF {path}: cannot read ({error.strerror})") from None
    root = _parse_xml(text, str(where))
    if root.tag != "robot":
        raise ModelError(f"URDF: the root element is <{root.tag}>, expected <robot>")
    name = root.get("name", "robot")
    links = []
    for element in root.findall("link"):
        link_name = element.get("name")
        if not link_name:
            raise ModelError(f"URDF {name}: a <link> without a name")
        inertial = None
        if (node := element.find("inertial")) is not None:
            where = f"link {link_name} <inertial>"
            origin = node.find("origin")
            tensor = node.find("inertia")
            if tensor is None:
                raise ModelError(f"URDF {where}: missing <inertia>")
            # all six are required (urdfdom drops the whole <inertial> when one is missing; we refuse the file)
            xx, xy, xz, yy, yz, zz = (_float(tensor, a, where) for a in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"))
            inertial = UrdfInertial(mass=_float(node.find("mass"), "value", where),
                                    xyz=_floats(origin, "xyz", 3, (0.0, 0.0, 0.0), where),
                                    rpy=_floats(origin, "rpy", 3, (0.0, 0.0, 0.0), where),
                                    inertia=np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]))
        links.append(UrdfLink(link_name, inertial))
    names = [link.name for link in links]
    if len(set(names)) != len(names):
        raise ModelError(f"URDF {name}: duplicate link names")
    joints = []
    for element in root.findall("joint"):
        joint_name, kind = element.get("name"), element.get("type")
        where = f"joint {joint_name}"
        parent, child = element.find("parent"), element.find("child")
        if not joint_name or parent is None or child is None or kind is None:
            raise ModelError(f"URDF {name}: a <joint> needs name, type, <parent link> and <child link>")
        if kind not in MOVABLE + ("fixed",):
            raise ModelError(f"URDF {where}: type {kind!r} is not supported (revolute, continuous, prismatic, fixed)")
        origin = element.find("origin")
        mimic = None
        if (node := element.find("mimic")) is not None:
            mimic = UrdfMimic(node.get("joint", ""), _float(node, "multiplier", where, 1.0),
                              _float(node, "offset", where, 0.0))
        axis = _floats(element.find("axis"), "xyz", 3, (1.0, 0.0, 0.0), where)
        norm = math.sqrt(sum(a * a for a in axis))
        if kind != "fixed" and not norm > 0:
            raise ModelError(f"URDF {where}: axis must not be zero")
        joints.append(UrdfJoint(joint_name, kind, parent.get("link"), child.get("link"),
                                _floats(origin, "xyz", 3, (0.0, 0.0, 0.0), where),
                                _floats(origin, "rpy", 3, (0.0, 0.0, 0.0), where),
                                tuple(a / norm for a in axis) if norm > 0 else axis, mimic))
    children = [j.child for j in joints]
    for j in joints:
        if j.parent not in names or j.child not in names:
            raise ModelError(f"URDF {name}: joint {j.name} connects unknown link(s) {j.parent!r} -> {j.child!r}")
    if len(set(children)) != len(children):
        raise ModelError(f"URDF {name}: a link is the child of more than one joint (closed chains are not URDF)")
    roots = [n for n in names if n not in children]
    if len(roots) != 1:
        raise ModelError(f"URDF {name}: expected one root link, found {roots}")
    return UrdfRobot(name, tuple(links), tuple(joints), roots[0])


# --------------------------------------------------------------------------- numbers
def product(*factors) -> np.ndarray:
    """``A @ B @ …`` of 3 × 3 matrices, the last factor possibly a 3-vector, each entry the correctly rounded sum of
    its products (``math.fsum``). NumPy's ``@`` calls OpenBLAS, whose kernel is picked for the CPU: with FMA and
    without (``OPENBLAS_CORETYPE=Haswell`` against ``Prescott``) the Panda's link 7 inertia came out 1 ulp apart,
    and the committed exports of a model built from a URDF are compared digit for digit (``harness export
    --check``). These are the numbers the model is made of: they must not depend on the machine."""
    out = np.asarray(factors[-1], dtype=float).tolist()
    for factor in reversed(factors[:-1]):
        A = np.asarray(factor, dtype=float).tolist()
        if isinstance(out[0], list):
            out = [[math.fsum(A[i][k] * out[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
        else:
            out = [math.fsum(A[i][k] * out[k] for k in range(3)) for i in range(3)]
    return np.array(out)


def rpy_matrix(rpy) -> np.ndarray:
    """URDF roll-pitch-yaw (fixed axes): ``R = R_z(yaw) R_y(pitch) R_x(roll)``."""
    (cr, cp, cy), (sr, sp_, sy) = ([math.cos(float(a)) for a in rpy]), ([math.sin(float(a)) for a in rpy])
    return product([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]], [[cp, 0, sp_], [0, 1, 0], [-sp_, 0, cp]],
                   [[1, 0, 0], [0, cr, -sr], [0, sr, cr]])


def matrix_rpy(R: np.ndarray) -> tuple:
    """Roll-pitch-yaw of a rotation matrix (the inverse of :func:`rpy_matrix` away from pitch = ±π/2)."""
    pitch = math.atan2(-R[2, 0], math.hypot(R[0, 0], R[1, 0]))
    if math.isclose(abs(pitch), math.pi / 2, abs_tol=1e-12):
        return (math.atan2(-R[1, 2], R[1, 1]), pitch, 0.0)
    return (math.atan2(R[2, 1], R[2, 2]), pitch, math.atan2(R[1, 0], R[0, 0]))


def axis_rotation(axis, angle: float) -> np.ndarray:
    """Rotation by ``angle`` about the unit vector ``axis`` (Rodrigues)."""
    k = np.asarray(axis, dtype=float)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * product(K, K)


def exact_angle(value: float, snap: float = QUARTER_TURN_SNAP):
    """``value`` as an exact multiple of π/2 when it is within ``snap`` (:data:`QUARTER_TURN_SNAP`) of one, else a
    Float (``snap < 0``: always the Float, the file's decimals taken literally)."""
    k = round(value / (math.pi / 2))
    if abs(value - k * math.pi / 2) <= snap or value == 0:
        return sp.pi * k / 2 if k else sp.Integer(0)
    return sp.Float(value)


def _number(value: float):
    """A float as a SymPy constant: exact integers stay integers (0, ±1), others are the float64 itself."""
    return sp.Integer(int(value)) if float(value).is_integer() else sp.Float(value)


def _axis(axis) -> tuple:
    return tuple(_number(a) for a in axis)


@dataclass
class _Body:
    """Inertials lumped in one movable frame: ``(mass, com, inertia about com)`` in that frame."""

    parts: list = field(default_factory=list)

    def add(self, inertial: UrdfInertial, R: np.ndarray, p: np.ndarray, identity: bool) -> None:
        if identity and not any(inertial.rpy):
            self.parts.append((inertial.mass, np.array(inertial.xyz), inertial.inertia))
            return
        Rin = product(R, rpy_matrix(inertial.rpy))
        self.parts.append((inertial.mass, product(R, inertial.xyz) + p, product(Rin, inertial.inertia, Rin.T)))

    def lumped(self):
        return lump(self.parts)


# --------------------------------------------------------------------------- URDF -> System
@dataclass(frozen=True)
class Frame:
    """Where a URDF link sits: fixed in the movable link ``body`` at rotation ``R`` and position ``p``."""

    body: str
    R: np.ndarray
    p: np.ndarray

    @property
    def identity(self) -> bool:
        return bool(np.array_equal(self.R, np.eye(3)) and not np.any(self.p))


def frames(robot: UrdfRobot, free: set[str], lock: dict[str, float]) -> dict[str, Frame]:
    """The movable link (or ``world``) each URDF link is fixed to; ``free`` joints start a new body."""
    out = {robot.root: Frame(WORLD, np.eye(3), np.zeros(3))}
    pending = list(robot.joints)
    while pending:
        progressed = False
        for j in list(pending):
            if j.parent not in out:
                continue
            pending.remove(j)
            progressed = True
            if j.name in free:
                out[j.child] = Frame(j.child, np.eye(3), np.zeros(3))
                continue
            parent = out[j.parent]
            R_j = rpy_matrix(j.rpy)
            p_j = np.array(j.xyz, dtype=float)
            value = lock.get(j.name, 0.0)
            if j.type == "prismatic":
                p_j = p_j + product(R_j, np.array(j.axis) * value)
            elif j.type in ("revolute", "continuous") and value:
                R_j = product(R_j, axis_rotation(j.axis, value))
            out[j.child] = Frame(parent.body, product(parent.R, R_j), product(parent.R, p_j) + parent.p)
        if not progressed:
            raise ModelError(f"URDF {robot.name}: links {[j.child for j in pending]} are not connected to the root")
    return out


def lock_values(robot: UrdfRobot, lock: dict[str, float]) -> dict[str, float]:
    """``lock`` extended by the mimic joints of locked joints (``a · v + b``) and by every fixed joint (0)."""
    values = dict(lock)
    for name in lock:
        joint = robot.joint(name)
        if joint.type == "fixed":
            raise ModelError(f"URDF {robot.name}: joint {name} is fixed already; only movable joints can be locked")
        if joint.mimic is not None:
            raise ModelError(f"URDF {robot.name}: joint {name} mimics {joint.mimic.joint}; lock that joint instead")
    for j in robot.joints:
        if j.mimic is not None and j.mimic.joint in lock:
            values[j.name] = j.mimic.multiplier * lock[j.mimic.joint] + j.mimic.offset
        elif j.type == "fixed":
            values[j.name] = 0.0
    return values


def to_system(robot: UrdfRobot, *, name: str, title: str, lecture: str, doc: str = "",
              lock: dict[str, float] | None = None, coordinates: dict[str, str] | None = None,
              masses: bool = True, g: float = 9.81, mass_names: dict[str, str] | None = None,
              quarter_turns: bool = True) -> System:
    """Our model of ``robot``: one elementary joint per free URDF joint, one body per movable link.

    ``lock`` holds movable joints at a value (rad or m; their mimic joints follow); ``coordinates`` names the
    lecture coordinate of each free, non-mimic joint (default ``q_1``, ``q_2``, … in the file's order);
    ``masses`` makes each body's mass a parameter (``mass_names`` overrides ``m_<link>``); ``quarter_turns=False``
    takes every joint angle literally (no snap to multiples of π/2, see the module docstring)."""
    snap = QUARTER_TURN_SNAP if quarter_turns else -1.0
    for joint in lock or {}:
        if joint not in {j.name for j in robot.joints}:
            raise ModelError(f"URDF {robot.name}: cannot lock unknown joint {joint!r}")
    locked = lock_values(robot, lock or {})
    free = [j for j in robot.joints if j.name not in locked]
    leaders = [j for j in free if j.mimic is None]
    names = coordinates or {j.name: f"q_{k + 1}" for k, j in enumerate(leaders)}
    missing = [j.name for j in leaders if j.name not in names]
    if missing:
        raise ModelError(f"URDF {robot.name}: no coordinate name for joint(s) {missing}")
    coords = {j.name: Coordinate(names[j.name], "m" if j.type == "prismatic" else "rad",
                                 f"{j.type} joint {j.name} of the URDF") for j in leaders}
    where = frames(robot, {j.name for j in free}, locked)

    bodies: dict[str, _Body] = {}
    for link in robot.links:
        frame = where[link.name]
        if link.inertial is not None and frame.body != WORLD:
            bodies.setdefault(frame.body, _Body()).add(link.inertial, frame.R, frame.p, frame.identity)

    links = []
    for j in free:
        mass, com, inertia = bodies.get(j.child, _Body()).lumped()
        fixed_to_it = sorted(n for n, f in where.items() if f.body == j.child and n != j.child)
        description = f"URDF link {j.child}" + (f" with {', '.join(fixed_to_it)} fixed to it" if fixed_to_it else "")
        mass_value = _number(mass)
        if masses and mass > 0:
            pname = (mass_names or {}).get(j.child, f"m_{j.child}")
            mass_value = Parameter(pname, float(mass), "kg", f"mass of the body of {description}")
        links.append(Link(j.child, mass_value, tuple(_number(c) for c in com),
                          Inertia(*(_number(inertia[a, b]) for a, b in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)))),
                          description=description))

    joints = []
    for j in free:
        parent = where[j.parent]
        if parent.identity:
            origin, rpy = j.xyz, tuple(exact_angle(a, snap) for a in j.rpy)
        else:  # the joint sits on a link fixed to its body: compose the fixed chain with the joint's origin
            origin = tuple(product(parent.R, j.xyz) + parent.p)
            rpy = tuple(exact_angle(a, snap) for a in matrix_rpy(product(parent.R, rpy_matrix(j.rpy))))
        kind = "prismatic" if j.type == "prismatic" else "revolute"
        if j.mimic is None:
            phi = coords[j.name]
        else:
            if j.mimic.joint not in coords:
                raise ModelError(f"URDF {robot.name}: joint {j.name} mimics {j.mimic.joint!r}, which is not a free "
                                 f"joint of the model")
            phi = _number(j.mimic.multiplier) * coords[j.mimic.joint] + _number(j.mimic.offset)
        joints.append(Joint(j.name, kind, parent.body, j.child, axis=_axis(j.axis),
                            origin=tuple(_number(v) for v in origin), rpy=rpy, phi=phi))

    g_param = Parameter("g", g, "m/s^2", "acceleration due to gravity, along -z of the root link")
    return System(name=name, title=title, lecture=lecture, coordinates=tuple(coords.values()), links=tuple(links),
                  joints=tuple(joints), gravity=Gravity(g_param, (0, 0, -1)), doc=doc)


def from_urdf(path: str | Path, **kwargs) -> System:
    """:func:`to_system` of :func:`parse` ``(path)``."""
    return to_system(parse(path), **kwargs)
