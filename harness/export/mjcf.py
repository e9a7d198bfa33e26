"""MJCF of a system, built with MuJoCo's ``MjSpec``.

Every effect the system does not have is switched off: contacts and all constraints (no limits, no
equality), frictionloss; springs, dampers, gravity and actuation only where the model has them; armature
zero. Springs and dampers between points are spatial tendons (``stiffness``, ``springlength``, ``damping``),
joint springs/viscous friction are joint ``stiffness``/``springref``/``damping``, inputs on tree joints are
``motor`` actuators with unit gear, attachment points are sites.
"""

from __future__ import annotations

import mujoco
import numpy as np

from harness.export.numeric import MUJOCO_POINT_MASS_INERTIA, NumericTree
from harness.model import WORLD

_JOINT_TYPE = {"revolute": mujoco.mjtJoint.mjJNT_HINGE, "prismatic": mujoco.mjtJoint.mjJNT_SLIDE}


def rpy_quat(rpy) -> np.ndarray:
    """Quaternion (w, x, y, z) of URDF's fixed-axis roll-pitch-yaw."""
    quat = np.zeros(4)
    mat = np.zeros(9)
    r, p, y = rpy
    cr, sr, cp, sp_, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    R = np.array([[cy * cp, cy * sp_ * sr - sy * cr, cy * sp_ * cr + sy * sr],
                  [sy * cp, sy * sp_ * sr + cy * cr, sy * sp_ * cr - cy * sr],
                  [-sp_, cp * sr, cp * cr]])
    mat[:] = R.ravel()
    mujoco.mju_mat2Quat(quat, mat)
    return quat


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
    has_spring = bool(tree.joint_stiffness) or any(t[3] for t in tree.tendons)
    has_damper = bool(tree.joint_damping) or any(t[5] for t in tree.tendons)
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
    links = {link.name: link for link in tree.links}
    pending = list(tree.joints)
    while pending:
        for j in list(pending):
            if j.parent not in bodies:
                continue
            link = links[j.child]
            body = bodies[j.parent].add_body(name=link.name, pos=j.origin, quat=rpy_quat(j.rpy))
            body.explicitinertial = True
            body.mass = link.mass
            body.ipos = link.com
            inertia = link.inertia
            if not np.any(inertia):
                inertia = np.eye(3) * MUJOCO_POINT_MASS_INERTIA
            body.fullinertia = [inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1], inertia[0, 2], inertia[1, 2]]
            joint = body.add_joint(name=j.name, type=_JOINT_TYPE[j.type], axis=j.axis)
            joint.limited = mujoco.mjtLimited.mjLIMITED_FALSE
            joint.armature = 0.0
            if j.name in tree.joint_stiffness:
                # MuJoCo 4: stiffness/damping are polynomial coefficient vectors; [0] is the linear one
                stiffness, joint.springref = tree.joint_stiffness[j.name]
                joint.stiffness = [stiffness, 0.0, 0.0]
            if j.name in tree.joint_damping:
                joint.damping = [tree.joint_damping[j.name], 0.0, 0.0]
            bodies[j.child] = body
            pending.remove(j)
    for point in tree.points:
        bodies[point.link].add_site(name=point.name, pos=point.position)
    for name, a, b, stiffness, rest, damping in tree.tendons:
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


def mjcf_string(tree: NumericTree) -> str:
    spec = mjcf_spec(tree)
    spec.compile()
    return spec.to_xml()
