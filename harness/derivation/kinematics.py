"""Rigid-body kinematics of chapter 4: elementary rotations, homogeneous transformations, Jacobians.

Link poses are computed in tree joint coordinates ``theta`` (what an engine sees) and then expressed in
lecture coordinates by substituting the map ``theta = phi(q)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from harness.modeling.system import WORLD, Point, System


def rotation(axis, angle) -> sp.Matrix:
    """Rotation by ``angle`` about the unit vector ``axis``; for the coordinate axes these are the
    elementary rotation matrices ``R_x``, ``R_y``, ``R_z`` of (4.9), (4.10)."""
    x, y, z = (sp.nsimplify(v) for v in axis)
    c, s = sp.cos(angle), sp.sin(angle)
    if (x, y, z) == (1, 0, 0):
        return sp.Matrix([[1, 0, 0], [0, c, -s], [0, s, c]])
    if (x, y, z) == (0, 1, 0):
        return sp.Matrix([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    if (x, y, z) == (0, 0, 1):
        return sp.Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    k = sp.Matrix([x, y, z])
    K = skew(k)
    return sp.eye(3) + s * K + (1 - c) * K * K  # Rodrigues


def rpy_rotation(rpy) -> sp.Matrix:
    """Fixed-axis roll-pitch-yaw ``R = R_z(yaw) R_y(pitch) R_x(roll)`` (URDF's convention)."""
    r, p, y = (sp.nsimplify(v) for v in rpy)
    return rotation((0, 0, 1), y) * rotation((0, 1, 0), p) * rotation((1, 0, 0), r)


def skew(v) -> sp.Matrix:
    """The skew-symmetric matrix ``S(v)`` with ``S(v) w = v x w`` (4.50)."""
    return sp.Matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


@dataclass(frozen=True)
class Pose:
    """``R_0^k`` and ``d_0^k`` of a link frame, and the angular-velocity Jacobian w.r.t. ``theta``
    (``omega_0^k = J_omega,theta theta_dot``, columns ``R_0^{j} a_j`` for revolute joints j)."""

    R: sp.Matrix
    d: sp.Matrix
    J_omega_theta: sp.Matrix


def link_poses(system: System) -> dict[str, Pose]:
    """Poses of every link frame in tree joint coordinates, by chaining (4.21)."""
    n = len(system.joints)
    poses = {WORLD: Pose(sp.eye(3), sp.zeros(3, 1), sp.zeros(3, n))}
    index = {j.name: k for k, j in enumerate(system.joints)}
    pending = list(system.joints)
    while pending:
        for joint in list(pending):
            if joint.parent not in poses:
                continue
            parent = poses[joint.parent]
            R_off = parent.R * rpy_rotation(joint.rpy)
            d_off = parent.d + parent.R * joint.origin_vector
            Jw = parent.J_omega_theta.copy()
            if joint.type == "revolute":
                R = R_off * rotation(joint.axis, joint.theta)
                d = d_off
                Jw[:, index[joint.name]] = R_off * joint.axis_vector
            else:
                R = R_off
                d = d_off + R_off * joint.axis_vector * joint.theta
            poses[joint.child] = Pose(R, d, Jw)
            pending.remove(joint)
    return poses


def point_position(poses: dict[str, Pose], point: Point) -> sp.Matrix:
    """``p_0 = R_0^k p_k + d_0^k`` (4.21)."""
    pose = poses[point.link]
    return pose.R * point.vector + pose.d
