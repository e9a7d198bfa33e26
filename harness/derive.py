"""The equations of motion by the lecture's own procedure (chapter 5).

``M(q)`` (5.21), Christoffel symbols of the first kind (5.95) and ``C(q, q̇)`` (5.97), ``g(q) = ∂V/∂q``
(5.96) with ``V`` from gravity (5.20) and springs, the non-potential generalized forces ``f_q^np``
(5.60), (5.73), the kinetic energy ``T = ½ q̇ᵀ M q̇`` and the map ``theta = phi(q)`` with its Jacobian.
``M`` is never inverted symbolically.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, fields

import sympy as sp

from harness import cache
from harness.kinematics import link_poses, point_position
from harness.model import (BodyTorque, Damper, JointDamper, JointInput, JointSpring, PointForce, Spring,
                           System)



@dataclass
class Derivation:
    """Symbolic quantities of one system, in lecture coordinates ``q``."""

    M: sp.Matrix            # mass matrix (5.21)
    C: sp.Matrix            # Coriolis matrix from Christoffel symbols (5.95), (5.97)
    g: sp.Matrix            # potential forces ∂V/∂q (5.96): gravity and springs
    g_gravity: sp.Matrix    # the gravity part of g
    g_spring: sp.Matrix     # the spring part of g
    f_np: sp.Matrix         # non-potential generalized forces (5.73): dampers + inputs + external
    f_damper: sp.Matrix     # the damper part of f_np
    f_input: sp.Matrix      # the input part of f_np (depends on u)
    T: sp.Expr              # kinetic energy (5.21)
    V: sp.Expr              # potential energy (5.20) + springs
    M_dot: sp.Matrix        # dM/dt, for the skew-symmetry of Ṁ - 2C (Note 5.4)
    phi: sp.Matrix          # theta = phi(q)
    J_phi: sp.Matrix        # ∂phi/∂q
    J_phi_dot: sp.Matrix    # d/dt ∂phi/∂q along q̇
    seconds: float = 0.0    # wall time of the derivation (0 when loaded from the cache)
    from_cache: bool = False

    def christoffel(self, q, i: int, j: int, k: int) -> sp.Expr:
        """Christoffel symbol of the first kind ``c_ijk`` (5.95)."""
        return christoffel(self.M, q, i, j, k)


def christoffel(M: sp.Matrix, q, i: int, j: int, k: int) -> sp.Expr:
    """``c_ijk = ½ (∂M_kj/∂q_i + ∂M_ki/∂q_j − ∂M_ij/∂q_k)`` (5.95)."""
    return (sp.diff(M[k, j], q[i]) + sp.diff(M[k, i], q[j]) - sp.diff(M[i, j], q[k])) / 2


def coriolis_matrix(M: sp.Matrix, q, qd) -> sp.Matrix:
    """``C_kj = Σ_i c_ijk q̇_i`` (5.97)."""
    n = len(q)
    return sp.Matrix(n, n, lambda k, j: _simplify(sum(christoffel(M, q, i, j, k) * qd[i] for i in range(n))))


# Simplification only makes expressions readable and smaller to compile; it never changes their value.
# trigsimp grows super-linearly with expression size (a closed chain's arccos map took minutes), so
# expressions above this many operations are left as derived.
SIMPLIFY_MAX_OPS = 150


def _simplify(expr):
    if sp.count_ops(expr) > SIMPLIFY_MAX_OPS:
        return expr
    expr = sp.expand(expr)
    if expr.has(sp.sin, sp.cos) and sp.count_ops(expr) <= SIMPLIFY_MAX_OPS:
        expr = sp.trigsimp(expr)
    return sp.factor_terms(expr)


def _simplify_matrix(m: sp.Matrix) -> sp.Matrix:
    return m.applyfunc(_simplify)


def time_derivative(expr, q, qd):
    """d/dt of an expression in ``q`` along ``q̇`` (chain rule)."""
    return sum(sp.diff(expr, qi) * qdi for qi, qdi in zip(q, qd))


def derive_uncached(system: System) -> Derivation:
    start = time.perf_counter()
    q, qd = system.q, system.qd
    n = len(q)
    phi = system.phi
    to_q = dict(zip(system.theta, phi))
    J_phi = phi.jacobian(q)
    J_phi_dot = _simplify_matrix(J_phi.applyfunc(lambda e: time_derivative(e, q, qd)))
    poses = link_poses(system)

    def in_q(expr):
        return expr.xreplace(to_q)

    def rotation_q(link):
        return in_q(poses[link].R)

    # (5.21): M = Σ m J_vᵀ J_v + J_ωᵀ R I Rᵀ J_ω, with J_ω = J_ω,θ ∂φ/∂q. The rotational part is
    # evaluated as (Rᵀ J_ω)ᵀ I (Rᵀ J_ω), the same product (5.15) grouped to keep expressions small.
    M = sp.zeros(n, n)
    V_gravity = sp.Integer(0)
    for link in system.links:
        if not link.has_mass:
            continue
        pose = poses[link.name]
        p_s = in_q(pose.R * link.com_vector + pose.d)
        J_v = p_s.jacobian(q)
        M += sp.sympify(link.mass) * J_v.T * J_v
        if not link.inertia.matrix.is_zero_matrix:
            J_w_body = _simplify_matrix(in_q(pose.R.T * pose.J_omega_theta) * J_phi)
            M += J_w_body.T * link.inertia.matrix * J_w_body
        if system.gravity is not None:
            e_g = sp.Matrix(system.gravity.direction)
            V_gravity += -sp.sympify(link.mass) * sp.sympify(system.gravity.g) * (e_g.T * p_s)[0]  # (5.20)
    for k, joint in enumerate(system.joints):  # armature: I_a theta_dot_k² / 2 in T
        if sp.sympify(joint.armature) != 0:
            row = J_phi[k, :]
            M += sp.sympify(joint.armature) * row.T * row
    M = _simplify_matrix(M)

    V_spring = sp.Integer(0)
    f_damper = sp.zeros(n, 1)
    f_input = sp.zeros(n, 1)
    for element in system.forces:
        if isinstance(element, Spring):
            length = _distance(poses, element.a, element.b, in_q)
            V_spring += sp.sympify(element.stiffness) * (length - sp.sympify(element.rest_length)) ** 2 / 2
        elif isinstance(element, Damper):
            # axial force -d L̇ r/L on b; its generalized force (5.73) is -d L̇ ∂L/∂q, and with the
            # squared length S = L²: ∂L/∂q = ∂S/∂q / (2L), L̇ = ∂S/∂q q̇ / (2L)
            squared = _distance(poses, element.a, element.b, in_q) ** 2
            grad = sp.Matrix([squared]).jacobian(q)
            f_damper += -sp.sympify(element.damping) * (grad * sp.Matrix(qd))[0] / (4 * squared) * grad.T
        elif isinstance(element, JointSpring):
            theta = phi[system.joints.index(system.joint(element.joint))]
            V_spring += sp.sympify(element.stiffness) * (theta - sp.sympify(element.rest)) ** 2 / 2
        elif isinstance(element, JointDamper):
            row = J_phi[system.joints.index(system.joint(element.joint)), :]
            f_damper += -sp.sympify(element.damping) * (row * sp.Matrix(qd))[0] * row.T
        elif isinstance(element, JointInput):
            row = J_phi[system.joints.index(system.joint(element.joint)), :]
            f_input += sp.Symbol(element.input, real=True) * row.T
        elif isinstance(element, PointForce):
            p = in_q(point_position(poses, element.point))
            force = sp.Matrix(element.force)
            if element.frame != "world":
                force = rotation_q(element.frame) * force  # follower force, body components
            f_input += p.jacobian(q).T * force  # (5.73)
        elif isinstance(element, BodyTorque):
            J_w = in_q(poses[element.link].J_omega_theta) * J_phi
            torque = sp.Matrix(element.torque)
            if element.frame != "world":
                torque = rotation_q(element.frame) * torque
            f_input += J_w.T * torque  # (5.73)
    V = V_gravity + V_spring
    g_gravity = _simplify_matrix(sp.Matrix([V_gravity]).jacobian(q).T)  # (5.96)
    g_spring = _simplify_matrix(sp.Matrix([V_spring]).jacobian(q).T)
    C = coriolis_matrix(M, q, qd)
    qd_vec = sp.Matrix(qd)
    T = (qd_vec.T * M * qd_vec)[0] / 2
    M_dot = _simplify_matrix(M.applyfunc(lambda e: time_derivative(e, q, qd)))
    return Derivation(M=M, C=C, g=g_gravity + g_spring, g_gravity=g_gravity, g_spring=g_spring,
                      f_np=f_damper + f_input, f_damper=f_damper, f_input=f_input, T=T, V=V,
                      M_dot=M_dot, phi=phi, J_phi=J_phi, J_phi_dot=J_phi_dot,
                      seconds=time.perf_counter() - start)


def _distance(poses, a, b, in_q) -> sp.Expr:
    r = in_q(point_position(poses, b) - point_position(poses, a))
    return sp.sqrt(_simplify((r.T * r)[0]))


SYMBOLIC_FIELDS = [f.name for f in fields(Derivation) if f.name not in ("seconds", "from_cache")]


def derive(system: System, use_cache: bool = True) -> Derivation:
    """Derive (or load from the on-disk cache keyed by the model's fingerprint)."""
    key = f"{system.name}-{system.fingerprint()}-{cache.code_version()}"
    if use_cache:
        stored = cache.load(key)
        if stored is not None and sorted(stored) == sorted(SYMBOLIC_FIELDS):
            return Derivation(**stored, from_cache=True)
    derivation = derive_uncached(system)
    if use_cache:
        cache.store(key, {name: getattr(derivation, name) for name in SYMBOLIC_FIELDS})
    return derivation
