"""Per-body quantities of chapters 4 and 5, in lecture coordinates ``q``: what the lecture prints body by body
before it sums them (rotation matrices, angular velocities, the inertia tensor in the inertial frame, the
translational and rotational kinetic energy and the potential energy of one body). The printed equations of
these kinds (``R:``, ``S:``, ``omega:``, ``I_0:``, ``T_t:``, ``T_r:``, ``V:``) are compared with them
(:mod:`harness.compare.claims`); :mod:`harness.derivation.derive` assembles the same terms into ``M`` and ``V``.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from harness.derivation.kinematics import link_poses, point_position
from harness.modeling.system import (WORLD, BodyTorque, Damper, JointDamper, JointInput, Point, PointForce, Spring,
                                    System)


def _in_q(system: System, expr):
    return expr.xreplace(dict(zip(system.theta, system.phi)))


def _frame(system: System, name: str) -> str:
    """``name`` when it is a link of ``system`` or the world (a frame :func:`link_poses` has), else ModelError."""
    if name != WORLD:
        system.link(name)
    return name


def rotation_matrix(system: System, link: str, relative_to: str = WORLD) -> sp.Matrix:
    """``R_a^b = (R_0^a)ᵀ R_0^b`` (4.9)–(4.21): the orientation of ``link``'s frame in ``relative_to``'s frame
    (the inertial frame by default)."""
    poses = link_poses(system)
    return _in_q(system, poses[_frame(system, relative_to)].R.T * poses[_frame(system, link)].R)


def angular_velocity_matrix(system: System, link: str, relative_to: str = WORLD) -> sp.Matrix:
    """``S_a^b = Ṙ_a^b (R_a^b)ᵀ`` (4.44): the skew-symmetric matrix of the angular velocity of ``link``
    relative to ``relative_to``, in ``relative_to``'s frame."""
    R = rotation_matrix(system, link, relative_to)
    R_dot = R.applyfunc(lambda e: (sp.Matrix([e]).jacobian(system.q) * sp.Matrix(system.qd))[0])
    return R_dot * R.T


def rotational_jacobian(system: System, link: str) -> sp.Matrix:
    """``(J_ω)_0^k`` (4.62) of ``link`` in the inertial frame and lecture coordinates: ``J_ω,θ ∂φ/∂q``."""
    pose = link_poses(system)[_frame(system, link)]
    return _in_q(system, pose.J_omega_theta) * system.phi.jacobian(system.q)


def angular_velocity(system: System, link: str) -> sp.Matrix:
    """``ω_0^k = J_ω q̇`` (4.57), (4.62): the angular velocity of ``link`` in the inertial frame."""
    return rotational_jacobian(system, link) * sp.Matrix(system.qd)


def point_in_q(system: System, point: Point) -> sp.Matrix:
    """``p_0 = R_0^k p_k + d_0^k`` (4.21) of a body-fixed point, in lecture coordinates."""
    return _in_q(system, point_position(link_poses(system), point))


def centre_of_mass(system: System, link: str) -> sp.Matrix:
    """``p_0^s = R_0^k p_k^s + d_0^k`` (4.21) of ``link``'s centre of mass."""
    return point_in_q(system, Point(link, system.link(link).com))


def inertia_in_inertial_frame(system: System, link: str) -> sp.Matrix:
    """``I_0^s = R_0^k I_k^s (R_0^k)ᵀ`` (5.15): the inertia tensor about the centre of mass, inertial frame."""
    R = rotation_matrix(system, link)
    return R * system.link(link).inertia.matrix * R.T


def translational_energy(system: System, link: str) -> sp.Expr:
    """``T_t = ½ m (ṗ_0^s)ᵀ ṗ_0^s`` (5.6) of one body."""
    v = centre_of_mass(system, link).jacobian(system.q) * sp.Matrix(system.qd)
    return sp.sympify(system.link(link).mass) * (v.T * v)[0] / 2


def rotational_energy(system: System, link: str) -> sp.Expr:
    """``T_r = ½ (ω_0)ᵀ I_0^s ω_0`` (5.12) of one body."""
    w = angular_velocity(system, link)
    return (w.T * inertia_in_inertial_frame(system, link) * w)[0] / 2


def gravity_potential(system: System, link: str) -> sp.Expr:
    """``V = −m g e_gᵀ p_0^s`` (5.20) of one body (zero at the inertial origin's level)."""
    if system.gravity is None:
        return sp.Integer(0)
    e_g = sp.Matrix(system.gravity.direction)
    mass = sp.sympify(system.link(link).mass)
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


# --------------------------------------------------------------------------- cut forces
def joint_force(system: System, joint: str) -> sp.Matrix:
    """The force the joint ``joint`` exerts on everything it carries, inertial frame, by the momentum balance of that
    subtree cut free (3.104): ``f = Σ m_i p̈_i − Σ m_i g e_g − Σ f^e`` over its bodies and the external forces on them
    (point forces, springs and dampers with one end in the subtree), in ``q, q̇, q̈``. Only for a tree whose joint
    coordinates are the lecture's coordinates: a map ``θ = φ(q)`` stands for a rope, gear or rolling contact whose
    forces the tree does not carry."""
    from harness.derivation.derive import _identity_map

    if _identity_map(system) is None:
        raise ValueError(f"{system.name}: its joints are coupled by a map theta = phi(q) (a rope, gear or contact): "
                         "the cut force of a joint is not the tree's")
    cut = system.joint(joint)
    carried = {link.name for link in system.links if cut in system.chain(link.name)}
    q, qd = system.q, sp.Matrix(system.qd)
    qdd = sp.Matrix([c.accel for c in system.coordinates])

    def acceleration(p):
        J = p.jacobian(q)
        return (J * qd).jacobian(q) * qd + J * qdd

    force = sp.zeros(3, 1)
    e_g = sp.Matrix(system.gravity.direction) if system.gravity is not None else sp.zeros(3, 1)
    g = sp.sympify(system.gravity.g) if system.gravity is not None else 0
    for link in system.links:
        if link.name in carried and link.has_mass:
            m = sp.sympify(link.mass)
            force += m * acceleration(centre_of_mass(system, link.name)) - m * g * e_g
    for element in system.forces:
        if isinstance(element, PointForce) and element.point.link in carried:
            vector = sp.Matrix(element.force)
            if element.frame != WORLD:
                vector = rotation_matrix(system, element.frame) * vector
            force -= vector
        elif isinstance(element, (Spring, Damper)):
            a_in, b_in = element.a.link in carried, element.b.link in carried
            if a_in != b_in:  # the element's force on b is f, on a −f (3.84)
                f = element_force(system, element.name)
                force -= f if b_in else -f
    return _in_q(system, force)


# --------------------------------------------------------------------------- force elements
def element_force(system: System, name: str) -> sp.Matrix:
    """The force vector the spring or damper ``name`` exerts on its point ``b``, in the inertial frame and lecture
    coordinates, along ``r = p_b − p_a`` (``l = |r|``): a spring ``−c (l − l_0) r/l`` (3.84), a damper
    ``−d l̇ r/l`` with ``l̇ = rᵀ ṙ / l`` (an element acts along its line)."""
    element = point_element(system, name)
    r, length = element_vector(system, element)
    if isinstance(element, Spring):
        return -element.stiffness * (length - element.rest_length) * r / length
    r_dot = r.jacobian(system.q) * sp.Matrix(system.qd)
    return -element.damping * (r.T * r_dot)[0] / length * r / length


def element_generalized_force(system: System, name: str, force=None) -> sp.Matrix:
    """The generalized force of the force element ``name`` (5.58), (5.73): of a spring or damper ``J_rᵀ f`` with
    ``J_r = ∂r/∂q`` and ``f`` its force on ``b`` (:func:`element_force`; ``force``: another force vector, e.g. a
    printed one); of an external force ``J_vᵀ f^e`` at its point, of an external torque ``J_ωᵀ τ^e``."""
    external = _external(system, name)
    if external is not None:
        return external
    element = point_element(system, name)
    r, _ = element_vector(system, element)
    f = element_force(system, name) if force is None else sp.Matrix(force)
    return r.jacobian(system.q).T * f


def _external(system: System, name: str):
    """(5.73) for the external force or torque ``name``, or the input or viscous friction of a tree joint (a torque
    pair on the two links it joins: ``J_φᵀ`` of that joint's row, (5.111)); None when ``name`` is no such element."""
    for f in system.forces:
        if getattr(f, "name", None) == name and isinstance(f, (JointInput, JointDamper)):
            k = [j.name for j in system.joints].index(f.joint)
            row = system.phi.jacobian(system.q)[k, :]
            if isinstance(f, JointInput):
                return sp.Symbol(f.input, real=True) * row.T
            return -sp.sympify(f.damping) * (row * sp.Matrix(system.qd))[0] * row.T
    for f in system.forces:
        if getattr(f, "name", None) != name or not isinstance(f, (PointForce, BodyTorque)):
            continue
        vector = sp.Matrix(f.force if isinstance(f, PointForce) else f.torque)
        if f.frame != WORLD:  # follower: components in a link's frame
            vector = rotation_matrix(system, f.frame) * vector
        if isinstance(f, PointForce):
            return point_in_q(system, f.point).jacobian(system.q).T * vector
        return rotational_jacobian(system, f.link).T * vector
    return None


def point_element(system: System, name: str):
    """The spring or damper ``name`` of ``system`` (a force claim's element)."""
    for f in system.forces:
        if isinstance(f, (Spring, Damper)) and f.name == name:
            return f
    raise ValueError(f"{system.name}: no spring or damper named {name!r} for a force claim")


def element_vector(system: System, element) -> tuple[sp.Matrix, sp.Expr]:
    """``r = p_b − p_a`` of a spring or damper in lecture coordinates, and its length ``|r|``."""
    r = point_in_q(system, element.b) - point_in_q(system, element.a)
    return r, sp.sqrt((r.T * r)[0])
