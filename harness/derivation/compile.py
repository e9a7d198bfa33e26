"""Compile a :class:`~harness.derivation.derive.Derivation` to fast numeric functions.

Each quantity becomes one ``lambdify``'d NumPy function with common-subexpression elimination, taking
``(q, qd, p, u)`` as flat float arrays in the order of the system's coordinates, parameters and inputs; the same
expressions evaluate at ``N`` states at once (:meth:`CompiledModel.batched`).
Forward dynamics, the function every simulation calls, has its own: one function of plain Python floats returning
the terms of (5.93), ``M``, ``C q̇``, ``g`` and ``f_np`` with their subexpressions shared (:meth:`CompiledModel.terms`)
— a NumPy call per quantity costs 20–100 µs where the arithmetic costs a few. ``M q̈ = f_np − C q̇ − g`` is
solved numerically; M is never inverted symbolically.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import math

import numpy as np
import sympy as sp
from numpy.linalg import _umath_linalg

from harness import profiling
from harness.derivation.lambdified import lambdify
from harness.derivation.derive import Derivation, derive, is_per_body, matrix_vector
from harness.errors import ModelError, NotApplicable
from harness.modeling.system import System, drawn_parameters

QUANTITIES = ("M", "C", "g", "g_gravity", "g_spring", "g_spring_terms", "f_np", "f_damper", "f_input", "T", "V", "M_dot",
              "phi", "J_phi", "J_phi_dot")


@dataclass
class CompiledModel:
    """Numeric functions of one system in lecture coordinates."""

    system: System
    derivation: Derivation

    def warm(self) -> "CompiledModel":
        """Compile now what every conformance check and claim evaluates (the quantities, the float function of
        the forward dynamics), so that no later phase pays for it."""
        self.compile_quantities()
        self._terms_function
        return self

    def compile_quantities(self) -> dict:
        """Every quantity of :data:`QUANTITIES` compiled (:attr:`_functions`), name → function."""
        return {name: self._functions[name] for name in QUANTITIES}

    @cached_property
    def _functions(self) -> dict:
        """Quantity name → its NumPy function, each compiled when first asked for: a scene's pruned and idle models
        evaluate their forward dynamics, ``T`` and ``V``, not the 14 quantities."""
        return _Compiled(self._lambdified)

    def _lambdified(self, name: str):
        s, d = self.system, self.derivation
        with profiling.phase("lambdify quantities"):
            if self._per_body or d.graph is not None:
                return _lambdify_graph([s.q, s.qd, s.p, s.u], _compiled_form(d, name), d.graph)
            return lambdify([s.q, s.qd, s.p, s.u], getattr(d, name), modules="numpy", cse=True, docstring_limit=0)

    @cached_property
    def _per_body(self) -> bool:
        return is_per_body(self.system)

    @cached_property
    def _terms_function(self):
        """The entries of ``M``, ``C q̇``, ``g``, ``f_np`` (row-major) as one function of floats."""
        s, d = self.system, self.derivation
        M, C, g, f_np = (_compiled_form(d, name) for name in ("M", "C", "g", "f_np"))
        with profiling.phase("lambdify terms of (5.93)"):
            return float_function(s, [*M, *matrix_vector(C, s.qd), *g, *f_np], d.graph)

    @cached_property
    def _map_function(self):
        """The entries of ``θ = φ(q)``, ``J = ∂φ/∂q``, ``J̇`` as one function of floats."""
        s, d = self.system, self.derivation
        phi, J_phi, J_phi_dot = (_compiled_form(d, name) for name in ("phi", "J_phi", "J_phi_dot"))
        return float_function(s, [*phi, *J_phi, *J_phi_dot], d.graph)

    @cached_property
    def dof(self) -> int:
        """Degrees of freedom ``n`` (``len(system.q)`` builds the symbols each time)."""
        return len(self.system.coordinates)

    @cached_property
    def identity_map(self) -> bool:
        """Whether ``θ = q`` (:attr:`System.identity_map`)."""
        return self.system.identity_map

    @cached_property
    def constant_map(self) -> bool:
        """Whether ``J = ∂φ/∂q`` is constant (no coordinate, rate or input in it, none in ``φ``): ``φ`` is affine,
        ``θ = φ(0) + J q`` and ``J̇ = 0`` at every state (gears, ropes, relative angles)."""
        s, d = self.system, self.derivation
        moving = set(s.q) | set(s.qd) | set(s.u)
        return not (d.J_phi.free_symbols & moving) and not (d.phi.free_symbols & set(s.u))

    @property
    def affine(self) -> bool:
        """Whether ``θ = φ(0) + J q`` with a constant square ``J`` (:attr:`constant_map`, as many tree joints as
        coordinates): :meth:`affine_map` is defined."""
        return self.constant_map and self.derivation.J_phi.is_square

    def affine_map(self, p, u) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(φ(0), J, J⁻¹)`` of a constant square map (:attr:`affine`): ``θ = φ(0) + J q`` at every state,
        evaluated once."""
        if not self.affine:
            raise NotApplicable(f"{self.system.name}: θ = φ(q) is not an affine map with a square J")
        n = self.dof
        phi0, J, _ = self.map_at(np.zeros(n), np.zeros(n), p, u)
        return phi0, J, np.linalg.inv(J)

    @cached_property
    def _native(self):
        """``(terms, qdd, batched, state_derivative)``: :meth:`terms`' function compiled to machine code by numba
        (``njit``, NumPy's error model: ``nan`` / ``inf`` instead of exceptions) returning one array; ``q̈`` of
        :meth:`forward_dynamics` with its regularity test, all in machine code; the terms at ``N`` states in a loop
        (:meth:`batched_terms`); the first-order right-hand side (:attr:`native_state_derivative`). Measured over
        the catalogue: 0.6–4 µs per call of the terms instead of 1.3–170 µs, after 0.1–16 s of compilation (the
        7-DoF arm the slowest): opt-in."""
        import numba

        n = self.dof
        size = n * (n + 3)
        jit = numba.njit(error_model="numpy")
        arithmetic = jit(self._terms_function)
        is_regular = jit(regular_spectrum)
        solve_certified = jit(cholesky_solve)

        @jit
        def terms(q, qd, p, u):
            values = arithmetic(q, qd, p, u)
            out = np.empty(size)
            for k in range(size):
                out[k] = values[k]
            return out

        @jit
        def qdd(q, qd, p, u):
            """``(q̈, regular)``: ``regular`` is the test of :meth:`forward_dynamics` (finite state, finite M,
            eigenvalue ratio above SINGULAR_M), decided by :func:`cholesky_solve`'s bound where it proves M
            regular, else by the eigenvalues."""
            v = terms(q, qd, p, u)
            if not (np.isfinite(v[:n * n]).all() and np.isfinite(q).all()):
                return np.full(n, np.nan), False
            rhs = v[n * n + 2 * n:] - v[n * n:n * n + n] - v[n * n + n:n * n + 2 * n]  # f_np − C q̇ − g
            a, proved = solve_certified(v[:n * n], rhs, n)
            if proved:
                return a, True
            w, V = np.linalg.eigh(v[:n * n].reshape((n, n)))
            return V @ ((V.T @ rhs) / w), is_regular(w)

        @jit
        def batched(Q, QD, p, U):
            out = np.empty((Q.shape[0], size))
            for i in range(Q.shape[0]):
                values = arithmetic(Q[i], QD[i], p, U[i])
                for k in range(size):
                    out[i, k] = values[k]
            return out

        singular = (f"{self.system.name}: M is singular or not finite along the integration (a coordinate "
                    f"singularity, or a state outside the map's domain); CompiledModel.forward_dynamics names it")

        @jit
        def state_derivative(t, y, p, u):
            a, regular = qdd(y[:n], y[n:], p, u)
            if not regular:
                raise ModelError(singular)
            out = np.empty(2 * n)
            out[:n] = y[n:]
            out[n:] = a
            return out

        return terms, qdd, batched, state_derivative

    @property
    def native_state_derivative(self):
        """``ẏ = (q̇, q̈)`` of the first-order system ``y = (q, q̇)`` as one numba function ``f(t, y, p, u)``, for
        an integrator to call directly (:attr:`_native`); a singular ``M`` raises :class:`ModelError`."""
        return self._native[3]

    def terms_array(self, q, qd, p, u, native: bool = False) -> np.ndarray:
        """The entries of ``M`` (row-major), ``C q̇``, ``g``, ``f_np`` of (5.93) at one state in one array, from one
        call of one compiled function (``native``: its machine code, :attr:`_native`)."""
        if native:
            return self._native[0](np.asarray(q, dtype=float), np.asarray(qd, dtype=float),
                                   np.asarray(p, dtype=float), np.asarray(u, dtype=float))
        n = self.dof
        return np.array(call_floats(self._terms_function, n * (n + 3), q, qd, p, u), dtype=float)

    def batched_terms(self, Q, QD, p, U) -> np.ndarray:
        """:meth:`terms_array` at ``N`` states, ``(N, n (n + 3))``, in machine code (numba, a loop over the states:
        no NumPy temporaries of every intermediate as in :meth:`batched`)."""
        return self._native[2](*(np.ascontiguousarray(x, dtype=float) for x in (Q, QD, p, U)))

    def terms(self, q, qd, p, u, native: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``M``, ``C q̇``, ``g``, ``f_np`` of (5.93) at one state (:meth:`terms_array`, split)."""
        n = self.dof
        values = self.terms_array(q, qd, p, u, native)
        Cqd, g, f_np = values[n * n:].reshape(3, n)
        return values[:n * n].reshape(n, n), Cqd, g, f_np

    def map_at(self, q, qd, p, u) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``θ = φ(q)``, ``J`` and ``J̇`` (5.58) at one state, from one call of one compiled function."""
        n, k = self.dof, self.derivation.phi.shape[0]
        values = np.array(call_floats(self._map_function, k * (2 * n + 1), q, qd, p, u), dtype=float)
        return values[:k], values[k:k + k * n].reshape(k, n), values[k + k * n:].reshape(k, n)

    def __call__(self, name: str, q, qd=None, p=None, u=None) -> np.ndarray:
        """Evaluate quantity ``name`` (one of :data:`QUANTITIES`) at one state; ``qd``, ``u`` zero and ``p`` the
        defaults where not given."""
        qd = np.zeros(self.dof) if qd is None else qd
        p = self._default_parameters if p is None else p
        u = np.zeros(len(self.system.inputs)) if u is None else u
        return np.asarray(self._functions[name](q, qd, p, u), dtype=float)

    @cached_property
    def _default_parameters(self) -> tuple:
        return tuple(self.system.default_parameters().values())

    @cached_property
    def _batched_functions(self) -> dict:
        return {}

    def batched(self, name: str, Q, QD=None, p=None, U=None) -> np.ndarray:
        """Quantity ``name`` at ``N`` states at once, shape ``(N, *shape)``: ``Q``, ``QD`` are ``(N, n)``, ``U``
        ``(N, m)``, ``p`` one parameter vector. One lambdified function of the flattened entries, evaluated
        by NumPy broadcasting (a constant entry is broadcast to ``N``)."""
        s = self.system
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        N = Q.shape[0]
        QD = np.zeros_like(Q) if QD is None else np.asarray(QD, dtype=float)
        U = np.zeros((N, len(s.u))) if U is None else np.asarray(U, dtype=float)
        p = list(s.default_parameters().values()) if p is None else p
        expr = _compiled_form(self.derivation, name)
        shape = expr.shape if isinstance(expr, sp.MatrixBase) else ()
        if name not in self._batched_functions:
            flat = list(expr) if shape else [expr]
            self._batched_functions[name] = lambdify([s.q, s.qd, s.p, s.u], flat, modules="numpy",
                                                        docstring_limit=0,
                                                        **_lambdify_options(s, self.derivation.graph))
        values = self._batched_functions[name](Q.T, QD.T, p, U.T)
        out = np.empty((len(values), N))
        for k, v in enumerate(values):
            out[k] = v
        return np.moveaxis(out.reshape(*shape, N), -1, 0)

    def batched_forward_dynamics(self, Q, QD, p, U=None) -> np.ndarray:
        """``q̈`` (5.93) at ``N`` states: ``(N, n)``, each ``M`` solved numerically."""
        QD = np.asarray(QD, dtype=float)
        rhs = self.batched("f_np", Q, QD, p, U)[..., 0] - np.einsum("nij,nj->ni", self.batched("C", Q, QD, p), QD) \
            - self.batched("g", Q, QD, p)[..., 0]
        return np.linalg.solve(self.batched("M", Q, QD, p), rhs[..., None])[..., 0]

    # ------------------------------------------------------------------ the lecture's quantities
    def mass_matrix(self, q, p):
        """``M(q)`` (5.21)."""
        return self("M", q, p=p)

    def coriolis_matrix(self, q, qd, p):
        """``C(q, q̇)`` from Christoffel symbols (5.95), (5.97)."""
        return self("C", q, qd, p)

    def potential_forces(self, q, p):
        """``g(q) = ∂V/∂q`` (5.96)."""
        return self("g", q, p=p).ravel()

    def generalized_forces(self, q, qd, p, u):
        """Non-potential generalized forces ``f_q^np`` (5.73)."""
        return self("f_np", q, qd, p, u).ravel()

    def forward_dynamics(self, q, qd, p, u, native: bool = False):
        """``q̈ = M⁻¹ (f_np − C q̇ − g)`` from (5.93), solved numerically; a clear error at a singular ``M``.
        One symmetric eigendecomposition ``M = V diag(w) Vᵀ`` both checks the regularity (:data:`SINGULAR_M`)
        and solves: ``q̈ = V (Vᵀ rhs / w)``; one or two coordinates in Python floats, the same test
        (:meth:`_forward_dynamics_2`). ``native``: all of it in machine code (:attr:`_native`)."""
        if native:
            qdd, regular = self._native[1](np.asarray(q, dtype=float), np.asarray(qd, dtype=float),
                                           np.asarray(p, dtype=float), np.asarray(u, dtype=float))
            if not regular:
                self.not_regular(q, qd, p, u)
            return qdd
        if self.dof == 1:  # eigh of a 1 × 1 M is w = M, V = [[1]]: the same q̈, bit for bit, without LAPACK
            m, Cqd, g, f_np = call_floats(self._terms_function, 4, q, qd, p, u)
            if not regular_spectrum((m,)) or not math.isfinite(q[0]):  # also nan: every comparison is false
                self.not_regular(q, qd, p, u)
            return np.array([(f_np - Cqd - g) / m])
        if self.dof == 2:
            return self._forward_dynamics_2(q, qd, p, u)
        M, Cqd, g, f_np = self.terms(q, qd, p, u)
        try:
            w, V = symmetric_eigen(M)
        except np.linalg.LinAlgError:  # not finite
            w = None
        if w is None or not regular_spectrum(w) or not math.isfinite(sum(q)):
            self.not_regular(q, qd, p, u)
        return V @ ((V.T @ (f_np - Cqd - g)) / w)

    def not_regular(self, q, qd, p, u) -> None:
        """Raise the clear error of a state where ``q̈`` cannot be computed (:class:`ModelError`): ``M`` singular or
        not finite (:func:`check_regular`), else the force terms that are not finite there. ``M``, ``C q̇``, ``g``
        and ``f_np`` are computed together (:meth:`terms`): one term that is not finite makes them all ``nan``, and
        was reported as a mass matrix that is not finite."""
        with np.errstate(all="ignore"):   # the terms below are not finite: the error says which
            check_regular(self.system, self("M", q, p=p), q, p)
            C, g, f_np = self("C", q, qd, p, u), self("g", q, p=p), self("f_np", q, qd, p, u)
        bad = [name for name, x in (("C(q, q̇) q̇ (5.95)", C @ np.asarray(qd, dtype=float)), ("g(q) (5.96)", g),
                                     ("f_np (5.73)", f_np)) if not np.all(np.isfinite(x))]
        raise ModelError(f"{' and '.join(bad) or 'q̈'} not finite at {state_text(self.system, q)} in "
                         f"{self.system.name}: a force element is singular there (e.g. a spring or damper between "
                         "two points at the same place, whose direction is undefined)")

    def _forward_dynamics_2(self, q, qd, p, u) -> np.ndarray:
        """:meth:`forward_dynamics` of two coordinates in Python floats: the eigenvalues of the symmetric ``M =
        [[a, b], [b, d]]`` (its lower triangle, as ``eigh``) in closed form (:func:`eigenvalues_2`), the same
        regularity test (:func:`regular_spectrum`), and ``q̈ = M⁻¹ rhs`` by Cramer's rule. The same q̈ to
        rounding (``cond(M) ε``, tests/test_engines.py), without the eigendecomposition's and NumPy's fixed cost per
        call: measured on planar_manipulator (its swing's model), 9.6 µs → 3.0 µs a call."""
        a, _, b, d, c0, c1, g0, g1, f0, f1 = call_floats(self._terms_function, 10, q, qd, p, u)
        if not regular_spectrum(eigenvalues_2(a, b, d)) or not math.isfinite(q[0] + q[1]):
            self.not_regular(q, qd, p, u)
        r0, r1, det = f0 - c0 - g0, f1 - c1 - g1, a * d - b * b
        return np.array([(d * r0 - b * r1) / det, (a * r1 - b * r0) / det])


def cholesky_solve(M, rhs, n: int):
    """``(M⁻¹ rhs, True)`` where a Cholesky factorization ``M = L Lᵀ`` (of ``M``'s lower triangle, ``M`` row-major
    flat) proves ``M`` regular: its eigenvalues are positive, ``λ_max ≤ tr M`` and ``λ_min ≥ 1 / tr M⁻¹``, with
    ``tr M⁻¹ = ‖L⁻¹‖_F²``, so ``λ_min / λ_max ≥ 1 / (tr M tr M⁻¹)``; proved where that is above twice
    :data:`SINGULAR_M`. Else ``(rhs, False)``, and the eigenvalues decide (:func:`regular_spectrum`). Where proved,
    the eigenvalue test passes too: then ``cond(M) < 5e12``, and both the bound's and ``eigh``'s rounding
    (``n ε cond(M)`` relative, below 1 %) are far within the factor 2. For the machine code of ``q̈``
    (:attr:`CompiledModel._native`): measured on lightweight_robot's ``M`` (n = 7), solve and test 0.6 µs instead of
    ``eigh``'s 4.7 µs; the same ``q̈`` to rounding (``cond(M) ε``)."""
    L = np.zeros((n, n))
    for j in range(n):
        d = M[j * n + j]
        for k in range(j):
            d -= L[j, k] * L[j, k]
        if not d > 0.0:  # also nan
            return rhs, False
        L[j, j] = math.sqrt(d)
        for i in range(j + 1, n):
            s = M[i * n + j]
            for k in range(j):
                s -= L[i, k] * L[j, k]
            L[i, j] = s / L[j, j]
    inverse = np.zeros((n, n))   # L⁻¹, lower triangular, by forward substitution of the unit vectors
    for j in range(n):
        inverse[j, j] = 1.0 / L[j, j]
        for i in range(j + 1, n):
            s = 0.0
            for k in range(j, i):
                s -= L[i, k] * inverse[k, j]
            inverse[i, j] = s / L[i, i]
    trace, trace_inverse = 0.0, 0.0
    for i in range(n):
        trace += M[i * n + i]
        for j in range(i + 1):
            trace_inverse += inverse[i, j] * inverse[i, j]
    if not trace * trace_inverse * (2.0 * SINGULAR_M) < 1.0:
        return rhs, False
    return inverse.T @ (inverse @ rhs), True


def eigenvalues_2(a: float, b: float, d: float) -> tuple[float, float]:
    """Ascending eigenvalues of the symmetric ``[[a, b], [b, d]]`` in floats: ``w₁ = (a + d)/2 + hypot((a − d)/2,
    b)``, ``w₀ = (a d − b²) / w₁`` (exact for a diagonal matrix, else off by about ``ε w₁`` as LAPACK's);
    ``(-inf, w₁)`` where ``w₁ ≤ 0`` or not finite (no regular mass matrix: :func:`regular_spectrum` rejects
    it)."""
    w1 = 0.5 * (a + d) + math.hypot(0.5 * (a - d), b)
    return (a * d - b * b) / w1 if w1 > 0.0 else -math.inf, w1


def symmetric_eigen(M: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``numpy.linalg.eigh(M)`` of a float64 ``M`` (its lower triangle): the same LAPACK gufunc, bit for bit, without
    NumPy's Python wrapper around it (its checks and conversions: 5.7 of 7.5 µs for a 2 × 2 ``M``, a third of a
    scene's right-hand side call, measured with NumPy 2.4.6). A non-finite ``M`` gives non-finite eigenvalues here as
    there, which :func:`regular_spectrum` rejects; tests/test_engines.py checks the identity with the pinned NumPy."""
    return _umath_linalg.eigh_lo(M, signature="d->dd")


SINGULAR_M = 1e-13  # smallest/largest eigenvalue of M below which q̈ is round-off (relative error ≳ 1e-3)


class _Compiled(dict):
    """A dict that compiles a missing quantity with ``compile(name)`` and keeps it."""

    def __init__(self, compile):
        super().__init__()
        self._compile = compile

    def __missing__(self, name: str):
        if name not in QUANTITIES:
            raise KeyError(name)
        function = self[name] = self._compile(name)
        return function


def regular_spectrum(w) -> bool:
    """Whether ascending eigenvalues ``w`` of ``M`` are those of a regular mass matrix (:data:`SINGULAR_M`)."""
    return w[0] > SINGULAR_M * max(abs(w[-1]), 1e-300)


def _drawn(system: System, p) -> str:
    """The parameter values of ``p`` that are not the defaults, as an error names them (none: "")."""
    changed = "" if p is None else drawn_parameters(system, p)
    return (f" with the parameters {changed} (the checks draw each from its range=, a positive "
            "one without a range from [default/2, 2 default]: a map that closes a chain must be defined over that "
            "range)") if changed else ""


def state_text(system: System, q) -> str:
    """``q`` as an error message names it: ``name = value`` of each coordinate."""
    return ", ".join(f"{c.name} = {float(x):.6g}" for c, x in zip(system.coordinates, q))


def check_regular(system: System, M, q, p=None) -> None:
    """Raise :class:`ModelError` where ``M(q)`` is singular to working precision (a coordinate singularity:
    some q̇ moves no mass, e.g. ``phi`` at ``theta = 0`` of the spherical pendulum, (5.81)), instead of
    returning a q̈ made of round-off. ``p``: the parameter values, named in the error where they are not the defaults
    (a map that closes a chain may be undefined at drawn parameters, not at ``q``)."""
    if not np.all(np.isfinite(q)):
        raise ModelError(f"the state is not finite ({state_text(system, q)}) in {system.name}: the integration "
                         "diverged")
    if not np.all(np.isfinite(M)):
        raise ModelError(f"the mass matrix M is not finite at {state_text(system, q)} in {system.name}"
                         f"{_drawn(system, p)}: the state is outside the domain of the map theta = phi(q) or at its "
                         "singularity")
    w, v = np.linalg.eigh(M)
    if regular_spectrum(w):
        return
    idle = [c.name for c, x in zip(system.coordinates, v[:, 0]) if abs(x) > 0.1]
    raise ModelError(f"coordinate singularity at {state_text(system, q)} in {system.name}: the mass matrix M is "
                     f"singular (eigenvalues {w[0]:.2g} … {w[-1]:.2g}); a rate of {', '.join(idle)} moves no mass")


def float_function(system: System, exprs: list, graph=None):
    """``exprs`` as one function of four lists of floats ``(q, q̇, p, u)`` returning a list of floats, printed with
    Python's ``math`` (``sin`` of a float: 50 ns; ``numpy.sin`` of a NumPy scalar: 1 µs), shared subexpressions
    computed once (those of ``graph`` when the expressions are in its symbols: :func:`_compiled_form`)."""
    return lambdify([system.q, system.qd, system.p, system.u], exprs, modules="math", docstring_limit=0,
                       **_lambdify_options(system, graph))


def _compiled_form(derivation: Derivation, name: str):
    """The quantity ``name`` of ``derivation`` as it is compiled: in the symbols of its stored common
    subexpressions when it was stored as a graph (``derivation.graph``), else as derived."""
    if derivation.graph is not None:
        return derivation.graph.reduced[name]
    return getattr(derivation, name)


def _floats(x) -> list:
    return x.tolist() if isinstance(x, np.ndarray) else [float(v) for v in x]


def call_floats(fn, size: int, q, qd, p, u) -> list:
    """``fn`` of :func:`float_function` at one state; ``nan`` where ``math`` raises (NumPy returns nan / inf)."""
    try:
        return fn(_floats(q), _floats(qd), _floats(p), _floats(u))
    except (ValueError, ZeroDivisionError, OverflowError):
        return [math.nan] * size


def _lambdify_options(system: System, graph=None) -> dict:
    """Options of ``lambdify`` for a list of expressions: a per-body derivation is walked as a graph
    (:func:`_lambdify_graph`)."""
    if graph is not None or is_per_body(system):
        return _graph_options(graph)
    return {"cse": True}


def _graph_options(graph) -> dict:
    """``lambdify``'s options for the expressions of a per-body derivation (:func:`_lambdify_graph`)."""
    return {"use_imps": False, "cse": graph.cse if graph is not None else canonical_cse}


def canonical_cse(exprs):
    """``cse`` ordered canonically by counting nodes (``order="none"``): every shared sub-expression visited once."""
    return sp.cse(exprs, order="none")


canonical_cse.cache_key = "sympy.cse(order='none')"  # a cse function of lambdify's keys its compiled code by this


def _lambdify_graph(args, expr, graph=None):
    """``lambdify`` of a per-body derivation (:func:`harness.derivation.derive._per_body`), whose expressions are small graphs
    but huge trees. Every step that walks the tree is avoided (measured on the 7-DoF arm): ``lambdify`` collects
    the symbols of a Matrix or expression with ``expr.atoms`` (skipped for a plain list) and searches it for
    implemented functions (``use_imps``, 29 s of 52 s for C). The common subexpressions are the ones stored with
    the derivation (``graph``: ``expr`` is in its symbols, :func:`_compiled_form`); without a stored graph (a
    derivation not cached), ``cse`` orders canonically by counting nodes (``order="none"``) and visits every
    shared sub-expression once. Returns the same shapes as ``lambdify`` of the Matrix / expression."""
    shape = expr.shape if isinstance(expr, sp.MatrixBase) else None
    fn = lambdify(args, list(expr) if shape else [expr], modules="numpy", docstring_limit=0,
                     **_graph_options(graph))
    if shape is None:
        return lambda *a: fn(*a)[0]
    return lambda *a: np.asarray(fn(*a), dtype=float).reshape(shape)


_COMPILED: dict[str, CompiledModel] = {}


def compiled(system: System) -> CompiledModel:
    """The compiled model of ``system`` (derived or loaded from the cache once per process)."""
    key = system.fingerprint()
    if key not in _COMPILED:
        if profiling.enabled():
            from harness.derivation import cache

            hit = (cache.cache_dir() / f"{system.name}-{key}-{cache.code_version()}.json").exists()
            profiling.count(f"derivation cache {'hit' if hit else 'miss'}")
            with profiling.phase(f"derive (cache {'hit' if hit else 'miss'})"):
                _COMPILED[key] = CompiledModel(system, derive(system))
        else:
            _COMPILED[key] = CompiledModel(system, derive(system))
    return _COMPILED[key]
