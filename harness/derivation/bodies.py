"""Per-body quantities of chapters 4 and 5, in lecture coordinates ``q``: what the lecture prints body by body
before it sums them (rotation matrices, angular velocities, the inertia tensor in the inertial frame, the
translational and rotational kinetic energy and the potential energy of one body). The printed equations of
these kinds (``R:``, ``S:``, ``omega:``, ``I_0:``, ``T_t:``, ``T_r:``, ``V:``) are compared with them
(:mod:`harness.compare.claims`); :mod:`harness.derivation.derive` assembles the same terms into ``M`` and ``V``.
"""

from __future__ import annotations

from dataclasses import dataclass

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


# --------------------------------------------------------------------------- standard bodies by their volume integral
@dataclass(frozen=True)
class Box:
    """A homogeneous cuboid ``x0 ≤ x ≤ x1``, ``y0 ≤ y ≤ y1``, ``z0 ≤ z ≤ z1`` in a body-fixed frame."""

    x: tuple
    y: tuple
    z: tuple

    @staticmethod
    def around(centre, edges) -> "Box":
        """The cuboid with edges ``(a, b, c)`` along x, y, z centred at ``centre``."""
        return Box(*[(sp.sympify(c) - sp.sympify(e) / 2, sp.sympify(c) + sp.sympify(e) / 2)
                     for c, e in zip(centre, edges)])


@dataclass(frozen=True)
class Cylinder:
    """A homogeneous solid cylinder of ``radius`` about the frame's z axis, ``0 ≤ z ≤ length``."""

    radius: object
    length: object


@dataclass(frozen=True)
class Ball:
    """A homogeneous solid ball of ``radius`` centred at the frame's origin."""

    radius: object


def moment_of_inertia(solid, density, axis=(0, 0, 1), about=(0, 0, 0)) -> sp.Expr:
    """``I = ∫ ρ (rᵀ r − (eᵀ r)²) dV`` (3.120) of a homogeneous solid about the axis ``e`` through ``about``: one
    entry of :func:`solid_inertia`, at the cost of one integral."""
    e = sp.Matrix(axis)
    return (e.T * solid_inertia(solid, density, about, entries=[tuple(e)]) * e)[0]


def solid_inertia(solid, density, about=(0, 0, 0), entries=None) -> sp.Matrix:
    """``I = ∫ ρ (rᵀ r E − r rᵀ) dV`` (3.118), (3.120) of a homogeneous solid about the point ``about``, by its
    volume integral in Cartesian, cylindrical or spherical coordinates (3.122), (3.123): independent of the formulas a
    model builds its inertia from. ``entries``: only the diagonal entries of these coordinate axes (others 0)."""
    x, y, z = sp.symbols("x y z", real=True)
    r_, t_, p_ = sp.symbols("r t p", nonnegative=True)
    if isinstance(solid, Box):
        point, jacobian, limits = sp.Matrix([x, y, z]), 1, [(x, *solid.x), (y, *solid.y), (z, *solid.z)]
    elif isinstance(solid, Cylinder):
        point = sp.Matrix([r_ * sp.cos(t_), r_ * sp.sin(t_), z])
        jacobian, limits = r_, [(r_, 0, solid.radius), (t_, 0, 2 * sp.pi), (z, 0, solid.length)]
    elif isinstance(solid, Ball):
        point = sp.Matrix([r_ * sp.sin(t_) * sp.cos(p_), r_ * sp.sin(t_) * sp.sin(p_), r_ * sp.cos(t_)])
        jacobian, limits = r_**2 * sp.sin(t_), [(r_, 0, solid.radius), (t_, 0, sp.pi), (p_, 0, 2 * sp.pi)]
    else:
        raise TypeError(f"no volume integral for {type(solid).__name__}")
    r = point - sp.Matrix(about)
    integrand = sp.sympify(density) * ((r.T * r)[0] * sp.eye(3) - r * r.T) * jacobian
    wanted = None if entries is None else {[tuple(row) for row in sp.eye(3).tolist()].index(tuple(e))
                                           for e in entries}
    return sp.Matrix(3, 3, lambda i, j: _integral(integrand[i, j], limits)
                     if wanted is None or (i == j and i in wanted) else sp.Integer(0))


def _integral(expr, limits) -> sp.Expr:
    """The volume integral of ``expr``, term by term, each term as the product of its one-variable integrals when it
    separates (a product over the three coordinates of the solid: far cheaper than the nested integral)."""
    total = sp.Integer(0)
    variables = [v for v, _, _ in limits]
    for term in sp.Add.make_args(sp.expand(expr)):
        parts = sp.separatevars(term, symbols=variables, dict=True)
        if parts is None:
            total += sp.integrate(term, *limits)
            continue
        product = parts.pop("coeff")
        for v, lo, hi in limits:
            product *= sp.integrate(parts.get(v, sp.Integer(1)), (v, lo, hi))
        total += product
    return sp.simplify(total)


def solid_volume(solid) -> sp.Expr:
    """The volume of a :class:`Box`, :class:`Cylinder` or :class:`Ball` (for its density ``m / V``)."""
    if isinstance(solid, Box):
        return sp.Mul(*[hi - lo for lo, hi in (solid.x, solid.y, solid.z)])
    if isinstance(solid, Cylinder):
        return sp.pi * sp.sympify(solid.radius)**2 * sp.sympify(solid.length)
    return sp.Rational(4, 3) * sp.pi * sp.sympify(solid.radius)**3
