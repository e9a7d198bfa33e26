"""Trajectory checks of a scene, with their tolerances and reasons (one place).

* **reference**: our symbolic model, DOP853 at ``rtol = atol = 1e-12``, confirmed by Radau at the same
  tolerance (an implicit method of another family): they must agree to ``REFERENCE_TOL = 1e-8`` of the
  state's scale (global error of both, grown over the horizon; scenes are chosen non-chaotic over it).
* **engines**: Pinocchio's and MuJoCo's forward dynamics integrated by DOP853 at ``rtol = atol = 1e-10``
  must stay within ``ENGINE_TOL = 1e-6`` of the reference: the per-step tolerance 1e-10 grows over a few
  hundred steps and a few periods by at most ~1e4 for the (non-chaotic) scenes.
* **MuJoCo's own RK4** (``mj_step``, where the map is the identity and no external load is applied): its
  global error is O(dt⁴); at ``dt`` and ``dt/2`` the error must fall by at least 8 (order ≥ 3) unless both are
  already at round-off (< 1e-10), and be below ``ENGINE_TOL`` at ``dt/2``. MuJoCo holds ``ctrl`` constant over
  a step (zero-order hold), so with an input that varies within steps the error is O(dt): there the error
  must fall by at least 1.8 (order ≥ 0.85) and is reported, not bounded.
* **invariants**: a conservative scene keeps ``E = T + V`` within ``INVARIANT_TOL = 1e-8`` of its scale;
  otherwise the power balance ``E(t) − E(0) = ∫ q̇ᵀ f_np dt`` (3.101) holds to the same tolerance.
* **pruning**: the scene run with every effect of the system switched on but idle (its coefficients zero)
  gives the same trajectory (``ENGINE_TOL``); the time ratio idle/pruned is reported.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from harness.compile import compiled
from harness.model import Damper, Gravity, JointDamper, JointSpring, Spring, System
from harness.scenes import Scene, effects_of, pruned
from harness import simulate as sim

REFERENCE_TOL = 1e-8
ENGINE_TOL = 1e-6
INVARIANT_TOL = 1e-8


@dataclass
class SceneResult:
    system: str
    scene: str
    checks: list = field(default_factory=list)     # (check, source, error, tolerance)
    notes: dict = field(default_factory=dict)
    trajectories: dict = field(default_factory=dict)

    def add(self, check, source, error, tolerance):
        self.checks.append((check, source, float(error), float(tolerance)))

    @property
    def passed(self) -> bool:
        return all(e <= tol for _, _, e, tol in self.checks)


def _energy_balance(system: System, scene: Scene) -> tuple[float, float]:
    """Largest ``|E(t) − E(0) − W(t)|`` relative to the energy scale, with ``Ẇ = q̇ᵀ f_np`` integrated
    alongside the motion (DOP853, 1e-12)."""
    s = pruned(system, scene.effects)
    c = compiled(s)
    params = {**system.default_parameters(), **scene.params}
    p = np.array([params[x.name] for x in s.parameters])
    n = len(s.q)

    def rhs(t, y):
        q, qd = y[:n], y[n:2 * n]
        u = scene.u(t, s)
        power = float(qd @ c.generalized_forces(q, qd, p, u))
        return np.concatenate([qd, c.forward_dynamics(q, qd, p, u), [power]])

    y0 = np.concatenate([scene.q0, scene.qd0, [0.0]])
    _, ys, _ = sim.solve_piecewise(rhs, scene, y0, "DOP853", 1e-12, 1e-12, sim.sample_times(scene))
    zeros = np.zeros(len(s.u))
    energy = np.array([float(c("T", y[:n], y[n:2 * n], p, zeros)) + float(c("V", y[:n], y[n:2 * n], p, zeros))
                       for y in ys.T])
    work = ys[2 * n]
    kinetic = [abs(float(c("T", y[:n], y[n:2 * n], p, zeros))) for y in ys.T]
    scale = max(1e-300, float(np.max(np.abs(energy - energy[0]))), float(np.max(kinetic)), float(np.max(np.abs(work))))
    return float(np.max(np.abs(energy - energy[0] - work))) / scale, scale


def idle_parameters(system: System, scene: Scene) -> dict | None:
    """Parameter values that make every effect the scene does not call for idle (its coefficients zero);
    None when a coefficient is also used elsewhere in the model (it cannot be zeroed alone)."""
    absent = effects_of(system) - set(scene.effects)
    coefficients: set = set()
    kept: set = set()
    for f in system.forces:
        values = [getattr(f, a) for a in ("stiffness", "damping") if hasattr(f, a)]
        kind = {Spring: "springs", JointSpring: "springs", Damper: "dampers", JointDamper: "dampers"}.get(type(f))
        if kind is None:
            continue
        (coefficients if kind in absent else kept).update(*(sp.sympify(v).free_symbols for v in values))
    if "gravity" in absent and isinstance(system.gravity, Gravity):
        coefficients |= sp.sympify(system.gravity.g).free_symbols
    if absent - {"springs", "dampers", "gravity", "inputs"}:
        return None  # external loads: no single coefficient switches them off
    used = set()
    for link in system.links:
        used |= set().union(*(sp.sympify(v).free_symbols for v in [link.mass, *link.com, *link.inertia.matrix]))
    for j in system.joints:
        used |= set().union(*(sp.sympify(v).free_symbols for v in [*j.origin, *j.rpy, j.armature]))
    if coefficients & (used | kept):
        return None
    params = {**system.default_parameters(), **scene.params}
    params.update({s.name: 0.0 for s in coefficients})
    return params


def _symbolic_with(system: System, scene: Scene, params: dict, prune: bool) -> sim.Trajectory:
    s = pruned(system, scene.effects) if prune else system
    c = compiled(s)
    p = np.array([params[x.name] for x in s.parameters])
    n = len(s.q)

    def rhs(t, y):
        return np.concatenate([y[n:], c.forward_dynamics(y[:n], y[n:], p, scene.u(t, s))])

    start = time.perf_counter()
    t, y, nfev = sim.solve_piecewise(rhs, scene, np.concatenate([scene.q0, scene.qd0]), "DOP853", 1e-10, 1e-10,
                                     sim.sample_times(scene))
    return sim.Trajectory("symbolic", t, y[:n].T, y[n:].T, time.perf_counter() - start, nfev)


def run_scene(system: System, scene: Scene, engines=("pinocchio", "mujoco"), mujoco_dt: float | None = None) -> SceneResult:
    result = SceneResult(system.name, scene.name)
    ref = sim.integrate(system, scene, "symbolic", **{k: v for k, v in sim.REFERENCE.items() if k != "method"})
    result.trajectories["reference"] = ref
    radau = sim.integrate(system, scene, "symbolic", method="Radau", rtol=1e-12, atol=1e-12)
    result.add("reference confirmed (Radau vs DOP853)", "symbolic", sim.max_error(radau, ref), REFERENCE_TOL)
    for engine in engines:
        if system.engine_note(engine):
            result.notes[engine] = system.engine_note(engine)
            continue
        tr = sim.integrate(system, scene, engine, rtol=1e-10, atol=1e-10)
        result.trajectories[engine] = tr
        result.add("trajectory (DOP853 1e-10)", engine, sim.max_error(tr, ref), ENGINE_TOL)
    if "mujoco" in engines and not system.engine_note("mujoco"):
        dt = mujoco_dt or scene.horizon / 4000
        try:
            coarse, fine = sim.mujoco_native(system, scene, dt), sim.mujoco_native(system, scene, dt / 2)
        except ValueError as why:
            result.notes["mujoco mj_step"] = str(why)
        else:
            e1, e2 = sim.max_error(coarse, ref), sim.max_error(fine, ref)
            result.trajectories["mujoco mj_step"] = fine
            ratio = e1 / e2 if e2 > 0 else np.inf
            result.notes["mj_step RK4 error ratio dt -> dt/2"] = ratio
            if scene.inputs_vary_within_steps:
                result.notes[f"mj_step RK4 error at dt={dt / 2:g} (zero-order-hold input)"] = e2
                result.add("mj_step RK4 convergence, zero-order-hold input (ratio >= 1.8)", "mujoco",
                           0.0 if ratio >= 1.8 else 1.0, 0.0)
            else:
                result.add(f"mj_step RK4 dt={dt / 2:g}", "mujoco", e2, ENGINE_TOL)
                result.add("mj_step RK4 convergence (error ratio >= 8)", "mujoco",
                           0.0 if (ratio >= 8 or max(e1, e2) < 1e-10) else 1.0, 0.0)
    balance, _ = _energy_balance(system, scene)
    result.add("energy constant" if scene.conservative else "power balance (3.101)", "symbolic", balance,
               INVARIANT_TOL)
    idle = idle_parameters(system, scene)
    if idle is None:
        result.notes["pruning"] = "not measurable: a coefficient of an absent effect is used elsewhere"
    else:
        base = {**system.default_parameters(), **scene.params}
        lean = _symbolic_with(system, scene, base, prune=True)
        full = _symbolic_with(system, scene, idle, prune=False)
        result.add("pruned = all effects on but idle", "symbolic", sim.max_error(full, lean), ENGINE_TOL)
        result.notes["pruning time ratio (idle / pruned), symbolic"] = full.seconds / max(lean.seconds, 1e-12)
    return result
