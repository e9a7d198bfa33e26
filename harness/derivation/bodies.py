"""Per-body quantities of chapters 4 and 5, in lecture coordinates ``q``: what the lecture prints body by body
before it sums them (rotation matrices, angular velocities, the inertia tensor in the inertial frame, the
translational and rotational kinetic energy and the potential energy of one body). The printed equations of
these kinds (``R:``, ``S:``, ``omega:``, ``I_0:``, ``T_t:``, ``T_r:``, ``V:``) are compared with them
(:mod:`harness.compare.claims`); :mod:`harness.derivation.derive` assembles the same terms into ``M`` and ``V``.
"""

from __future__ import annotations

import sympy as sp

from harness.derivation.kinematics import link_poses
from harness.modeling.system import WORLD, System


def _in_q(system: System, expr):
    return expr.xreplace(dict(zip(system.theta, system.phi)))


def _link(system: System, name: str):
    for link in system.links:
        if link.name == name:
            return link
    if name == WORLD:
        return None
    raise ValueError(f"{system.name}: no link named {name!r}")


def rotation_matrix(system: System, link: str, relative_to: str = WORLD) -> sp.Matrix:
    """``R_a^b = (R_0^a)ᵀ R_0^b`` (4.9)–(4.21): the orientation of ``link``'s frame in ``relative_to``'s frame
    (the inertial frame by default)."""
    _link(system, link), _link(system, relative_to)
    poses = link_poses(system)
    return _in_q(system, poses[relative_to].R.T * poses[link].R)


def angular_velocity_matrix(system: System, link: str, relative_to: str = WORLD) -> sp.Matrix:
    """``S_a^b = Ṙ_a^b (R_a^b)ᵀ`` (4.44): the skew-symmetric matrix of the angular velocity of ``link``
    relative to ``relative_to``, in ``relative_to``'s frame."""
    R = rotation_matrix(system, link, relative_to)
    R_dot = R.applyfunc(lambda e: (sp.Matrix([e]).jacobian(system.q) * sp.Matrix(system.qd))[0])
    return R_dot * R.T


def angular_velocity(system: System, link: str) -> sp.Matrix:
    """``ω_0^k = J_ω q̇`` (4.57), (4.62): the angular velocity of ``link`` in the inertial frame."""
    _link(system, link)
    pose = link_poses(system)[link]
    return _in_q(system, pose.J_omega_theta) * system.phi.jacobian(system.q) * sp.Matrix(system.qd)


def centre_of_mass(system: System, link: str) -> sp.Matrix:
    """``p_0^s = R_0^k p_k^s + d_0^k`` (4.21) of ``link``'s centre of mass."""
    body = _link(system, link)
    pose = link_poses(system)[link]
    return _in_q(system, pose.R * body.com_vector + pose.d)


def inertia_in_inertial_frame(system: System, link: str) -> sp.Matrix:
    """``I_0^s = R_0^k I_k^s (R_0^k)ᵀ`` (5.15): the inertia tensor about the centre of mass, inertial frame."""
    R = rotation_matrix(system, link)
    return R * _link(system, link).inertia.matrix * R.T


def translational_energy(system: System, link: str) -> sp.Expr:
    """``T_t = ½ m (ṗ_0^s)ᵀ ṗ_0^s`` (5.6) of one body."""
    v = centre_of_mass(system, link).jacobian(system.q) * sp.Matrix(system.qd)
    return sp.sympify(_link(system, link).mass) * (v.T * v)[0] / 2


def rotational_energy(system: System, link: str) -> sp.Expr:
    """``T_r = ½ (ω_0)ᵀ I_0^s ω_0`` (5.12) of one body."""
    w = angular_velocity(system, link)
    return (w.T * inertia_in_inertial_frame(system, link) * w)[0] / 2


def gravity_potential(system: System, link: str) -> sp.Expr:
    """``V = −m g e_gᵀ p_0^s`` (5.20) of one body (zero at the inertial origin's level)."""
    if system.gravity is None:
        return sp.Integer(0)
    e_g = sp.Matrix(system.gravity.direction)
    mass = sp.sympify(_link(system, link).mass)
    return -mass * sp.sympify(system.gravity.g) * (e_g.T * centre_of_mass(system, link))[0]
