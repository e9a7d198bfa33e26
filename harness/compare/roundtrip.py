"""Round trip: do the engines hold what we exported?

An exported file can be loaded into something other than what we meant without any error: urdfdom drops a
link's whole ``<inertial>`` when one of its numbers does not parse (the link loads massless, the complaint
goes to stderr only), Pinocchio folds links into joint inertias, MuJoCo re-expresses inertias in principal
axes and normalizes axes. This module reads the numbers back from the *loaded* models and compares them with
the :class:`NumericTree` they were exported from:

* per link: mass, centre of mass in the link frame, inertia tensor about the centre of mass in the link
  frame (3x3), and that the link's frame is where we put it (Pinocchio: the link's body frame sits on its
  joint with identity placement);
* per joint: parent, type (``revolute`` / ``prismatic``), axis in the joint frame, placement relative to the
  parent (``origin`` translation, ``rotation`` matrix from URDF roll-pitch-yaw);
* per attachment point: the link it is fixed in and its position in that link's frame;
* the number of degrees of freedom (an extra joint would go unnoticed otherwise).

:func:`pinocchio_roundtrip` and :func:`mujoco_roundtrip` return one record per compared item (error 0 when
it matches); :func:`roundtrip` keeps the findings, the items whose error exceeds the tolerance.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import mujoco
import numpy as np
import pinocchio as pin

from harness.engines.mujoco_engine import MujocoModel
from harness.engines.pinocchio_engine import PinocchioModel
from harness.export.mjcf import fused_links
from harness.export.numeric import MUJOCO_POINT_MASS_INERTIA, NumericTree
from harness.modeling.system import WORLD

ROUNDTRIP_RTOL = 1e-12
"""Largest accepted error of a loaded item, relative to the item's scale ``max|intended|`` (absolute for an
all-zero item). The exporters lose nothing: the URDF holds every float as its shortest round-tripping
decimal (Python ``repr``, at most 17 significant digits) or exactly, the MJCF is handed to MuJoCo as an
``MjSpec`` in float64. What remains is arithmetic: MuJoCo's principal-axis decomposition of a full inertia
tensor and its quaternions cost a few ulps (observed ≤ 2e-14 relative), Pinocchio's roll-pitch-yaw rotation
about the same. 1e-12 leaves two orders of margin above that and is six orders below the damage a number
printed with 6 significant digits does (1e-6)."""

PINOCCHIO, MUJOCO = "pinocchio", "mujoco"


@dataclass
class RoundTripError:
    """One compared item. ``intended``/``loaded`` hold numbers, or names for structural items (parent,
    type); ``loaded`` is empty when the engine does not have the item at all. ``error`` is the max abs
    difference relative to ``max|intended|`` (absolute for an all-zero item); ``inf`` for a structural
    mismatch, a missing item or a shape mismatch."""

    engine: str
    item: str
    intended: list
    loaded: list
    error: float

    def __str__(self):
        return f"{self.engine}: {self.item}: intended {self.intended}, loaded {self.loaded} (error {self.error:.3g})"


def _numbers(engine, item, intended, loaded) -> RoundTripError:
    intended, loaded = np.asarray(intended, dtype=float).ravel(), np.asarray(loaded, dtype=float).ravel()
    if intended.shape != loaded.shape or not np.all(np.isfinite(loaded)):
        error = math.inf
    else:
        scale = np.abs(intended).max(initial=0.0) or 1.0
        error = float(np.abs(loaded - intended).max(initial=0.0) / scale)
    return RoundTripError(engine, item, intended.tolist(), loaded.tolist(), error)


def _names(engine, item, intended, loaded) -> RoundTripError:
    return RoundTripError(engine, item, list(intended), list(loaded), 0.0 if list(intended) == list(loaded) else math.inf)


def _missing(engine, name) -> RoundTripError:
    return RoundTripError(engine, f"{name} present", [name], [], math.inf)


def rpy_matrix(rpy) -> np.ndarray:
    """URDF roll-pitch-yaw (fixed axes x, y, z): ``R = Rz(yaw) Ry(pitch) Rx(roll)``, computed here and not
    taken from either exporter so that it checks them."""
    (cr, cp, cy), (sr, sp, sy) = np.cos(rpy), np.sin(rpy)
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


# --------------------------------------------------------------------------- Pinocchio
_PIN_ALIGNED = re.compile(r"JointModel([RP])([XYZ])")
_PIN_UNALIGNED = {"JointModelRevoluteUnaligned": "revolute", "JointModelPrismaticUnaligned": "prismatic"}


def _pin_joint_axis(joint) -> tuple[str, list]:
    """(type, axis) of a Pinocchio joint: axis-aligned joints (``JointModelRZ``, ``JointModelPX``) carry the
    axis in their type, unaligned ones (URDF axes that are not +x/+y/+z, e.g. -z) in ``.axis``. Any other
    joint model (e.g. ``JointModelRUBZ`` for a continuous joint) is reported by its name, without axis."""
    name = joint.shortname()
    if match := _PIN_ALIGNED.fullmatch(name):
        return ("revolute" if match[1] == "R" else "prismatic"), np.eye(3)["XYZ".index(match[2])].tolist()
    if name in _PIN_UNALIGNED:
        return _PIN_UNALIGNED[name], np.asarray(joint.extract().axis, dtype=float).tolist()
    return name, []


def pinocchio_roundtrip(tree: NumericTree, model: PinocchioModel) -> list[RoundTripError]:
    """Every item of ``tree`` against the Pinocchio model loaded from our URDF.

    ``model.inertias[jid]`` is the spatial inertia of everything rigidly attached to joint ``jid``, in the
    joint frame (massless point links add nothing); in our trees each joint carries exactly one link whose
    frame is the joint frame, so it must equal that link's mass, centre of mass (``lever``) and inertia about
    the centre of mass (``inertia``). Links and points are found as BODY frames of their name; a point's
    frame placement is relative to its parent joint, i.e. to its link's frame (joint 0, ``universe``, for
    world points)."""
    E, m = PINOCCHIO, model.model
    joint_of = {j.child: j.name for j in tree.joints} | {WORLD: "universe"}
    out = [_names(E, "dofs", [len(tree.joints)], [m.nv])]

    def body_frame(name):
        return m.frames[m.getFrameId(name, pin.FrameType.BODY)] if m.existFrame(name, pin.FrameType.BODY) else None

    for link in tree.links:
        frame = body_frame(link.name)
        if frame is None:
            out.append(_missing(E, link.name))
            continue
        jid = frame.parentJoint
        inertia = m.inertias[jid]
        out += [_names(E, f"{link.name} joint", [joint_of[link.name]], [m.names[jid]]),
                _numbers(E, f"{link.name} frame", np.eye(4)[:3], frame.placement.homogeneous[:3]),
                _numbers(E, f"{link.name} mass", [link.mass], [inertia.mass]),
                _numbers(E, f"{link.name} inertia", link.inertia, inertia.inertia)]
        if link.mass > 0:  # a massless link has no centre of mass (and none is exported)
            out.append(_numbers(E, f"{link.name} com", link.com, inertia.lever))
    for j in tree.joints:
        if not m.existJointName(j.name):
            out.append(_missing(E, j.name))
            continue
        jid = m.getJointId(j.name)
        kind, axis = _pin_joint_axis(m.joints[jid])
        placement = m.jointPlacements[jid]
        out += [_names(E, f"{j.name} parent", [joint_of[j.parent]], [m.names[m.parents[jid]]]),
                _names(E, f"{j.name} type", [j.type], [kind]),
                _numbers(E, f"{j.name} axis", j.axis, axis),
                _numbers(E, f"{j.name} origin", j.origin, placement.translation),
                _numbers(E, f"{j.name} rotation", rpy_matrix(j.rpy), placement.rotation)]
    for point in tree.points:
        frame = body_frame(point.name)
        if frame is None:
            out.append(_missing(E, point.name))
            continue
        out += [_names(E, f"{point.name} link", [joint_of[point.link]], [m.names[frame.parentJoint]]),
                _numbers(E, f"{point.name} position", point.position, frame.placement.translation)]
    return out


# --------------------------------------------------------------------------- MuJoCo
_MJ_TYPE = {mujoco.mjtJoint.mjJNT_HINGE: "revolute", mujoco.mjtJoint.mjJNT_SLIDE: "prismatic"}


def _quat_matrix(quat) -> np.ndarray:
    mat = np.zeros(9)
    mujoco.mju_quat2Mat(mat, np.asarray(quat, dtype=float))
    return mat.reshape(3, 3)


def mujoco_roundtrip(tree: NumericTree, model: MujocoModel) -> list[RoundTripError]:
    """Every item of ``tree`` against the compiled MuJoCo model.

    MuJoCo keeps a body's inertia as principal moments ``body_inertia`` in the frame ``body_iquat`` at
    ``body_ipos``; the full tensor in the body frame is ``R diag(I) Rᵀ``. A joint's axis ``jnt_axis`` is in
    its body's frame, its anchor ``jnt_pos`` must be the body origin (our joint frame), and the body's
    placement in its parent is ``body_pos``/``body_quat``. Points are sites, ``site_pos`` in their body."""
    E, m = MUJOCO, model.model

    def find(kind, name):
        return mujoco.mj_name2id(m, kind, name)

    def body_name(bid):
        return mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, bid)

    fused = fused_links(tree)
    child_of = {j.parent: j.child for j in tree.joints}

    def body_of(link):  # a fused massless link lives in its child's body
        while link in fused:
            link = child_of[link]
        return link

    out = [_names(E, "dofs", [len(tree.joints)], [m.nv])]
    for link in tree.links:
        if link.name in fused:
            continue  # no body of its own; its joint is checked in the child's body below
        bid = find(mujoco.mjtObj.mjOBJ_BODY, link.name)
        if bid < 0:
            out.append(_missing(E, link.name))
            continue
        R = _quat_matrix(m.body_iquat[bid])
        intended = link.inertia
        if not np.any(intended):
            # A zero inertia tensor (point mass) is exported as the isotropic MUJOCO_POINT_MASS_INERTIA,
            # which MuJoCo requires (see numeric.py); exactly that value counts as a match, anything else
            # (zero included) is a finding.
            intended = np.eye(3) * MUJOCO_POINT_MASS_INERTIA
        out += [_numbers(E, f"{link.name} mass", [link.mass], [m.body_mass[bid]]),
                _numbers(E, f"{link.name} inertia", intended, R @ np.diag(m.body_inertia[bid]) @ R.T)]
        if link.mass > 0:  # a massless link has no centre of mass
            out.append(_numbers(E, f"{link.name} com", link.com, m.body_ipos[bid]))
    for j in tree.joints:
        jid = find(mujoco.mjtObj.mjOBJ_JOINT, j.name)
        if jid < 0:
            out.append(_missing(E, j.name))
            continue
        bid = m.jnt_bodyid[jid]
        kind = _MJ_TYPE.get(mujoco.mjtJoint(m.jnt_type[jid]), str(mujoco.mjtJoint(m.jnt_type[jid])))
        parent = j.parent
        while parent in fused:  # the placement of a fused chain is the first joint's
            parent = next(k.parent for k in tree.joints if k.child == parent)
        out += [_names(E, f"{j.name} bodies", [body_of(parent), body_of(j.child)],
                       [body_name(m.body_parentid[bid]), body_name(bid)]),
                _names(E, f"{j.name} type", [j.type], [kind]),
                _numbers(E, f"{j.name} axis", j.axis, m.jnt_axis[jid]),
                _numbers(E, f"{j.name} anchor", np.zeros(3), m.jnt_pos[jid])]
        if j.parent not in fused:
            out += [_numbers(E, f"{j.name} origin", j.origin, m.body_pos[bid]),
                    _numbers(E, f"{j.name} rotation", rpy_matrix(j.rpy), _quat_matrix(m.body_quat[bid]))]
    for point in tree.points:
        sid = find(mujoco.mjtObj.mjOBJ_SITE, point.name)
        if sid < 0:
            out.append(_missing(E, point.name))
            continue
        out += [_names(E, f"{point.name} link", [point.link], [body_name(m.site_bodyid[sid])]),
                _numbers(E, f"{point.name} position", point.position, m.site_pos[sid])]
    return out


def roundtrip(tree: NumericTree, pin_model: PinocchioModel | None, mj_model: MujocoModel | None,
              rtol: float = ROUNDTRIP_RTOL) -> list[RoundTripError]:
    """The findings: items of either engine (skipped when its model is ``None``) whose error exceeds
    ``rtol``."""
    items = (pinocchio_roundtrip(tree, pin_model) if pin_model is not None else []) \
        + (mujoco_roundtrip(tree, mj_model) if mj_model is not None else [])
    return [e for e in items if not e.error <= rtol]
