"""What every hard case records, and the small tools the cases share (one place)."""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from functools import partial

import numpy as np
from scipy.integrate import solve_ivp

from harness.checks import Bound, Check, relative_error
from harness.derivation.compile import compiled
from harness.engines.base import to_lecture
from harness.modeling.system import System
from harness.modeling.scenes import Scene, pruned
from harness.scenes.simulate import Dynamics

ENGINES = ("pinocchio", "mujoco")
SOURCES = ("symbolic", *ENGINES)


reference_error = partial(relative_error, scale=1.0, symmetric=False)
"""A run against the reference ``b``: ``max |a − b|`` relative to ``max(1, |b|)``."""


@dataclass
class CaseResult:
    """A hard case: what goes wrong when done naively (a number and a figure), what the harness does
    instead, and the bounds that hold (the regression test)."""

    id: str
    title: str
    systems: list
    strategy: str                 # chart switch | implicit integrator | event location | reduction | ...
    problem: str                  # what goes wrong naively
    remedy: str                   # what the harness does instead
    naive: dict = field(default_factory=dict)      # {"what", "metric", "value"}
    checks: list = field(default_factory=list)   # harness.checks.Check
    numbers: dict = field(default_factory=dict)
    notes: list = field(default_factory=list)
    figure: object = None         # a matplotlib Figure until written
    seconds: float = 0.0

    def check(self, name, source, value, bound, reason="", derived: Bound | None = None):
        """``value <= bound`` (a :class:`harness.checks.Check`; ``reason``: how the bound or its scale was
        chosen, its ``detail``). ``derived``: the :class:`~harness.checks.Bound` (``derived=True``) the bound follows
        from, scaled to this check, its basis; without one the bound is a margin bound, which the check must stay
        within 0.1 of (:data:`harness.checks.MARGIN`)."""
        if derived is not None and not derived.derived:
            raise ValueError(f"bound {derived.name!r} is not a derived bound")
        self.checks.append(Check(name, source, float(value), float(bound), derived.name if derived else "", reason))

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.checks)

    def record(self, figure_path: str | None) -> dict:
        """The case as ``hard.json`` holds it (non-finite numbers are encoded by the writer,
        :func:`harness.checks.json_clean`)."""
        return {"id": self.id, "title": self.title, "systems": self.systems, "strategy": self.strategy,
                "problem": self.problem, "remedy": self.remedy, "naive": dict(self.naive),
                "checks": [c.record() for c in self.checks], "numbers": self.numbers,
                "notes": self.notes, "figure": figure_path, "seconds": round(self.seconds, 3),
                "passed": self.passed}


def scene_for(name: str, effects, params=None, inputs=None, horizon: float = 1.0) -> Scene:
    """A scene that only carries effects, parameters and inputs (the initial state is passed separately)."""
    return Scene(name, name, (), (), horizon, frozenset(effects), inputs=inputs or {}, params=params or {})


class Terms(Dynamics):
    """:class:`Dynamics` that also gives ``M``, ``C q̇``, ``g`` and ``f_np`` in lecture coordinates from its source
    (for a reduction that must not factorize a singular ``M``)."""

    def terms(self, t, q, qd):
        u = self.scene.u(t, self.system)
        args = (q, qd, self.p, u)
        if self.source == "symbolic":   # one generated function of all four (CompiledModel.terms)
            return self.c.terms(q, qd, self.p, u)
        theta = self.c("phi", *args).ravel()
        J, J_dot = self.c("J_phi", *args), self.c("J_phi_dot", *args)
        loads = self.loads(q, qd, u)
        inputs = dict(zip((i.name for i in self.system.inputs), u))
        tree = self.model.quantities(theta, J @ qd, inputs, loads, christoffel=False)
        from harness.scenes.simulate import _MapAt
        e = to_lecture(self.source, _MapAt(J, J_dot, qd), tree)
        f_np = J.T @ tree.tau_input + e.f_damper if hasattr(tree, "tau_input") else e.f_damper
        return e.M, e.Cqd, e.g, f_np


def fd_jacobian(rhs, step: float = 1e-7):
    """Forward-difference Jacobian with a fixed relative step, for the implicit methods: scipy's adaptive
    ``num_jac`` grows its step without bound on an exactly zero column (a cyclic coordinate such as the
    governor's shaft angle) until the state overflows."""
    def jac(t, y):
        f0 = np.asarray(rhs(t, y))
        J = np.empty((len(f0), len(y)))
        for k in range(len(y)):
            h = step * max(1.0, abs(y[k]))
            yk = y.copy()
            yk[k] += h
            J[:, k] = (np.asarray(rhs(t, yk)) - f0) / h
        return J
    return jac


def solve(rhs, t_span, y0, method="DOP853", rtol=1e-12, atol=1e-12, t_eval=None, events=None, **kw):
    """``solve_ivp`` with CPU time; returns (solution, cpu seconds). Implicit methods get :func:`fd_jacobian`."""
    if method in ("Radau", "BDF", "LSODA") and "jac" not in kw:
        kw["jac"] = fd_jacobian(rhs)
    start = time.process_time()
    sol = solve_ivp(rhs, t_span, np.asarray(y0, dtype=float), method=method, rtol=rtol, atol=atol, t_eval=t_eval,
                    events=events, **kw)
    return sol, time.process_time() - start


def second_order(f, n):
    """``y' = [q̇, f(t, q, q̇)]`` for ``y = [q, q̇]``."""
    def rhs(t, y):
        return np.concatenate([y[n:], f(t, y[:n], y[n:])])
    return rhs


def energy_function(system: System, effects, params: dict):
    """``E(q, q̇) = T + V`` of the system pruned to ``effects`` (our derivation)."""
    s = pruned(system, effects)
    c = compiled(s)
    values = {**system.default_parameters(), **params}
    p = np.array([values[x.name] for x in s.parameters])
    u = np.zeros(len(s.inputs))
    return lambda q, qd: float(c("T", q, qd, p, u)) + float(c("V", q, qd, p, u))


def finite(*arrays) -> bool:
    return all(np.all(np.isfinite(np.asarray(a, dtype=float))) for a in arrays)
