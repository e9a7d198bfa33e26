"""Per-body quantities of chapters 4 and 5, in lecture coordinates ``q``: what the lecture prints body by body
before it sums them (rotation matrices, angular velocities, the inertia tensor in the inertial frame, the
translational and rotational kinetic energy and the potential energy of one body). The printed equations of
these kinds (``R:``, ``S:``, ``omega:``, ``I_0:``, ``T_t:``, ``T_r:``, ``V:``) are compared with them
(:mod:`harness.compare.claims`); :mod:`harness.derivation.derive` assembles the same terms into ``M`` and ``V``.
"""

from __future__ import annotations

import itertools

import numpy as np
import sympy as sp

from harness.derivation.kinematics import link_poses, point_position
from harness.modeling.solids import Ball, Box, Cylinder
from harness.modeling.system import (WORLD, BodyTorque, Damper, JointDamper, JointInput, JointSpring, Point,
                                    PointForce, Spring, System)


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
def moment_of_inertia(solid, density, axis=(0, 0, 1), about=(0, 0, 0)) -> sp.Expr:
    """``I = ∫ ρ (rᵀ r − (eᵀ r)²) dV`` (3.120) of a homogeneous solid about the axis ``e`` through ``about``: one
    entry of :func:`solid_inertia`, at the cost of one integral."""
    e = sp.Matrix(axis)
    return (e.T * solid_inertia(solid, density, about, entries=[tuple(e)]) * e)[0]


def _volume(solid):
    """``(point r(u), Jacobian determinant, limits of u)`` of a solid's volume integral in Cartesian, cylindrical or
    spherical coordinates (3.122), (3.123)."""
    x, y, z = sp.symbols("x y z", real=True)
    r_, t_, p_ = sp.symbols("r t p", nonnegative=True)
    if isinstance(solid, Box):
        return sp.Matrix([x, y, z]), 1, [(x, *solid.x), (y, *solid.y), (z, *solid.z)]
    if isinstance(solid, Cylinder):
        point = sp.Matrix([r_ * sp.cos(t_), r_ * sp.sin(t_), z])
        return point, r_, [(r_, 0, solid.radius), (t_, 0, 2 * sp.pi), (z, 0, solid.length)]
    if isinstance(solid, Ball):
        point = sp.Matrix([r_ * sp.sin(t_) * sp.cos(p_), r_ * sp.sin(t_) * sp.sin(p_), r_ * sp.cos(t_)])
        return point, r_**2 * sp.sin(t_), [(r_, 0, solid.radius), (t_, 0, sp.pi), (p_, 0, 2 * sp.pi)]
    raise TypeError(f"no volume integral for {type(solid).__name__}")


def solid_inertia(solid, density, about=(0, 0, 0), entries=None) -> sp.Matrix:
    """``I = ∫ ρ (rᵀ r E − r rᵀ) dV`` (3.118), (3.120) of a homogeneous solid about the point ``about``, by its
    volume integral (:func:`_volume`): independent of the formulas a model builds its inertia from. ``entries``:
    only the diagonal entries of these coordinate axes (others 0)."""
    point, jacobian, limits = _volume(solid)
    r = point - sp.Matrix(about)
    integrand = sp.sympify(density) * ((r.T * r)[0] * sp.eye(3) - r * r.T) * jacobian
    wanted = None if entries is None else {[tuple(row) for row in sp.eye(3).tolist()].index(tuple(e))
                                           for e in entries}
    return sp.Matrix(3, 3, lambda i, j: _integral(integrand[i, j], limits)
                     if wanted is None or (i == j and i in wanted) else sp.Integer(0))


def solid_mass(solid, density) -> tuple[sp.Expr, sp.Matrix]:
    """``(m, m p_s)``: the mass ``∫ ρ dV`` and the first moment ``∫ ρ r dV`` (the mass times the centre of mass,
    (3.115)) of a homogeneous solid, by their volume integrals."""
    point, jacobian, limits = _volume(solid)
    density = sp.sympify(density)
    return (_integral(density * jacobian, limits),
            sp.Matrix([_integral(density * entry * jacobian, limits) for entry in point]))


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
def acceleration(system: System, p: sp.Matrix) -> sp.Matrix:
    """``p̈ = J q̈ + J̇ q̇`` of a position ``p(q)`` (4.64) differentiated, in ``q, q̇, q̈``."""
    return rate(system, p.jacobian(system.q) * sp.Matrix(system.qd))


def _skew(r: sp.Matrix) -> sp.Matrix:
    return sp.Matrix([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])


def _material_jacobian(system: System, poses, link: str, at: Point) -> sp.Matrix:
    """``∂p/∂θ`` of the material point of ``link`` that is at ``at`` now (a point of any frame): ``δp = δd + δω ×
    (p − d)`` (4.64), in lecture coordinates."""
    pose = poses[_frame(system, link)]
    r = point_position(poses, at) - pose.d
    return _in_q(system, pose.d.jacobian(system.theta) - _skew(r) * pose.J_omega_theta)


def joint_space_balance(system: System) -> sp.Matrix:
    """What the tree joints' constraints must supply, one row per tree joint ``θ``: the momentum rates of every body
    minus the applied forces, projected on the joint's motion (3.104), (3.105), (5.58) —
    ``Σ J_vᵀ (m p̈ − m g e_g) + J_ωᵀ (I_0 ω̇ + ω × I_0 ω) − Σ (applied)`` with the Jacobians taken in ``θ`` —
    in ``q, q̇, q̈``. ``(∂φ/∂q)ᵀ`` of it is ``M q̈ + C q̇ + g − f_np``; a joint coupled by the map carries the
    rest, which :func:`constraint_forces` splits into the constraints' forces."""
    poses, theta = link_poses(system), system.theta
    n = len(theta)
    qd = sp.Matrix(system.qd)
    e_g = sp.Matrix(system.gravity.direction) if system.gravity is not None else sp.zeros(3, 1)
    g = sp.sympify(system.gravity.g) if system.gravity is not None else sp.Integer(0)
    rows = sp.zeros(n, 1)
    for link in system.links:
        if not link.has_mass:
            continue
        m = sp.sympify(link.mass)
        J_v = _material_jacobian(system, poses, link.name, Point(link.name, link.com))
        rows += J_v.T * (m * acceleration(system, centre_of_mass(system, link.name)) - m * g * e_g)
        inertia = link.inertia.matrix
        if any(e != 0 for e in inertia):
            w = angular_velocity(system, link.name)
            w_dot = rate(system, w)
            I_0 = inertia_in_inertial_frame(system, link.name)
            J_w = _in_q(system, poses[link.name].J_omega_theta)
            rows += J_w.T * (I_0 * w_dot + w.cross(I_0 * w))
    J_phi = system.phi.jacobian(system.q)
    theta_dot = J_phi * qd
    for k, joint in enumerate(system.joints):
        if sp.sympify(joint.armature) != 0:
            rows[k] += joint.armature * rate(system, theta_dot[k])
    return rows - _applied_in_theta(system, poses, theta_dot)


def gravity_in_theta(system: System) -> sp.Matrix:
    """The weights' generalized forces on the tree joints, one row per ``θ``: ``Σ J_vᵀ m g e_g`` with the Jacobians
    taken in ``θ`` (the weights' share of the tree's balance (3.104)), in ``q``. ``(∂φ/∂q)ᵀ`` of it is ``−g(q)``;
    where the map constrains the tree, a row may be nonzero where ``g(q)`` is 0: the weights load the constraint
    rows without working on a motion the coordinates allow (a piston's weight on its guide)."""
    rows = sp.zeros(len(system.theta), 1)
    if system.gravity is None:
        return rows
    poses = link_poses(system)
    e_g, g = sp.Matrix(system.gravity.direction), sp.sympify(system.gravity.g)
    for link in system.links:
        if link.has_mass:
            J_v = _material_jacobian(system, poses, link.name, Point(link.name, link.com))
            rows += J_v.T * (sp.sympify(link.mass) * g * e_g)
    return rows


def rate(system: System, expr):
    """``d/dt`` of an expression (or matrix) in ``q, q̇`` along the motion, ``q̈`` as the coordinates' ``accel``
    (the chain rule of (5.69))."""
    pairs = (*zip(system.q, system.qd), *zip(system.qd, [c.accel for c in system.coordinates]))
    if isinstance(expr, sp.MatrixBase):
        return expr.applyfunc(lambda e: rate(system, e))
    return sum((sp.diff(expr, x) * dx for x, dx in pairs), sp.Integer(0))


def load_vector(system: System, load) -> sp.Matrix:
    """The force of a :class:`PointForce` or the torque of a :class:`BodyTorque` in the inertial frame (a follower
    load's components are given in a link's frame: ``R_0^k`` times them)."""
    vector = sp.Matrix(load.force if isinstance(load, PointForce) else load.torque)
    return vector if load.frame == WORLD else rotation_matrix(system, load.frame) * vector


def _applied_in_theta(system: System, poses, theta_dot: sp.Matrix) -> sp.Matrix:
    """The applied forces' generalized forces in the tree joints ``θ`` (5.73), in lecture coordinates: springs and
    dampers ``J_rᵀ f``, external forces and torques ``J_vᵀ f^e``, ``J_ωᵀ τ^e``, and a joint's own spring, damper
    and input in its row. Gravity is in :func:`joint_space_balance`."""
    n = len(system.joints)
    rows = sp.zeros(n, 1)
    index = {j.name: k for k, j in enumerate(system.joints)}
    for f in system.forces:
        if isinstance(f, (Spring, Damper)):
            J_r = (_material_jacobian(system, poses, f.b.link, f.b) if f.b.link != WORLD else sp.zeros(3, n)) - (
                _material_jacobian(system, poses, f.a.link, f.a) if f.a.link != WORLD else sp.zeros(3, n))
            rows += J_r.T * element_force(system, f.name)
        elif isinstance(f, PointForce):
            rows += _material_jacobian(system, poses, f.point.link, f.point).T * load_vector(system, f)
        elif isinstance(f, BodyTorque):
            rows += _in_q(system, poses[f.link].J_omega_theta).T * load_vector(system, f)
        elif isinstance(f, JointSpring):
            k = index[f.joint]
            rows[k] += -sp.sympify(f.stiffness) * (system.phi[k] - sp.sympify(f.rest))
        elif isinstance(f, JointDamper):
            rows[index[f.joint]] += -sp.sympify(f.damping) * theta_dot[index[f.joint]]
        elif isinstance(f, JointInput):
            rows[index[f.joint]] += sp.Symbol(f.input, real=True)
    return rows


def constraint_directions(system: System) -> sp.Matrix:
    """One column per :class:`ConstraintForce`: its generalized force per unit magnitude in the tree joints,
    ``Σ J_vᵀ direction + Σ J_ωᵀ axis`` (5.73), in lecture coordinates."""
    poses = link_poses(system)
    columns = []
    for cf in system.constraint_forces:
        column = sp.zeros(len(system.joints), 1)
        for link, at, direction in cf.forces:
            column += _material_jacobian(system, poses, link, at).T * sp.Matrix(direction)
        for link, axis in cf.torques:
            column += _in_q(system, poses[_frame(system, link)].J_omega_theta).T * sp.Matrix(axis)
        columns.append(column)
    return sp.Matrix.hstack(*columns) if columns else sp.zeros(len(system.joints), 0)


_CONSTRAINT_FORCES: dict = {}


def constraint_forces(system: System) -> dict[str, sp.Expr]:
    """The magnitude ``λ`` of each declared :class:`ConstraintForce`, in ``q, q̇, q̈`` (at the q̈ of the motion: the
    balance holds only there): the tree's balance :func:`joint_space_balance` ``= A λ`` with ``A`` the constraint
    directions (the principle of cutting free, (3.104), in the tree joints). The declaration is checked first: the
    forces do no work on the motions the map allows (``(∂φ/∂q)ᵀ A = 0``, ideal constraints) and there is one per
    constraint (``A`` has rank ``len(θ) − len(q)``), else ValueError naming what is wrong."""
    key = system.fingerprint()
    if key in _CONSTRAINT_FORCES:
        return _CONSTRAINT_FORCES[key]
    from harness.derivation.derive import _simplify

    names = [cf.name for cf in system.constraint_forces]
    needed = len(system.joints) - len(system.coordinates)
    if len(names) != needed:
        raise ValueError(f"{system.name}: {len(system.joints)} tree joints and {len(system.coordinates)} "
                         f"coordinates: declare {needed} constraint force(s) (the map's constraints), not "
                         f"{len(names)}")
    A = constraint_directions(system)
    if names:
        J_phi = system.phi.jacobian(system.q)
        at = {s: 0.3 + 0.17 * k for k, s in enumerate(system.q)}
        at.update({p.symbol: float(p.default) for p in system.parameters})
        A_num = np.array(A.xreplace(at).evalf(), dtype=float)
        work = np.array((J_phi.T * A).xreplace(at).evalf(), dtype=float)
        if np.max(np.abs(work)) > 1e-9 * max(1.0, float(np.max(np.abs(A_num)))):
            raise ValueError(f"{system.name}: the constraint forces {names} do work on the motions the map allows "
                             f"((dphi/dq)^T A = {work.round(6).tolist()} at a generic state): wrong point or direction")
    balance = joint_space_balance(system)
    if names:  # the rows λ is solved from: a regular square block of A, the one with the shortest balance rows
        regular = [list(r) for r in itertools.combinations(range(A_num.shape[0]), len(names))
                   if np.linalg.matrix_rank(A_num[list(r), :], tol=1e-9) == len(names)]
        if not regular:
            raise ValueError(f"{system.name}: the constraint forces {names} are not independent")
        rows = min(regular, key=lambda r: sum(sp.count_ops(balance[k]) for k in r))
    solved = A.extract(rows, list(range(len(names)))).LUsolve(balance.extract(rows, [0])) if names else []
    result = _CONSTRAINT_FORCES[key] = {name: _simplify(value) for name, value in zip(names, solved)}
    return result


def joint_force(system: System, joint: str) -> sp.Matrix:
    """The force the joint ``joint`` exerts on everything it carries, inertial frame, by the momentum balance of that
    subtree cut free (3.104): ``f = Σ m_i p̈_i − Σ m_i g e_g − Σ f^e`` over its bodies and the forces on them from
    outside (point forces, springs and dampers with one end in the subtree, the declared constraint forces of a map
    ``θ = φ(q)`` — a rope, gear or rolling contact — with their magnitudes from :func:`constraint_forces`), in
    ``q, q̇, q̈``."""
    from harness.derivation.derive import _identity_map

    if _identity_map(system) is None and len(system.constraint_forces) != len(system.joints) - len(system.coordinates):
        raise ValueError(f"{system.name}: its joints are coupled by a map theta = phi(q) (a rope, gear or contact) "
                         "whose constraint forces the model does not declare: the cut force of a joint is not the "
                         "tree's")
    cut = system.joint(joint)
    carried = {link.name for link in system.links if cut in system.chain(link.name)}
    force = sp.zeros(3, 1)
    e_g = sp.Matrix(system.gravity.direction) if system.gravity is not None else sp.zeros(3, 1)
    g = sp.sympify(system.gravity.g) if system.gravity is not None else 0
    for link in system.links:
        if link.name in carried and link.has_mass:
            m = sp.sympify(link.mass)
            force += m * acceleration(system, centre_of_mass(system, link.name)) - m * g * e_g
    for element in system.forces:
        if isinstance(element, PointForce) and element.point.link in carried:
            force -= load_vector(system, element)
        elif isinstance(element, (Spring, Damper)):
            a_in, b_in = element.a.link in carried, element.b.link in carried
            if a_in != b_in:  # the element's force on b is f, on a −f (3.84)
                f = element_force(system, element.name)
                force -= f if b_in else -f
    magnitudes = constraint_forces(system) if system.constraint_forces else {}
    for cf in system.constraint_forces:
        for link, _, direction in cf.forces:
            if link in carried:
                force -= magnitudes[cf.name] * sp.Matrix(direction)
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
        vector = load_vector(system, f)
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
