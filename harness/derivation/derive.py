"""The equations of motion by the lecture's own procedure (chapter 5).

``M(q)`` (5.21), Christoffel symbols of the first kind (5.95) and ``C(q, q̇)`` (5.97), ``g(q) = ∂V/∂q``
(5.96) with ``V`` from gravity (5.20) and springs, the non-potential generalized forces ``f_q^np``
(5.60), (5.73), the kinetic energy ``T = ½ q̇ᵀ M q̇`` and the map ``theta = phi(q)`` with its Jacobian.
``M`` is never inverted symbolically.
"""

from __future__ import annotations

import functools
import time
from dataclasses import dataclass, field, fields

import sympy as sp

from harness.derivation import cache
from harness.derivation.kinematics import link_poses, point_position, rotation, rpy_rotation, skew
from harness.modeling.system import (BodyTorque, Damper, JointDamper, JointInput, JointSpring, PointForce, Spring,
                           System)



@dataclass
class Derivation:
    """Symbolic quantities of one system, in lecture coordinates ``q``."""

    M: sp.Matrix            # mass matrix (5.21)
    C: sp.Matrix            # Coriolis matrix from Christoffel symbols (5.95), (5.97)
    g: sp.Matrix            # potential forces ∂V/∂q (5.96): gravity and springs
    g_gravity: sp.Matrix    # the gravity part of g
    g_spring: sp.Matrix     # the spring part of g
    g_spring_terms: sp.Matrix  # the size of the terms whose difference g_spring is: its round-off's scale
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
    graph: cache.Graph | None = field(default=None, repr=False, compare=False)  # a per-body derivation's stored
    # form: the same quantities in the symbols of their common subexpressions, as the compiler takes them

    def christoffel(self, q, i: int, j: int, k: int) -> sp.Expr:
        """Christoffel symbol of the first kind ``c_ijk`` (5.95)."""
        return christoffel(self.M, q, i, j, k)

    @classmethod
    def stored(cls, trees, graph: cache.Graph, seconds: float = 0.0, from_cache: bool = True) -> "Derivation":
        """A derivation read from the cache as a graph: each quantity's tree is built from ``trees``
        (:class:`~harness.derivation.cache.Trees`) when first read; the compiler takes ``graph``."""
        self = cls.__new__(cls)
        self.__dict__.update(seconds=seconds, from_cache=from_cache, graph=graph, _trees=trees)
        return self

    def __getattr__(self, name: str):
        """A quantity of a :meth:`stored` derivation not read before (called only for an attribute not set)."""
        trees = self.__dict__.get("_trees")
        if trees is None or name not in trees:
            raise AttributeError(name)
        value = trees[name]
        setattr(self, name, value)
        return value

    def __getstate__(self) -> dict:  # every tree built: a stored graph's compiled texts do not pickle
        return {name: getattr(self, name) for name in (f.name for f in fields(self))}


def christoffel(M: sp.Matrix, q, i: int, j: int, k: int) -> sp.Expr:
    """``c_ijk = ½ (∂M_kj/∂q_i + ∂M_ki/∂q_j − ∂M_ij/∂q_k)`` (5.95)."""
    return (sp.diff(M[k, j], q[i]) + sp.diff(M[k, i], q[j]) - sp.diff(M[i, j], q[k])) / 2


def coriolis_matrix(M: sp.Matrix, q, qd) -> sp.Matrix:
    """``C_kj = Σ_i c_ijk q̇_i`` (5.97)."""
    n = len(q)
    return sp.Matrix(n, n, lambda k, j: _simplify(sum(christoffel(M, q, i, j, k) * qd[i] for i in range(n))))


# Simplification only makes expressions readable and smaller to compile; it never changes their value (their
# round-off it can: expanding a difference of large terms forms the cancellation symbolically, see _difference).
# trigsimp grows super-linearly with expression size (a closed chain's arccos map took minutes), so
# expressions above this many operations are left as derived.
SIMPLIFY_MAX_OPS = 150


@functools.lru_cache(maxsize=16384)
def _simplify(expr):
    """``expr`` expanded, trigsimp'd and its common factors taken out (as derived when too large). Remembered per
    process: a scene's pruned and idle variants of a system derive mostly the same expressions again (the same
    ``M`` and Christoffel sums), and the same input gives the same output."""
    if sp.count_ops(expr) > SIMPLIFY_MAX_OPS:
        return expr
    expr = sp.expand(expr)
    if expr.has(sp.sin, sp.cos) and sp.count_ops(expr) <= SIMPLIFY_MAX_OPS:
        expr = sp.trigsimp(expr)
    return sp.factor_terms(expr)


def _simplify_matrix(m: sp.Matrix) -> sp.Matrix:
    return m.applyfunc(_simplify)


def quadratic_form(M: sp.Matrix, v) -> sp.Expr:
    """``vᵀ M v`` as the sums ``Σ_j (Σ_i v_i M_ij) v_j`` that ``v.T * M * v`` forms, without SymPy's matrix product:
    its inner loop tests every entry with ``0 * M_ij == 0`` (an infinite entry would make ``nan``), which asks the
    assumptions of the whole expression tree. On a per-body derivation (a small graph, a huge tree) that test walks
    the tree: 51 of the 55 s of the 6-DoF so101 arm's derivation (measured). Our entries are finite, the sums are the
    same expressions."""
    n = len(v)
    return sp.Add(*[sp.Add(*[v[i] * M[i, j] for i in range(n) if M[i, j] != 0]) * v[j] for j in range(n)])


def matrix_vector(A: sp.Matrix, v) -> list:
    """The entries of ``A v`` as the sums ``Σ_j A_ij v_j`` that ``A * v`` forms (without the test of
    :func:`quadratic_form`)."""
    return [sp.Add(*[A[i, j] * v[j] for j in range(A.cols) if A[i, j] != 0]) for i in range(A.rows)]


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
    identity = _identity_map(system) if n >= PER_BODY_MIN_DOF else None
    per_body = _per_body(system, identity, poses) if identity is not None else None
    M = sp.zeros(n, n)
    V_gravity = sp.Integer(0)
    for link in (system.links if per_body is None else ()):
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
    for k, joint in enumerate(system.joints if per_body is None else ()):  # armature: I_a theta_dot_k² / 2 in T
        if sp.sympify(joint.armature) != 0:
            row = J_phi[k, :]
            M += sp.sympify(joint.armature) * row.T * row
    M = _simplify_matrix(M) if per_body is None else per_body[0]
    if per_body is not None:
        V_gravity = per_body[3]

    V_spring = sp.Integer(0)
    V_joint_springs = sp.Integer(0)
    g_point_springs = sp.zeros(n, 1)
    g_spring_terms = sp.zeros(n, 1)
    f_damper = sp.zeros(n, 1)
    f_input = sp.zeros(n, 1)
    for element in system.forces:
        if isinstance(element, Spring):
            # ∂V/∂q of V = c/2 (L − l0)², L = |r|, r = p_b − p_a: c (L − l0)/L J_rᵀ r, J_r = ∂r/∂q, formed
            # from r as the engines form it (see _difference); not the expanded ∂V/∂q, whose L² is a sum
            # of terms of size |p_a|², |p_b|² that cancel to L²
            r, J_r, length = _difference(poses, element.a, element.b, in_q, q)
            rest = sp.sympify(element.rest_length)
            V_spring += sp.sympify(element.stiffness) * (length - rest) ** 2 / 2
            g_point_springs += sp.sympify(element.stiffness) * (1 - rest / length) * (J_r.T * r)
            # c J_rᵀ r and c l0 / L J_rᵀ r cancel where L ≈ l0: their size, not the force's, is what round-off
            # is relative to (each product of J_rᵀ r by the sizes of its factors)
            g_spring_terms += (sp.Abs(sp.sympify(element.stiffness)) * (1 + sp.Abs(rest) / length)
                               * (J_r.applyfunc(sp.Abs).T * r.applyfunc(sp.Abs)))
        elif isinstance(element, Damper):
            # axial force -d L̇ r/L on b; its generalized force (5.73) is -d L̇ ∂L/∂q with ∂L/∂q = J_rᵀ r / L,
            # L̇ = rᵀ J_r q̇ / L (r, J_r and L as for a spring)
            r, J_r, length = _difference(poses, element.a, element.b, in_q, q)
            f_damper += -sp.sympify(element.damping) * (r.T * J_r * sp.Matrix(qd))[0] / length ** 2 * (J_r.T * r)
        elif isinstance(element, JointSpring):
            theta = phi[system.joints.index(system.joint(element.joint))]
            V_joint = sp.sympify(element.stiffness) * (theta - sp.sympify(element.rest)) ** 2 / 2
            V_spring += V_joint
            V_joint_springs += V_joint
            # k (θ − θ0) ∂θ/∂q: k θ and k θ0 cancel where θ ≈ θ0
            row = J_phi[system.joints.index(system.joint(element.joint)), :]
            g_spring_terms += (sp.Abs(sp.sympify(element.stiffness)) * (sp.Abs(theta) + sp.Abs(sp.sympify(element.rest)))
                               * row.applyfunc(sp.Abs).T)
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
    g_gravity = _simplify_matrix(sp.Matrix([V_gravity]).jacobian(q).T) if per_body is None else per_body[4]  # (5.96)
    g_spring = g_point_springs + _simplify_matrix(sp.Matrix([V_joint_springs]).jacobian(q).T)
    C = coriolis_matrix(M, q, qd) if per_body is None else per_body[1]
    T = quadratic_form(M, qd) / 2
    M_dot = _simplify_matrix(M.applyfunc(lambda e: time_derivative(e, q, qd))) if per_body is None else per_body[2]
    return Derivation(M=M, C=C, g=g_gravity + g_spring, g_gravity=g_gravity, g_spring=g_spring,
                      g_spring_terms=g_spring_terms,
                      f_np=f_damper + f_input, f_damper=f_damper, f_input=f_input, T=T, V=V,
                      M_dot=M_dot, phi=phi, J_phi=J_phi, J_phi_dot=J_phi_dot,
                      seconds=time.perf_counter() - start)


# --------------------------------------------------------------------------- large trees: body by body
# Differentiating the assembled M costs n³ derivatives of its largest expressions: for the 7-DoF arm of
# models/lightweight_robot.py that did not finish within 15 minutes (measured). From this many degrees of
# freedom on, a tree whose map θ = φ(q) is the identity gets M, the Christoffel C, Ṁ and V_gravity body by body
# from the Jacobians and their time derivatives (:func:`_per_body`); every system with fewer degrees of
# freedom is derived exactly as before (the largest other system has 5).
PER_BODY_MIN_DOF = 6


def is_per_body(system: System) -> bool:
    """Whether ``system`` is derived body by body (:func:`_per_body`); such a derivation is cached as a graph."""
    return len(system.q) >= PER_BODY_MIN_DOF and _identity_map(system) is not None


GRAPH_MIN_NODES = 50_000
"""A derivation whose trees have more nodes than this together is cached as a graph too (:func:`as_graph`): the
catalogue's largest not derived body by body has 3546 (the trebuchet); a user's four-bar linkage, its closed chain a
closed-form map of nested ``atan2`` and ``arccos``, 327 543 (its C alone 1.7 MB of ``srepr``): reading that back
took 7 CPU s at every run and compiling it 5 s, where as a graph it is 26 kB, read in 0.01 s."""


def as_graph(system: System, derivation) -> bool:
    """Whether ``derivation`` of ``system`` is cached (and compiled) as a graph: a per-body derivation, or one
    whose trees are larger than :data:`GRAPH_MIN_NODES` (counted until that is passed)."""
    if is_per_body(system):
        return True
    nodes = 0
    for name in SYMBOLIC_FIELDS:
        for _ in sp.preorder_traversal(getattr(derivation, name)):
            nodes += 1
            if nodes > GRAPH_MIN_NODES:
                return True
    return False


def _identity_map(system: System) -> dict | None:
    """``{theta_j: (q_k, q̇_k)}`` when every tree joint's coordinate is a distinct lecture coordinate, else None."""
    rates = dict(zip(system.q, system.qd))
    out = {}
    for joint, expr in zip(system.joints, system.phi):
        if expr not in rates or expr in {pair[0] for pair in out.values()}:
            return None
        out[joint.theta] = (expr, rates[expr])
    return out if len(out) == len(system.q) else None


def _per_body(system: System, identity: dict, poses) -> tuple:
    """``(M, C, Ṁ, V_gravity, g_gravity)``: (5.21), the Christoffel ``C`` (5.95), (5.97), ``Ṁ``, (5.20) and
    ``g = ∂V/∂q`` (5.96) as ``−Σ m g J_vᵀ e_g``, body by body.

    For a body with centre of mass ``p`` (world components), ``J_v = ∂p/∂q`` and the body-frame angular
    Jacobian ``J_ω`` (``ω = J_ω q̇`` in body components), the Christoffel symbols (5.95) of
    ``M = m J_vᵀ J_v + J_ωᵀ I J_ω`` sum to (with ``∂_i J_v,k = ∂_k J_v,i`` and the body-frame identity
    ``∂_i J_ω,k − ∂_k J_ω,i = J_ω,k × J_ω,i`` that follows from ``∂_k R = R S(J_ω,k)``)::

        C = m J_vᵀ J̇_v + J_ωᵀ (I J̇_ω + ½ (I S(ω) + S(ω) I − S(I ω)) J_ω)

    — the matrix (5.97), without differentiating ``M``. The Jacobians follow the chain (4.21): a revolute joint
    ``l`` with world axis ``z_l`` at ``o_l`` gives ``J_v,l = z_l × (p − o_l)``,
    ``J̇_v,l = (ω_l⁻ × z_l) × (p − o_l) + z_l × (ω_l⁻ × (p − o_l) + Σ_{m≥l} J_v,m q̇_m)`` (``ω_l⁻``: angular velocity
    before the joint), ``J_ω,l = (R_l^k)ᵀ a_l``, ``J̇_ω,l = J_ω,l × Σ_{m>l} J_ω,m q̇_m``; a prismatic joint gives
    ``J_v,l = z_l``, ``J̇_v,l = ω_l⁻ × z_l`` and no ``J_ω`` column. Nothing is expanded: every quantity is a product
    of the previous link's quantities, so the expressions share their sub-expressions (a small graph, a large
    tree) and only graph-aware operations may touch them: the compiler's common-subexpression elimination
    does; ``srepr``, ``count_ops``, ``expand``, ``diff`` would walk the tree (see :func:`derive`).
    """
    q, n = system.q, len(system.q)
    to_q = {theta: pair[0] for theta, pair in identity.items()}
    column = {j.name: q.index(identity[j.theta][0]) for j in system.joints}
    rate = {j.name: identity[j.theta][1] for j in system.joints}
    R = {name: pose.R.xreplace(to_q) for name, pose in poses.items()}
    d = {name: pose.d.xreplace(to_q) for name, pose in poses.items()}
    z = {j.name: R[j.child] * j.axis_vector for j in system.joints}
    M, C, M_dot = sp.zeros(n, n), sp.zeros(n, n), sp.zeros(n, n)
    V_gravity, g_gravity = sp.Integer(0), sp.zeros(n, 1)
    for link in system.links:
        if not link.has_mass:
            continue
        chain = system.chain(link.name)
        p = R[link.name] * link.com_vector + d[link.name]
        J_v, J_v_dot = sp.zeros(3, n), sp.zeros(3, n)
        for joint in chain:
            J_v[:, column[joint.name]] = z[joint.name].cross(p - d[joint.child]) if joint.type == "revolute" \
                else z[joint.name]
        omega = sp.zeros(3, 1)  # world angular velocity before the joint, ω_l⁻
        for l, joint in enumerate(chain):
            k, z_l = column[joint.name], z[joint.name]
            if joint.type == "revolute":
                r = p - d[joint.child]
                relative = omega.cross(r) + sum((J_v[:, column[m.name]] * rate[m.name] for m in chain[l:]),
                                                sp.zeros(3, 1))  # ṗ − ȯ_l
                J_v_dot[:, k] = omega.cross(z_l).cross(r) + z_l.cross(relative)
                omega = omega + z_l * rate[joint.name]
            else:
                J_v_dot[:, k] = omega.cross(z_l)
        mass = sp.sympify(link.mass)
        M += mass * J_v.T * J_v
        C += mass * J_v.T * J_v_dot
        M_dot += mass * (J_v_dot.T * J_v + J_v.T * J_v_dot)
        if system.gravity is not None:
            e_g = sp.Matrix(system.gravity.direction)
            V_gravity += -mass * sp.sympify(system.gravity.g) * (e_g.T * p)[0]  # (5.20)
            g_gravity += -mass * sp.sympify(system.gravity.g) * J_v.T * e_g    # (5.96), ∂p/∂q = J_v
        if link.inertia.matrix.is_zero_matrix:
            continue
        J_w, J_w_dot = sp.zeros(3, n), sp.zeros(3, n)
        later = sp.eye(3)        # R_l^k: from the frame after joint l to the link frame, built backwards
        after = sp.zeros(3, 1)   # Σ_{m>l} J_ω,m q̇_m; at the end ω in body components
        for joint in reversed(chain):
            if joint.type == "revolute":
                k = column[joint.name]
                J_w[:, k] = later.T * joint.axis_vector
                J_w_dot[:, k] = J_w[:, k].cross(after)
                after = after + J_w[:, k] * rate[joint.name]
                later = rpy_rotation(joint.rpy) * rotation(joint.axis, to_q[joint.theta]) * later
            else:
                later = rpy_rotation(joint.rpy) * later
        I, w = link.inertia.matrix, after
        M += J_w.T * I * J_w
        C += J_w.T * (I * J_w_dot + (I * skew(w) + skew(w) * I - skew(I * w)) * J_w / 2)
        M_dot += J_w_dot.T * I * J_w + J_w.T * I * J_w_dot
    for joint in system.joints:  # armature: a constant I_a in M[k, k], nothing in C
        if sp.sympify(joint.armature) != 0:
            M[column[joint.name], column[joint.name]] += sp.sympify(joint.armature)
    return M, C, M_dot, V_gravity, g_gravity


def _difference(poses, a, b, in_q, q) -> tuple[sp.Matrix, sp.Matrix, sp.Expr]:
    """``r = p_b − p_a``, ``J_r = ∂r/∂q`` and ``L = |r|`` of a spring or damper between points ``a`` and ``b``.

    Each component of ``r`` and ``J_r`` is simplified on its own (its terms are of the size of the positions
    ``|p_a|``, ``|p_b|``, as where an engine subtracts two world positions), and ``L = sqrt(r_x² + r_y² + r_z²)`` is
    kept a sum of squares. Simplifying (expanding) ``rᵀ r`` as one expression would form ``L²`` from terms of
    size ``|p_a|²``, ``|p_b|²`` that cancel: a relative error of ``ε (|p_a| + |p_b|)² / L²`` in ``L``, amplified once
    more by ``L / |L − l0|`` in the spring force ``c (L − l0)`` (measured: 3.9e-13 of ``g_spring`` of
    models/rotating_body.py, a 0.075 m spring 1.05 m from the bearing, where both engines agree with an exact
    evaluation to 6e-15)."""
    r = _simplify_matrix(in_q(point_position(poses, b) - point_position(poses, a)))
    J_r = _simplify_matrix(r.jacobian(q))
    return r, J_r, sp.sqrt(sum(x ** 2 for x in r))


SYMBOLIC_FIELDS = [f.name for f in fields(Derivation) if f.name not in ("seconds", "from_cache", "graph")]


def derive(system: System, use_cache: bool = True) -> Derivation:
    """Derive (or load from the on-disk cache keyed by the model's fingerprint)."""
    if not use_cache:
        return derive_uncached(system)
    key = f"{system.name}-{system.fingerprint()}-{cache.code_version()}"
    loaded = _loaded(key)
    if loaded is not None:
        return loaded
    with cache.once(key):   # another process deriving the same model: wait for it and read its entry
        loaded = _loaded(key)
        if loaded is not None:
            return loaded
        derivation = derive_uncached(system)
        # a per-body or large derivation as a graph: srepr would write out its trees
        values, graph = cache.store(key, {name: getattr(derivation, name) for name in SYMBOLIC_FIELDS},
                                    graph=as_graph(system, derivation))
    if graph is not None:  # as a cached run reads it
        return Derivation.stored(values, graph, derivation.seconds, from_cache=False)
    return Derivation(**values, seconds=derivation.seconds)


def _loaded(key: str) -> Derivation | None:
    """The derivation stored under ``key``, None when there is none (or it is not trusted)."""
    stored = cache.load_graph(key)
    if stored is None or sorted(stored[0]) != sorted(SYMBOLIC_FIELDS):
        return None
    if stored[1] is not None:
        return Derivation.stored(*stored)
    return Derivation(**stored[0], from_cache=True)
