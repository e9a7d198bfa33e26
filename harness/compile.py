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

from harness.derive import Derivation, derive
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
        for name in QUANTITIES:
            expr = getattr(self.derivation, name)
            out[name] = sp.lambdify(args, expr, modules="numpy", cse=True, docstring_limit=0)
        return out

    def __call__(self, name: str, q, qd=None, p=None, u=None) -> np.ndarray:
        """Evaluate quantity ``name`` (one of :data:`QUANTITIES`) at one state."""
        s = self.system
        qd = np.zeros(len(s.q)) if qd is None else qd
        p = list(s.default_parameters().values()) if p is None else p
        u = np.zeros(len(s.u)) if u is None else u
        return np.asarray(self._functions[name](q, qd, p, u), dtype=float)

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
        """``q̈ = M⁻¹ (f_np − C q̇ − g)`` from (5.93), solved numerically."""
        rhs = self.generalized_forces(q, qd, p, u) - self.coriolis_matrix(q, qd, p) @ np.asarray(qd) \
            - self.potential_forces(q, p)
        return np.linalg.solve(self.mass_matrix(q, p), rhs)


_COMPILED: dict[str, CompiledModel] = {}


def compiled(system: System) -> CompiledModel:
    """The compiled model of ``system`` (derived or loaded from the cache once per process)."""
    key = system.fingerprint()
    if key not in _COMPILED:
        _COMPILED[key] = CompiledModel(system, derive(system))
    return _COMPILED[key]
