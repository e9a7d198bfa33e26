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

:func:`urdf_roundtrip` (an engine that reads the URDF: Pinocchio, Drake) and :func:`mjcf_roundtrip` (MuJoCo)
return one record per compared item (error 0 when it matches), :func:`items` the one for the file the engine
reads; :func:`roundtrip` keeps the findings, the items whose error exceeds the tolerance. The numbers as loaded
are each adapter's own reading (``link_as_loaded``, ``joint_as_loaded``, ``point_as_loaded``, ``dofs``,
:mod:`harness.engines`): no engine is called here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from harness.export.mjcf import exported_inertia, fused_links
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
    # in Python floats: an item has at most 12 numbers, and NumPy's per-call overhead was 60 % of a model's round
    # trip (measured; the same IEEE operations, so the same errors bit for bit)
    intended, loaded = _floats(intended), _floats(loaded)
    if len(intended) != len(loaded) or not all(map(math.isfinite, loaded)):
        error = math.inf
    else:
        scale = max(map(abs, intended), default=0.0) or 1.0
        error = max((abs(a - b) for a, b in zip(loaded, intended)), default=0.0) / scale
    return RoundTripError(engine, item, intended, loaded, error)


def _floats(values) -> list[float]:
    return np.asarray(values, dtype=float).ravel().tolist()


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


# --------------------------------------------------------------------------- URDF (Pinocchio, Drake)
def _inertia(engine, link, loaded) -> RoundTripError:
    """A link's inertia tensor as the engine keeps it: about the centre of mass, or (Drake:
    ``inertia_about_origin``) about the link origin, ``I_o = I_c + m (|c|² 1 − c cᵀ)`` (3.126). The tensor about
    the centre of mass Drake gives back is ``I_o`` shifted back, so it carries the round-off of ``I_o``: relative to
    ``max|I_c|`` that is ``ε max|I_o| / max|I_c|``, 3.3e-13 for a 5 cm ball on a 1 m pendulum (and past 1e-12 for a
    1 cm ball, a false failure of a model that is right). Compared about the origin, the error is relative to the
    scale of what Drake keeps and computes with."""
    if "inertia_about_origin" not in loaded:
        return _numbers(engine, f"{link.name} inertia", link.inertia, loaded["inertia"])
    c = np.asarray(link.com, dtype=float)   # Steiner's term in floats (modeling.system.steiner is its symbolic form)
    about_origin = np.asarray(link.inertia, dtype=float) + link.mass * ((c @ c) * np.eye(3) - np.outer(c, c))
    return _numbers(engine, f"{link.name} inertia about its origin", about_origin, loaded["inertia_about_origin"])


def urdf_roundtrip(tree: NumericTree, model) -> list[RoundTripError]:
    """Every item of ``tree`` against an engine that loaded our URDF (Pinocchio, Drake).

    Per link: the moving joint that carries it, its frame relative to that joint's frame (in our trees each
    joint carries exactly one link whose frame is the joint frame: identity), mass, centre of mass (lever) and
    inertia about the centre of mass in the link frame; per joint: the parent joint, type, axis, placement in
    the parent link; per point: the joint that carries it and its position in its link's frame (joints are named
    as in our tree, ``None`` for the world). The inertia is compared about the point the engine keeps it about
    (:func:`_inertia`)."""
    E = model.name
    joint_of = {j.child: j.name for j in tree.joints} | {WORLD: None}
    out = [_names(E, "dofs", [len(tree.joints)], [model.dofs])]
    for link in tree.links:
        loaded = model.link_as_loaded(link.name)
        if loaded is None:
            out.append(_missing(E, link.name))
            continue
        out += [_names(E, f"{link.name} joint", [joint_of[link.name]], [loaded["joint"]]),
                _numbers(E, f"{link.name} frame", np.eye(4)[:3], loaded["frame"]),
                _numbers(E, f"{link.name} mass", [link.mass], [loaded["mass"]]),
                _inertia(E, link, loaded)]
        if link.mass > 0:  # a massless link has no centre of mass (and none is exported)
            out.append(_numbers(E, f"{link.name} com", link.com, loaded["com"]))
    for j in tree.joints:
        loaded = model.joint_as_loaded(j.name)
        if loaded is None:
            out.append(_missing(E, j.name))
            continue
        out += [_names(E, f"{j.name} parent", [joint_of[j.parent]], [loaded["parent"]]),
                _names(E, f"{j.name} type", [j.type], [loaded["type"]]),
                _numbers(E, f"{j.name} axis", j.axis, loaded["axis"]),
                _numbers(E, f"{j.name} origin", j.origin, loaded["origin"]),
                _numbers(E, f"{j.name} rotation", rpy_matrix(j.rpy), loaded["rotation"])]
    for point in tree.points:
        loaded = model.point_as_loaded(point.name)
        if loaded is None:
            out.append(_missing(E, point.name))
            continue
        out += [_names(E, f"{point.name} link", [joint_of[point.link]], [loaded["joint"]]),
                _numbers(E, f"{point.name} position", point.position, loaded["position"])]
    return out


# --------------------------------------------------------------------------- MJCF (MuJoCo)
def mjcf_roundtrip(tree: NumericTree, model) -> list[RoundTripError]:
    """Every item of ``tree`` against MuJoCo's model compiled from our MJCF.

    MuJoCo keeps a body's inertia as principal moments in a frame of their own; the adapter reads the full tensor
    in the body frame. A joint's anchor must be the body origin (our joint frame), and the body's placement in
    its parent is the joint's placement. Points are sites. A massless link is fused into its child's body
    (:func:`~harness.export.mjcf.fused_links`): it has no body of its own, its joint is checked in the child's, at
    the anchor and along the axis the tree's placements put it there (:func:`_in_body`)."""
    E = model.name
    fused = fused_links(tree)
    child_of = {j.parent: j.child for j in tree.joints}

    def body_of(link):  # a fused massless link lives in its child's body
        while link in fused:
            link = child_of[link]
        return link

    out = [_names(E, "dofs", [len(tree.joints)], [model.dofs])]
    for link in tree.links:
        if link.name in fused:
            continue  # no body of its own; its joint is checked in the child's body below
        loaded = model.body_as_loaded(link.name)
        if loaded is None:
            out.append(_missing(E, link.name))
            continue
        intended = link.inertia
        if exported_inertia(intended) is not None:
            # A tensor MuJoCo refuses as it is (a point mass, a slender rod) is exported plus the isotropic
            # MUJOCO_POINT_MASS_INERTIA (see numeric.py, mjcf.exported_inertia); exactly that tensor counts as a
            # match, anything else (zero included) is a finding.
            intended = intended + np.eye(3) * MUJOCO_POINT_MASS_INERTIA
        out += [_numbers(E, f"{link.name} mass", [link.mass], [loaded["mass"]]),
                _numbers(E, f"{link.name} inertia", intended, loaded["inertia"])]
        if link.mass > 0:  # a massless link has no centre of mass
            out.append(_numbers(E, f"{link.name} com", link.com, loaded["com"]))
    for j in tree.joints:
        loaded = model.joint_as_loaded(j.name)
        if loaded is None:
            out.append(_missing(E, j.name))
            continue
        parent = j.parent
        while parent in fused:  # the placement of a fused chain is the first joint's
            parent = next(k.parent for k in tree.joints if k.child == parent)
        anchor, axis, (origin, rotation) = _in_body(tree, j, fused)
        out += [_names(E, f"{j.name} bodies", [body_of(parent), body_of(j.child)], loaded["bodies"]),
                _names(E, f"{j.name} type", [j.type], [loaded["type"]]),
                _numbers(E, f"{j.name} axis", axis, loaded["axis"]),
                _numbers(E, f"{j.name} anchor", anchor, loaded["anchor"])]
        if j.parent not in fused:
            out += [_numbers(E, f"{j.name} origin", origin, loaded["origin"]),
                    _numbers(E, f"{j.name} rotation", rotation, loaded["rotation"])]
    for point in tree.points:
        loaded = model.point_as_loaded(point.name)
        if loaded is None:
            out.append(_missing(E, point.name))
            continue
        out += [_names(E, f"{point.name} link", [point.link], [loaded["link"]]),
                _numbers(E, f"{point.name} position", point.position, loaded["position"])]
    return out


def _in_body(tree: NumericTree, j, fused: set) -> tuple:
    """``(anchor, axis, (origin, rotation))`` of joint ``j`` in the MuJoCo body that holds it, from the tree's
    placements alone: the body is the first link after ``j`` that is not fused; with ``(t, R)`` the placement of
    that body's frame in ``j``'s (the product of the fused joints' ``origin``, ``rpy`` after ``j``), the anchor is
    ``Rᵀ (0 − t)`` and the axis ``Rᵀ e``, and the body sits at ``j``'s placement times ``(t, R)`` in its parent."""
    t, R, child = np.zeros(3), np.eye(3), j.child
    while child in fused:
        k = next(k for k in tree.joints if k.parent == child)
        t, R, child = t + R @ np.asarray(k.origin, dtype=float), R @ rpy_matrix(k.rpy), k.child
    R_j = rpy_matrix(j.rpy)
    return R.T @ -t, R.T @ np.asarray(j.axis, dtype=float), (np.asarray(j.origin, dtype=float) + R_j @ t, R_j @ R)


READERS = {"URDF": urdf_roundtrip, "MJCF": mjcf_roundtrip}


def items(tree: NumericTree, model) -> list[RoundTripError]:
    """Every item of ``tree`` against ``model`` (an engine adapter), by the file the engine reads."""
    return READERS[model.reads](tree, model)


def roundtrip(tree: NumericTree, *models, rtol: float = ROUNDTRIP_RTOL) -> list[RoundTripError]:
    """The findings: items of each engine adapter in ``models`` (``None`` skipped) whose error exceeds ``rtol``."""
    compared = [item for model in models if model is not None for item in items(tree, model)]
    return [e for e in compared if not e.error <= rtol]
