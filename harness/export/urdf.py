"""URDF of a system, written with yourdfpy.

Links carry ``<inertial>`` (mass, centre of mass, full inertia tensor about it in the link frame); tree
joints become ``revolute`` / ``prismatic`` joints (URDF requires ``<limit>`` for them: the limits are set
wide and no engine enforces them in dynamics). Attachment points of springs, dampers and forces become
massless links on ``fixed`` joints, so that an engine can compute those forces from its own frames.
Joint viscous friction is recorded as ``<dynamics damping>`` (informative; Pinocchio does not apply it).
"""

from __future__ import annotations

import numpy as np
from lxml import etree

from harness.export.kept import exported
from harness.export.numeric import NumericTree
from harness.modeling.system import WORLD

WIDE_LIMIT = 1e6


def _origin(xyz, rpy=(0.0, 0.0, 0.0)) -> np.ndarray:
    from yourdfpy.urdf import tra  # transformations module vendored by yourdfpy

    matrix = tra.euler_matrix(*rpy, axes="sxyz")
    matrix[:3, 3] = xyz
    return matrix


_LAST: list = [None, None]  # (tree, its URDF text): Pinocchio and Drake load the same tree one after the other


def urdf_string(tree: NumericTree) -> str:
    """The URDF text of ``tree`` (the text of the last tree is kept: one writing for both engines that read it)."""
    if _LAST[0] is not tree:
        _LAST[1] = _urdf_string(tree)
        _LAST[0] = tree
    return _LAST[1]


def exported_urdf(tree: NumericTree) -> str:
    """:func:`urdf_string` of ``tree``, kept for the next run (:func:`harness.export.kept.exported`): the text
    Pinocchio and Drake load in a check (yourdfpy, which imports trimesh, 0.7 s a process, only where it is
    written)."""
    if _LAST[0] is not tree:
        _LAST[1] = exported(tree, "urdf", _urdf_string)
        _LAST[0] = tree
    return _LAST[1]


def _urdf_string(tree: NumericTree) -> str:
    import yourdfpy

    links = [yourdfpy.Link(name=WORLD)]
    joints = []
    for link in tree.links:
        inertial = None
        if link.mass > 0:
            inertial = yourdfpy.Inertial(origin=_origin(link.com), mass=link.mass, inertia=link.inertia)
        links.append(yourdfpy.Link(name=link.name, inertial=inertial))
    for j in tree.joints:
        joints.append(yourdfpy.Joint(
            name=j.name, type=j.type, parent=j.parent, child=j.child, origin=_origin(j.origin, j.rpy), axis=j.axis,
            limit=yourdfpy.Limit(effort=WIDE_LIMIT, velocity=WIDE_LIMIT, lower=-WIDE_LIMIT, upper=WIDE_LIMIT),
            dynamics=yourdfpy.Dynamics(damping=tree.joint_damping[j.name]) if j.name in tree.joint_damping else None))
    for point in tree.points:
        links.append(yourdfpy.Link(name=point.name))
        joints.append(yourdfpy.Joint(name=f"{point.name}_fixed", type="fixed", parent=point.link,
                                     child=point.name, origin=_origin(point.position)))
    robot = yourdfpy.Robot(name=tree.system, links=links, joints=joints)
    urdf = yourdfpy.URDF(robot=robot, build_scene_graph=False, load_meshes=False)
    return etree.tostring(urdf.write_xml(), pretty_print=True, xml_declaration=True, encoding="UTF-8").decode()
