"""Our own compiled symbolic model (already in lecture coordinates)."""

from __future__ import annotations

import numpy as np
import sympy as sp

from harness.derivation.compile import CompiledModel, compiled
from harness.derivation.derive import derive, is_per_body
from harness.engines.base import Evaluation, State
from harness.errors import EngineError
from harness.modeling.system import WORLD


def evaluate(state: State) -> Evaluation:
    c = compiled(state.system)
    args = (state.q, state.qd, state.p, state.u_vec)
    C = c("C", *args)
    return Evaluation(
        engine="symbolic",
        M=c("M", *args), C=C, Cqd=C @ state.qd, g=c("g", *args).ravel(),
        g_gravity=c("g_gravity", *args).ravel(), g_spring=c("g_spring", *args).ravel(),
        f_damper=c("f_damper", *args).ravel(), qdd=c.forward_dynamics(*args),
        extra={"M_dot": c("M_dot", *args), "f_np": c("f_np", *args).ravel(),
               "g_spring_terms": c("g_spring_terms", *args).ravel(), "T": float(c("T", *args)),
               "V": float(c("V", *args))},
        calls={"M": "M(q) (5.21)", "C": "Christoffel (5.95), (5.97)", "g": "dV/dq (5.96)",
               "f_damper": "f_damper (5.73)",
               "qdd": "M^-1 (f_np - C qd - g) (5.93): eigh of M (closed form for 1 or 2 coordinates)"},
    )


class SymbolicTree:
    """Our derivation of a tree :class:`~harness.modeling.system.System` (a URDF read by
    :func:`harness.files.from_urdf.from_urdf`) as an engine adapter seen through ``joints`` by name, for the
    robots sweep (:mod:`harness.files.robots`): ``M`` (5.21), ``C q̇`` from the Christoffel ``C`` (5.95), (5.97),
    ``g`` (5.96), compiled into one function (:meth:`~harness.derivation.compile.CompiledModel.terms`), and the
    forward dynamics ``q̈ = M⁻¹ (−C q̇ − g)`` solved numerically (no inputs, no dampers: the tree has none). What
    each joint moves (``subtree_parts``) comes from the link frames of the same model's joints (4.21), in float64.
    The masses and ``g`` at their defaults (the file's masses; ``g`` = the reference's gravity, along −z)."""

    name = "symbolic"
    free = None

    def __init__(self, system, joints: list[str], gravity, derivation=None):
        from harness.files.from_urdf import rpy_matrix

        own = [j.name for j in system.joints]
        if sorted(own) != sorted(joints):
            raise EngineError(f"our model of {system.name} has joints {sorted(set(own) - set(joints))} the "
                              f"reference does not, and lacks {sorted(set(joints) - set(own))}")
        rates = {c: k for k, c in enumerate(system.q)}
        phi = list(system.phi)
        if any(phi[own.index(j)] not in rates for j in joints):
            raise EngineError(f"our model of {system.name} maps its coordinates onto the joints (a <mimic>): not "
                              "one coordinate per joint")
        gravity = np.asarray(gravity, dtype=float)
        if gravity[0] or gravity[1] or gravity[2] > 0:
            raise EngineError(f"the reference's gravity {gravity.tolist()} is not along −z, as our model's")
        self.system, self.joints = system, list(joints)
        self.index = [rates[phi[own.index(j)]] for j in joints]   # our coordinate of each reference joint
        parameters = system.default_parameters()
        if "g" in parameters:
            parameters["g"] = float(-gravity[2])
        self.p = [parameters[p.name] for p in system.parameters]
        self.u = np.zeros(len(system.u))
        self.derivation = derivation or derive(system)
        self.model = CompiledModel(system, self.derivation)
        self.per_body = is_per_body(system)
        self._gravity = gravity
        values = dict(zip(system.p, self.p))
        self.links = [link for link in system.links if link.has_mass]
        self.parts = [(float(sp.sympify(link.mass).xreplace(values)),
                       np.array(link.com_vector, dtype=float).ravel(), np.array(link.inertia.matrix, dtype=float))
                      for link in self.links]
        ordered, done = [], {WORLD}   # parents first
        while len(ordered) < len(system.joints):
            step = [j for j in system.joints if j.parent in done and j not in ordered]
            if not step:
                raise EngineError(f"our model of {system.name} is not a tree rooted at the world")
            ordered += step
            done |= {j.child for j in step}
        self._chain = [(j.parent, j.child, rpy_matrix([float(a) for a in j.rpy]),
                        np.array(j.origin_vector, dtype=float).ravel(), np.array(j.axis_vector, dtype=float).ravel(),
                        j.type == "revolute", rates[phi[own.index(j.name)]]) for j in ordered]
        self.moved = {j.name: [k for k, link in enumerate(self.links) if j in system.chain(link.name)]
                      for j in system.joints}

    def _q(self, theta):
        q = np.zeros(len(self.index))
        q[self.index] = theta
        return q

    def terms(self, theta, theta_dot, base=None, forward: bool = True) -> dict:
        M, Cqd, g, f_np = self.model.terms(self._q(theta), self._q(theta_dot), self.p, self.u)
        i = self.index
        M, Cqd, g, f_np = M[np.ix_(i, i)], Cqd[i], g[i], f_np[i]
        out = {"M": M, "bias": Cqd + g}
        if forward:
            try:
                out["qdd"] = np.linalg.solve(M, f_np - Cqd - g)
            except np.linalg.LinAlgError:   # singular M: no forward dynamics (the reference's is not finite)
                out["qdd"] = np.full(len(i), np.nan)
            out["Cqd"], out["g"] = Cqd, g
        return out

    def mass_and_bias(self, theta, theta_dot, base=None):
        t = self.terms(theta, theta_dot, forward=False)
        return t["M"], t["bias"]

    def subtree_parts(self, theta, base=None) -> dict[str, list]:
        """Per joint, ``(mass, centre of mass, inertia tensor about it)`` of every body it moves, world axes: the
        link frames chained in float64 from the model's joints (4.21), ``H = H(origin, rpy) · H_axis(θ)``."""
        from harness.files.from_urdf import axis_rotation

        q = self._q(theta)
        frames = {WORLD: (np.eye(3), np.zeros(3))}
        for parent, child, R_rpy, origin, axis, revolute, k in self._chain:
            R, d = frames[parent]
            R_off, d_off = R @ R_rpy, d + R @ origin
            frames[child] = ((R_off @ axis_rotation(axis, q[k]), d_off) if revolute
                             else (R_off, d_off + R_off @ axis * q[k]))
        world = []
        for link, (m, c, I) in zip(self.links, self.parts):
            R, d = frames[link.name]
            world.append((m, R @ c + d, R @ I @ R.T))
        return {name: [world[k] for k in self.moved[name]] for name in self.joints}

    def body_names(self) -> list[str]:
        return [link.name for link in self.system.links]

    @property
    def gravity(self):
        return self._gravity

    @property
    def dofs(self) -> int:
        return len(self.index)

    def loaded_facts(self) -> dict:
        d = self.derivation
        return {"bodies": len(self.system.links), "nq": len(self.index), "nv": len(self.index),
                "mass": round(sum(m for m, _, _ in self.parts), 9),
                "derivation": "body by body (Jacobians, derive._per_body)" if self.per_body
                else "M (5.21), Christoffel symbols of M (5.95)",
                "from_cache": d.from_cache, "derive_seconds": round(d.seconds, 2)}
