"""MJCF of a system, built with MuJoCo's ``MjSpec``.

Every effect the system does not have is switched off: contacts and all constraints (no limits, no
equality), frictionloss; springs, dampers, gravity and actuation only where the model has them; armature
zero. Springs and dampers between points are spatial tendons (``stiffness``, ``springlength``, ``damping``),
joint springs/viscous friction are joint ``stiffness``/``springref``/``damping``, inputs on tree joints are
``motor`` actuators with unit gear, attachment points are sites.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
from lxml import etree

from harness.errors import ModelError
from harness.export.kept import exported
from harness.export.numeric import MUJOCO_POINT_MASS_INERTIA, NumericTree
from harness.modeling.system import WORLD

_JOINT_TYPE = {"revolute": mujoco.mjtJoint.mjJNT_HINGE, "prismatic": mujoco.mjtJoint.mjJNT_SLIDE}


def rpy_quat(rpy) -> np.ndarray:
    """Quaternion (w, x, y, z) of URDF's fixed-axis roll-pitch-yaw."""
    quat = np.zeros(4)
    mat = np.zeros(9)
    r, p, y = rpy
    # the C library's sine and cosine (NumPy's may take a SIMD path chosen per CPU): the exported numbers
    cr, sr, cp, sp_ = math.cos(r), math.sin(r), math.cos(p), math.sin(p)
    cy, sy = math.cos(y), math.sin(y)
    R = np.array([[cy * cp, cy * sp_ * sr - sy * cr, cy * sp_ * cr + sy * sr],
                  [sy * cp, sy * sp_ * sr + cy * cr, sy * sp_ * cr - cy * sr],
                  [-sp_, cp * sr, cp * cr]])
    mat[:] = R.ravel()
    mujoco.mju_mat2Quat(quat, mat)
    return quat


def fused_links(tree: NumericTree) -> set[str]:
    """Massless links MuJoCo cannot hold as bodies (moving bodies need mass and inertia > mjMINVAL): each is
    merged with its only child into one MuJoCo body carrying both joints in order. MuJoCo applies the joints
    of a body in sequence, each about/along its axis through its anchor (``pos``) in the frame moved by the
    previous ones: our chain, with the massless link's joint written in the child's frame (:class:`_Carried`).
    Nothing may be attached to the massless link (a site would move with the child's joint too)."""
    with_points = {p.link for p in tree.points}
    out = set()
    for link in tree.links:
        children = [j for j in tree.joints if j.parent == link.name]
        if link.mass == 0 and link.name not in with_points and len(children) == 1:
            out.add(link.name)
    return out


def unmerged_massless_links(tree: NumericTree) -> list[str]:
    """Massless links that are neither merged (:func:`fused_links`) nor the world's: MuJoCo refuses them as moving
    bodies. One clear message per link, with what to change, instead of MuJoCo's "mass and inertia of moving bodies
    must be larger than mjMINVAL"."""
    fused = fused_links(tree)
    out = []
    for link in tree.links:
        if link.mass != 0 or link.name in fused:
            continue
        children = [j.child for j in tree.joints if j.parent == link.name]
        points = sorted(p.name for p in tree.points if p.link == link.name)
        if len(children) == 1:
            why, fix = f"points are attached to it ({', '.join(points)})", "attach them to the link it carries"
        else:
            why = f"it carries {len(children)} links ({', '.join(children)})" if children else "it carries no link"
            fix = "give it a mass"
        out.append(f"link {link.name} is massless and MuJoCo cannot merge it with a child ({why}): {fix}")
    return out


class _Carried:
    """The joints of merged massless links on their way to the body that holds them (:func:`fused_links`): the
    placement ``pos``, ``quat`` of the current frame in the parent body, and each joint with its anchor and axis in
    that frame. :meth:`moved` passes to the next link's frame (a joint's ``origin``, ``rpy``): an anchor ``a``
    becomes ``Rᵀ (a − t)``, an axis ``Rᵀ e``; the placement ``pos + R_quat t``, ``quat ⊗ q(rpy)``."""

    def __init__(self, parent, pos, quat, joints=()):
        self.parent, self.pos, self.quat, self.joints = parent, pos, quat, list(joints)

    def moved(self, j) -> "_Carried":
        if not np.any(j.origin) and not np.any(j.rpy):  # the same frame: the same numbers, to the bit
            return _Carried(self.parent, self.pos, self.quat, self.joints)
        R, turn = np.zeros(9), rpy_quat(j.rpy)
        mujoco.mju_quat2Mat(R, turn)
        R = R.reshape(3, 3)
        placement, quat = np.zeros(9), np.zeros(4)
        mujoco.mju_quat2Mat(placement, np.asarray(self.quat, dtype=float))
        mujoco.mju_mulQuat(quat, np.asarray(self.quat, dtype=float), turn)
        joints = [(joint, R.T @ (anchor - j.origin), R.T @ axis) for joint, anchor, axis in self.joints]
        return _Carried(self.parent, self.pos + placement.reshape(3, 3) @ j.origin, quat, joints)


def _add_joint(body, j, tree: NumericTree, anchor=None, axis=None) -> None:
    """Joint ``j`` in ``body``: at the body's origin along ``j.axis``, or a merged massless link's joint at
    ``anchor`` along ``axis`` in the body's frame (:class:`_Carried`)."""
    joint = body.add_joint(name=j.name, type=_JOINT_TYPE[j.type], axis=j.axis if axis is None else axis)
    if anchor is not None and np.any(anchor):
        joint.pos = anchor
    joint.limited = mujoco.mjtLimited.mjLIMITED_FALSE
    joint.armature = j.armature  # zero unless the model has rotor inertia
    if j.name in tree.joint_stiffness:
        # MuJoCo 4: stiffness/damping are polynomial coefficient vectors; [0] is the linear one
        stiffness, joint.springref = tree.joint_stiffness[j.name]
        joint.stiffness = [stiffness, 0.0, 0.0]
    if j.name in tree.joint_damping:
        joint.damping = [tree.joint_damping[j.name], 0.0, 0.0]


def mjcf_spec(tree: NumericTree) -> mujoco.MjSpec:
    spec = mujoco.MjSpec()
    spec.modelname = tree.system
    spec.compiler.degree = False
    spec.compiler.autolimits = False
    spec.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_FALSE
    spec.option.gravity = tree.gravity
    disable = mujoco.mjtDisableBit
    flags = disable.mjDSBL_CONTACT | disable.mjDSBL_CONSTRAINT | disable.mjDSBL_FRICTIONLOSS | disable.mjDSBL_LIMIT \
        | disable.mjDSBL_EQUALITY
    has_spring = bool(tree.joint_stiffness) or any(t[3] is not None for t in tree.tendons)   # in the model, 0 or not
    has_damper = bool(tree.joint_damping) or any(t[5] is not None for t in tree.tendons)
    if not has_spring:
        flags |= disable.mjDSBL_SPRING
    if not has_damper:
        flags |= disable.mjDSBL_DAMPER
    if not np.any(tree.gravity):
        flags |= disable.mjDSBL_GRAVITY
    if not tree.actuators:
        flags |= disable.mjDSBL_ACTUATION
    spec.option.disableflags = int(flags)

    bodies = {WORLD: spec.worldbody}
    carried: dict[str, _Carried] = {}  # fused massless link -> its joints waiting for the child's body
    fused = fused_links(tree)
    refused = unmerged_massless_links(tree)
    if refused:
        raise ModelError(f"{tree.system}: {'; '.join(refused)}")
    links = {link.name: link for link in tree.links}
    pending = list(tree.joints)
    while pending:
        for j in list(pending):
            if j.parent in carried:
                here = carried[j.parent].moved(j)
            elif j.parent in bodies:
                here = _Carried(bodies[j.parent], j.origin, rpy_quat(j.rpy))
            else:
                continue
            pending.remove(j)
            if j.child in fused:
                carried[j.child] = _Carried(here.parent, here.pos, here.quat,
                                            here.joints + [(j, np.zeros(3), np.asarray(j.axis, dtype=float))])
                continue
            parent, pos, quat = here.parent, here.pos, here.quat
            link = links[j.child]
            body = parent.add_body(name=link.name, pos=pos, quat=quat)
            body.explicitinertial = True
            body.mass = link.mass
            body.ipos = link.com
            inertia, principal = link.inertia, exported_inertia(link.inertia)
            if principal is not None:  # a point mass, a slender rod: principal moments (exported_inertia)
                body.inertia = list(principal[0])
                if not np.array_equal(principal[1], [1.0, 0.0, 0.0, 0.0]):
                    body.iquat = list(principal[1])
            else:
                body.fullinertia = [inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1], inertia[0, 2],
                                    inertia[1, 2]]
            for joint, anchor, axis in here.joints:
                _add_joint(body, joint, tree, anchor, axis)
            _add_joint(body, j, tree)
            bodies[j.child] = body
    for point in tree.points:
        bodies[point.link].add_site(name=point.name, pos=point.position)
    add_visuals(tree, bodies, fused)
    for name, a, b, stiffness, rest, damping in tree.tendons:
        stiffness, rest, damping = stiffness or 0.0, rest or 0.0, damping or 0.0   # None: no spring, no damper
        tendon = spec.add_tendon(name=name, stiffness=[stiffness, 0.0, 0.0], springlength=[rest, rest],
                                 damping=[damping, 0.0, 0.0])
        tendon.limited = mujoco.mjtLimited.mjLIMITED_FALSE
        tendon.wrap_site(a)
        tendon.wrap_site(b)
    for input_name, joint in tree.actuators:
        act = spec.add_actuator(name=input_name, target=joint, trntype=mujoco.mjtTrn.mjTRN_JOINT)
        act.gear[0] = 1.0
        act.ctrllimited = mujoco.mjtLimited.mjLIMITED_FALSE
        act.forcelimited = mujoco.mjtLimited.mjLIMITED_FALSE
    return spec


# --------------------------------------------------------------------------- what the mechanism looks like
VISUAL_GROUP = 2          # MuJoCo geom group of the visual-only geoms (the renderer shows groups 0-2)
_COLOURS = ((0.20, 0.45, 0.75, 1.0), (0.85, 0.45, 0.15, 1.0), (0.25, 0.6, 0.3, 1.0), (0.6, 0.3, 0.65, 1.0),
            (0.75, 0.6, 0.15, 1.0), (0.35, 0.35, 0.35, 1.0))


def model_scale(tree: NumericTree) -> float:
    """The size of the mechanism: the largest joint offset, centre of mass or attachment point (1 m if none)."""
    lengths = [_length(j.origin) for j in tree.joints] + [_length(k.com) for k in tree.links]
    lengths += [_length(p.position) for p in tree.points]
    return max([v for v in lengths if np.isfinite(v)] + [0.0]) or 1.0


def _length(v) -> float:
    """Euclidean length by ``math.hypot`` (NumPy's ``norm`` is a BLAS dot product, whose kernel is chosen per CPU)."""
    return math.hypot(*(float(x) for x in v))


FULL_INERTIA_LEAST = 1e-14
"""The least principal moment of a tensor written as ``fullinertia``: MuJoCo's compiler refuses a full tensor whose
eigenvalue test finds a moment below about 5e-15, as it refuses principal moments below mjMINVAL = 1e-15. A tensor
with a smaller one is written by its principal moments (:func:`exported_inertia`)."""


def exported_inertia(inertia: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """``(principal moments, quaternion of their axes)`` a link's inertia tensor is written to MJCF with where MuJoCo
    refuses it as a full tensor, a principal moment below :data:`FULL_INERTIA_LEAST`: a point mass (the zero tensor)
    or a slender rod (0 about its long axis, which the lecture and papers neglect; it made MuJoCo's compiler fail with
    "inertia must have positive eigenvalues", exit 1 of a check). Such a tensor is written plus ``ε E``, ε =
    :data:`~harness.export.numeric.MUJOCO_POINT_MASS_INERTIA`: isotropic, so that its terms are ``ε J_ωᵀ J_ω`` in M
    and ``ε J_ωᵀ J̇_ω q̇`` in the bias whatever the body's orientation, which the MuJoCo adapter takes out of the
    quantities it reports (:meth:`~harness.engines.mujoco_engine.MujocoModel.stand_in`). None where the full
    tensor is written as it is."""
    if not np.any(inertia):
        return np.full(3, MUJOCO_POINT_MASS_INERTIA), np.array([1.0, 0.0, 0.0, 0.0])
    moments, quat = principal_axes(inertia)
    if moments.min() >= FULL_INERTIA_LEAST:
        return None
    return np.maximum(moments, 0.0) + MUJOCO_POINT_MASS_INERTIA, quat


def principal_axes(inertia: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Principal moments of a symmetric inertia tensor and the orientation (quaternion) of the axes they belong to:
    a diagonal tensor as it is, in the body's axes; a full one by MuJoCo's ``mju_eig3`` (the decomposition its
    compiler applies to ``fullinertia``). NumPy's ``eigh`` goes through the LAPACK/BLAS kernels OpenBLAS picks for
    the CPU: the Panda's boxes came out with other last digits under its AVX-512 kernels than under its AVX2 ones,
    so ``harness export --check`` called the committed MJCF stale on one machine and current on another
    (``OPENBLAS_CORETYPE=SkylakeX`` against ``Haswell``). ``mju_eig3`` is plain C arithmetic; its residual
    ``|V diag(w) Vᵀ − I| / |I|`` was at most 8.7e-15 over 20 000 random tensors (NumPy's ~1e-15): these numbers
    size the visual geoms only."""
    tensor = 0.5 * (np.asarray(inertia, dtype=float) + np.asarray(inertia, dtype=float).T)
    if not np.any(tensor - np.diag(np.diag(tensor))):
        return np.diag(tensor).copy(), np.array([1.0, 0.0, 0.0, 0.0])
    moments, axes, quat = np.zeros(3), np.zeros(9), np.zeros(4)
    mujoco.mju_eig3(moments, axes, quat, np.ascontiguousarray(tensor).ravel())
    return moments, quat


def equivalent_box(mass: float, inertia: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Half edge lengths and orientation (quaternion) of the homogeneous cuboid with this mass and inertia tensor
    about its centre (3.128) — the body's size as the model states it: edges ``a_i² = 6 (I_j + I_k − I_i) / m``
    along the principal axes."""
    moments, quat = principal_axes(inertia)
    total = moments.sum()
    edges = np.sqrt(np.maximum(6.0 * (total - 2.0 * moments) / mass, 0.0))
    return edges / 2.0, quat


# Two principal moments closer than this, relative to the largest, are taken as equal: a body with such a tensor is
# drawn as a sphere (all three) or a cylinder (two), not as a cuboid. mju_eig3's residual is below 1e-14 (above).
EQUAL_MOMENTS = 1e-9

# The turn that takes a cylinder's own axis (MuJoCo's geom z) to the principal axis x, y or z of its distinct moment.
_AXIS_FROM_Z = (np.array([np.sqrt(0.5), 0.0, np.sqrt(0.5), 0.0]), np.array([np.sqrt(0.5), -np.sqrt(0.5), 0.0, 0.0]),
                np.array([1.0, 0.0, 0.0, 0.0]))


def equivalent_cylinder(mass: float, inertia: np.ndarray) -> tuple[float, float, np.ndarray] | None:
    """Radius, half length and orientation (quaternion; the cylinder's axis is its z) of the homogeneous solid
    cylinder with this mass and inertia tensor about its centre (3.122), where two principal moments ``A`` are equal
    and the third, ``C``, is not: ``C = m r²/2`` about the axis and ``A = m (3 r² + h²)/12`` about a diameter, so
    ``r² = 2 C / m`` and ``h² = (12 A − 6 C) / m`` (not negative where the triangle inequality ``2 A ≥ C`` holds).
    None where no two moments are equal, or all three are (a sphere)."""
    moments, quat = principal_axes(inertia)
    equal = EQUAL_MOMENTS * moments.max()
    for axis in range(3):
        a, b = (moments[k] for k in range(3) if k != axis)
        if abs(a - b) <= equal < abs(moments[axis] - (a + b) / 2):
            across, along = (a + b) / 2, moments[axis]
            turned = np.zeros(4)
            mujoco.mju_mulQuat(turned, quat, _AXIS_FROM_Z[axis])
            return (float(np.sqrt(max(2.0 * along / mass, 0.0))),
                    float(np.sqrt(max((12.0 * across - 6.0 * along) / mass, 0.0))) / 2.0, turned)
    return None


def _capsule(body, name: str, a: np.ndarray, b: np.ndarray, radius: float, rgba) -> None:
    d = np.asarray(b, dtype=float) - np.asarray(a, dtype=float)
    length = _length(d)
    if length < 1e-9:
        return
    quat = np.zeros(4)
    mujoco.mju_quatZ2Vec(quat, d / length)
    body.add_geom(name=name, type=mujoco.mjtGeom.mjGEOM_CAPSULE, pos=(np.asarray(a) + np.asarray(b)) / 2.0,
                  quat=quat, size=[radius, length / 2.0, 0.0], rgba=rgba, contype=0, conaffinity=0,
                  group=VISUAL_GROUP, mass=0.0)


_SOLID_GEOMS = {"box": mujoco.mjtGeom.mjGEOM_BOX, "cylinder": mujoco.mjtGeom.mjGEOM_CYLINDER,
                "ball": mujoco.mjtGeom.mjGEOM_SPHERE}


def add_visuals(tree: NumericTree, bodies: dict, fused: set) -> None:
    """Visual-only geoms sized from the model (``contype = conaffinity = 0``, no mass; the inertia is explicit,
    ``inertiafromgeom="false"``, so that the dynamics do not change): a rigid body as the solids the model says it
    is made of (:attr:`Link.solids`), else as the cuboid of its mass and inertia tensor (:func:`equivalent_box`),
    one with an isotropic tensor as the homogeneous sphere of it (the rolling sphere, a ball, pulleys whose axial
    inertia alone matters), one with two equal principal moments as its cylinder (:func:`equivalent_cylinder`: a
    wheel, a disc, a round rod; not one built by ``Inertia.cuboid``, a cuboid of square section), a point mass as a
    small sphere, and the link frame as capsules from its origin to its centre of mass and to the joints of its
    children."""
    scale = model_scale(tree)
    radius = 0.015 * scale
    for k, link in enumerate(tree.links):
        if link.name not in bodies or link.name == WORLD:
            continue
        body, rgba = bodies[link.name], _COLOURS[k % len(_COLOURS)]
        ends = [j.origin for j in tree.joints if j.parent == link.name and j.parent not in fused]
        ends += [p.position for p in tree.points if p.link == link.name]
        if link.mass > 0:
            ends.append(link.com)
        for n, end in enumerate(ends):
            _capsule(body, f"visual_{link.name}_{n}", np.zeros(3), end, radius, rgba)
        if link.mass <= 0:
            continue
        if link.solids:
            for n, solid in enumerate(link.solids):
                body.add_geom(name=f"visual_{link.name}_solid_{n}", type=_SOLID_GEOMS[solid.kind], pos=solid.centre,
                              size=[*solid.size, *[0.0] * (3 - len(solid.size))], rgba=rgba, contype=0,
                              conaffinity=0, group=VISUAL_GROUP, mass=0.0)
            continue
        if not np.any(link.inertia):
            body.add_geom(name=f"visual_{link.name}_mass", type=mujoco.mjtGeom.mjGEOM_SPHERE, pos=link.com,
                          size=[0.06 * scale, 0.0, 0.0], rgba=rgba, contype=0, conaffinity=0, group=VISUAL_GROUP,
                          mass=0.0)
            continue
        moments, _ = principal_axes(link.inertia)
        if moments.max() - moments.min() <= EQUAL_MOMENTS * moments.max():  # the homogeneous sphere, 2/5 m r² (3.16)
            radius_s = float(np.clip(np.sqrt(2.5 * moments.min() / link.mass), 0.01 * scale, 2.0 * scale))
            body.add_geom(name=f"visual_{link.name}_body", type=mujoco.mjtGeom.mjGEOM_SPHERE, pos=link.com,
                          size=[radius_s, 0.0, 0.0], rgba=rgba, contype=0, conaffinity=0, group=VISUAL_GROUP, mass=0.0)
            continue
        cylinder = equivalent_cylinder(link.mass, link.inertia) if link.shape != "cuboid" else None
        if cylinder is not None:  # a wheel, a disc, a round rod (a cuboid of square section stays one)
            radius_c, half_length, quat = cylinder
            size = np.clip([radius_c, half_length], 0.01 * scale, 2.0 * scale)
            body.add_geom(name=f"visual_{link.name}_body", type=mujoco.mjtGeom.mjGEOM_CYLINDER, pos=link.com,
                          quat=quat, size=[*size, 0.0], rgba=rgba, contype=0, conaffinity=0, group=VISUAL_GROUP,
                          mass=0.0)
            continue
        half, quat = equivalent_box(link.mass, link.inertia)
        half = np.clip(half, 0.01 * scale, 2.0 * scale)
        body.add_geom(name=f"visual_{link.name}_body", type=mujoco.mjtGeom.mjGEOM_BOX, pos=link.com, quat=quat,
                      size=half, rgba=rgba, contype=0, conaffinity=0, group=VISUAL_GROUP, mass=0.0)


def _numbers(values) -> str:
    """Shortest decimals that read back as the same float64 (``repr``, at most 17 significant digits)."""
    return " ".join(repr(float(v)).removesuffix(".0") for v in values)


def _joint_stiffness(m, i):
    return [m.jnt_stiffness[i], *m.jnt_stiffnesspoly[i]]


def _joint_damping(m, i):
    return [m.dof_damping[m.jnt_dofadr[i]], *m.dof_dampingpoly[m.jnt_dofadr[i]]]


# (element, attribute) -> (object type whose id the element has, its values in the compiled model). An
# <inertial> has the id of its enclosing body; a tendon's stiffness/damping are polynomials like a joint's.
_OBJ = mujoco.mjtObj
_FIELDS = {
    ("option", "gravity"): (None, lambda m, i: m.opt.gravity),
    ("body", "pos"): (_OBJ.mjOBJ_BODY, lambda m, i: m.body_pos[i]),
    ("body", "quat"): (_OBJ.mjOBJ_BODY, lambda m, i: m.body_quat[i]),
    ("inertial", "pos"): (_OBJ.mjOBJ_BODY, lambda m, i: m.body_ipos[i]),
    ("inertial", "quat"): (_OBJ.mjOBJ_BODY, lambda m, i: m.body_iquat[i]),
    ("inertial", "mass"): (_OBJ.mjOBJ_BODY, lambda m, i: [m.body_mass[i]]),
    ("inertial", "diaginertia"): (_OBJ.mjOBJ_BODY, lambda m, i: m.body_inertia[i]),
    ("joint", "pos"): (_OBJ.mjOBJ_JOINT, lambda m, i: m.jnt_pos[i]),
    ("joint", "axis"): (_OBJ.mjOBJ_JOINT, lambda m, i: m.jnt_axis[i]),
    ("joint", "springref"): (_OBJ.mjOBJ_JOINT, lambda m, i: [m.qpos_spring[m.jnt_qposadr[i]]]),
    ("joint", "stiffness"): (_OBJ.mjOBJ_JOINT, _joint_stiffness),
    ("joint", "damping"): (_OBJ.mjOBJ_JOINT, _joint_damping),
    ("joint", "armature"): (_OBJ.mjOBJ_JOINT, lambda m, i: [m.dof_armature[m.jnt_dofadr[i]]]),
    ("site", "pos"): (_OBJ.mjOBJ_SITE, lambda m, i: m.site_pos[i]),
    ("site", "quat"): (_OBJ.mjOBJ_SITE, lambda m, i: m.site_quat[i]),
    ("spatial", "stiffness"): (_OBJ.mjOBJ_TENDON, lambda m, i: [m.tendon_stiffness[i], *m.tendon_stiffnesspoly[i]]),
    ("spatial", "damping"): (_OBJ.mjOBJ_TENDON, lambda m, i: [m.tendon_damping[i], *m.tendon_dampingpoly[i]]),
    ("spatial", "springlength"): (_OBJ.mjOBJ_TENDON, lambda m, i: m.tendon_lengthspring[i]),
    ("general", "gear"): (_OBJ.mjOBJ_ACTUATOR, lambda m, i: m.actuator_gear[i]),
    ("geom", "pos"): (_OBJ.mjOBJ_GEOM, lambda m, i: m.geom_pos[i]),
    ("geom", "quat"): (_OBJ.mjOBJ_GEOM, lambda m, i: m.geom_quat[i]),
    ("geom", "size"): (_OBJ.mjOBJ_GEOM, lambda m, i: m.geom_size[i]),
    ("geom", "rgba"): (_OBJ.mjOBJ_GEOM, lambda m, i: [round(float(v), 6) for v in m.geom_rgba[i]]),  # float32
    ("geom", "contype"): (_OBJ.mjOBJ_GEOM, lambda m, i: [m.geom_contype[i]]),
    ("geom", "conaffinity"): (_OBJ.mjOBJ_GEOM, lambda m, i: [m.geom_conaffinity[i]]),
    ("geom", "group"): (_OBJ.mjOBJ_GEOM, lambda m, i: [m.geom_group[i]]),
    ("geom", "mass"): (_OBJ.mjOBJ_GEOM, lambda m, i: [0.0]),
}
_ID_TAGS = {_OBJ.mjOBJ_BODY: "body", _OBJ.mjOBJ_JOINT: "joint", _OBJ.mjOBJ_SITE: "site",
            _OBJ.mjOBJ_TENDON: "spatial", _OBJ.mjOBJ_ACTUATOR: "general", _OBJ.mjOBJ_GEOM: "geom"}
_NAME_ATTRIBUTES = {"name", "model", "joint", "site"}


def _is_number_list(text: str) -> bool:
    try:
        [float(v) for v in text.split()]
    except ValueError:
        return False
    return bool(text.split())


def _element_ids(root, model: mujoco.MjModel):
    """``element -> id`` in ``model`` for the elements of each kind in :data:`_ID_TAGS`: by name, else by document
    order (body 0 is the world; a tendon's ``<site site=...>`` references are not sites, hence only ``<worldbody>``
    is searched for bodies, joints and sites). Built once per document: looking each element up again cost a
    list of its kind per attribute."""
    ids = {}
    for obj, tag in _ID_TAGS.items():
        scope = root.find("worldbody") if obj in (_OBJ.mjOBJ_BODY, _OBJ.mjOBJ_JOINT, _OBJ.mjOBJ_SITE) else root
        if scope is None:
            continue
        for k, element in enumerate(scope.iter(tag)):
            name = element.get("name")
            ids[element] = mujoco.mj_name2id(model, obj, name) if name is not None else \
                k + (1 if obj == _OBJ.mjOBJ_BODY else 0)
    return ids


def _full_precision(xml: str, model: mujoco.MjModel) -> str:
    """``xml`` (from ``MjSpec.to_xml``) with every number replaced by the float64 of the compiled ``model``.

    Measured with MuJoCo 4.0.0: ``MjSpec.to_xml()`` prints numbers with 6 significant digits (``pos="0.333333"``)
    and has no precision option, so the text loads into a model ~1e-6 (relative) off the spec it was written
    from. Each numeric attribute is rewritten from the model array it compiles into (``_FIELDS``), the
    element found by its name or, unnamed, by its position among the elements of its kind (MuJoCo numbers
    bodies, joints, sites, tendons, actuators in document order; ``<inertial>`` takes its body's). Only
    as many values are written as ``to_xml`` wrote (it drops trailing defaults, e.g. the zero polynomial
    terms of ``stiffness``); a numeric attribute without an entry in ``_FIELDS`` raises rather than stay
    rounded.
    """
    root = etree.fromstring(xml.encode())
    ids = _element_ids(root, model)
    for element in root.iter(etree.Element):
        for attribute, text in element.attrib.items():
            if attribute in _NAME_ATTRIBUTES or not _is_number_list(text):
                continue
            if (element.tag, attribute) not in _FIELDS:
                raise NotImplementedError(f"MJCF <{element.tag} {attribute}=...>: no full-precision source")
            obj, values = _FIELDS[element.tag, attribute]
            owner = element.getparent() if element.tag == "inertial" else element
            index = None if obj is None else ids[owner]
            element.set(attribute, _numbers(list(values(model, index))[:len(text.split())]))
    return etree.tostring(root, encoding="unicode") + "\n"


def mjcf_string(tree: NumericTree) -> str:
    """The MJCF text of ``mjcf_spec(tree)``, loading into the same model as the spec (see _full_precision)."""
    from harness.engines.warnings_log import capture

    spec = mjcf_spec(tree)
    with capture("mujoco", EXPORT, tree):
        model = spec.compile()
        xml = spec.to_xml()
    return _full_precision(xml, model)


EXPORT = "MjSpec.compile (export)"
"""Where the warnings of writing the MJCF are logged (:mod:`harness.engines.warnings_log`)."""


def exported_mjcf(tree: NumericTree) -> str:
    """:func:`mjcf_string` of ``tree``, kept for the next run with the warnings writing it raised
    (:func:`harness.export.kept.exported`): the text MuJoCo loads in a check."""
    return exported(tree, "mjcf", mjcf_string, warned_at=EXPORT)
