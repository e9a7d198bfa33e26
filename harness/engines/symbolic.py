"""Our own compiled symbolic model (already in lecture coordinates)."""

from __future__ import annotations

from harness.derivation.compile import compiled
from harness.engines.base import Evaluation, State


def evaluate(state: State) -> Evaluation:
    c = compiled(state.system)
    args = (state.q, state.qd, state.p, state.u_vec)
    C = c("C", *args)
    return Evaluation(
        engine="symbolic",
        M=c("M", *args), C=C, Cqd=C @ state.qd, g=c("g", *args).ravel(),
        g_gravity=c("g_gravity", *args).ravel(), g_spring=c("g_spring", *args).ravel(),
        f_damper=c("f_damper", *args).ravel(), qdd=c.forward_dynamics(*args),
        extra={"M_dot": c("M_dot", *args), "f_np": c("f_np", *args).ravel(), "T": float(c("T", *args)),
               "V": float(c("V", *args))},
        calls={"M": "M(q) (5.21)", "C": "Christoffel (5.95), (5.97)", "g": "dV/dq (5.96)",
               "qdd": "numpy.linalg.solve(M, f_np - C qd - g) (5.93)"},
    )
