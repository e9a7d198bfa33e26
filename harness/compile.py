"""Compile a :class:`~harness.derive.Derivation` to fast numeric functions.

Each quantity becomes one ``lambdify``'d NumPy function with common-subexpression elimination, taking
``(q, qd, p, u)`` as flat float arrays in the order of the system's coordinates, parameters and inputs.
Forward dynamics solves ``M q̈ = f_np − C q̇ − g`` numerically (5.93); M is never inverted symbolically.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import sympy as sp

from harness.derive import Derivation, derive, is_per_body
from harness.errors import ModelError
from harness.model import System

QUANTITIES = ("M", "C", "g", "g_gravity", "g_spring", "f_np", "f_damper", "f_input", "T", "V", "M_dot",
              "phi", "J_phi", "J_phi_dot")


@dataclass
class CompiledModel:
    """Numeric functions of one system in lecture coordinates."""

    system: System
    derivation: Derivation

    @cached_property
    def _functions(self):
        s = self.system
        args = [s.q, s.qd, s.p, s.u]
        out = {}
        graph = is_per_body(s)
        for name in QUANTITIES:
            expr = getattr(self.derivation, name)
            if graph:
                out[name] = _lambdify_graph(args, expr)
            else:
                out[name] = sp.lambdify(args, expr, modules="numpy", cse=True, docstring_limit=0)
        return out

    def __call__(self, name: str, q, qd=None, p=None, u=None) -> np.ndarray:
        """Evaluate quantity ``name`` (one of :data:`QUANTITIES`) at one state."""
        s = self.system
        qd = np.zeros(len(s.q)) if qd is None else qd
        p = list(s.default_parameters().values()) if p is None else p
        u = np.zeros(len(s.u)) if u is None else u
        return np.asarray(self._functions[name](q, qd, p, u), dtype=float)

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
        expr = getattr(self.derivation, name)
        shape = expr.shape if isinstance(expr, sp.MatrixBase) else ()
        if name not in self._batched_functions:
            flat = list(expr) if shape else [expr]
            graph = {"use_imps": False, "cse": lambda e: sp.cse(e, order="none")} if is_per_body(s) else {"cse": True}
            self._batched_functions[name] = sp.lambdify([s.q, s.qd, s.p, s.u], flat, modules="numpy",
                                                        docstring_limit=0, **graph)  # graph: see _lambdify_graph
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

    def forward_dynamics(self, q, qd, p, u):
        """``q̈ = M⁻¹ (f_np − C q̇ − g)`` from (5.93), solved numerically; a clear error at a singular ``M``."""
        rhs = self.generalized_forces(q, qd, p, u) - self.coriolis_matrix(q, qd, p) @ np.asarray(qd) \
            - self.potential_forces(q, p)
        M = self.mass_matrix(q, p)
        check_regular(self.system, M, q)
        return np.linalg.solve(M, rhs)


SINGULAR_M = 1e-13  # smallest/largest eigenvalue of M below which q̈ is round-off (relative error ≳ 1e-3)


def check_regular(system: System, M, q) -> None:
    """Raise :class:`ModelError` where ``M(q)`` is singular to working precision (a coordinate singularity:
    some q̇ moves no mass, e.g. ``phi`` at ``theta = 0`` of the spherical pendulum, (5.81)), instead of
    returning a q̈ made of round-off."""
    def at():
        return ", ".join(f"{c.name} = {float(x):.6g}" for c, x in zip(system.coordinates, q))
    if not np.all(np.isfinite(q)):
        raise ModelError(f"the state is not finite ({at()}) in {system.name}: the integration diverged")
    if not np.all(np.isfinite(M)):
        raise ModelError(f"the mass matrix M is not finite at {at()} in {system.name}: the state is outside the "
                         f"domain of the map theta = phi(q) or at its singularity")
    w, v = np.linalg.eigh(M)
    if w[0] > SINGULAR_M * max(abs(w[-1]), 1e-300):
        return
    idle = [c.name for c, x in zip(system.coordinates, v[:, 0]) if abs(x) > 0.1]
    raise ModelError(f"coordinate singularity at {at()} in {system.name}: the mass matrix M is singular "
                     f"(eigenvalues {w[0]:.2g} … {w[-1]:.2g}); a rate of {', '.join(idle)} moves no mass")


def _lambdify_graph(args, expr):
    """``lambdify`` of a per-body derivation (:func:`harness.derive._per_body`), whose expressions are small graphs
    but huge trees. Every step that walks the tree is avoided (measured on the 7-DoF arm): ``lambdify`` collects
    the symbols of a Matrix or expression with ``expr.atoms`` (skipped for a plain list) and searches it for
    implemented functions (``use_imps``, 29 s of 52 s for C); ``cse`` orders canonically by counting nodes
    (``order="none"``). Common-subexpression elimination itself visits every shared sub-expression once.
    Returns the same shapes as ``lambdify`` of the Matrix / expression."""
    shape = expr.shape if isinstance(expr, sp.MatrixBase) else None
    fn = sp.lambdify(args, list(expr) if shape else [expr], modules="numpy", use_imps=False,
                     cse=lambda exprs: sp.cse(exprs, order="none"), docstring_limit=0)
    if shape is None:
        return lambda *a: fn(*a)[0]
    return lambda *a: np.asarray(fn(*a), dtype=float).reshape(shape)


_COMPILED: dict[str, CompiledModel] = {}


def compiled(system: System) -> CompiledModel:
    """The compiled model of ``system`` (derived or loaded from the cache once per process)."""
    key = system.fingerprint()
    if key not in _COMPILED:
        _COMPILED[key] = CompiledModel(system, derive(system))
    return _COMPILED[key]
