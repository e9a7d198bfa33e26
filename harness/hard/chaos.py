"""Chaotic motion: the double pendulum (planar manipulator, gravity only) and the planar robot (A.123).

Pointwise comparison is only meaningful over a horizon on which a discrepancy of the size of the integration
error cannot grow beyond the comparison's tolerance. The horizon is *measured*, not guessed: the reference is
run again from a state perturbed by ``DELTA0`` (the size of the engines' integration error, rtol 1e-10) and the
justified horizon ``T*`` is the first time the two runs differ by ``ENGINE_TOL``; the largest Lyapunov
exponent is the slope of ``log |δ(t)|`` fitted on ``[0, T*]`` (``T* ≈ ln(ENGINE_TOL/DELTA0)/λ``). Beyond ``T*``
only invariants are compared: ``E = T + V`` of each source over the long horizon.
"""

from __future__ import annotations

import numpy as np

from harness.checks import Bound
from harness.hard.common import CaseResult, ENGINES, SOURCES, energy_function, finite, scene_for, second_order, solve
from harness.scenes.simulate import Dynamics

ENGINE_TOL = 1e-6
DELTA0 = 1e-10
HORIZON = Bound("justified horizon", ENGINE_TOL, "T* is the first time a perturbation of DELTA0 (the size of the "
                "engines' integration error) grows to ENGINE_TOL: an engine's error reaches the bound's order near T* "
                "by construction, not by round-off", derived=True)
ENERGY_TOL = {"symbolic": 1e-9, "pinocchio": 1e-7, "mujoco": 1e-7}   # reference 1e-12; engines 1e-10 per step


def _chaos_case(catalogue, case_id, title, system_name, q0, horizon, quick) -> CaseResult:
    r = CaseResult(
        case_id, title, [system_name], "short justified horizon + invariants",
        "The motion is chaotic: any difference (round-off, the engines' integration error 1e-10) grows like "
        "e^(λ t); pointwise comparison over a long horizon measures the chaos, not the model (errors of order 1).",
        f"Pointwise comparison only up to the measured horizon T* on which a perturbation of {DELTA0:g} stays below "
        f"{ENGINE_TOL:g} (Lyapunov-time argument, exponent fitted); over the long horizon only the energy "
        "E = T + V is compared (conservative scene).")
    system = catalogue.get(system_name)
    scene = scene_for("chaos", {"gravity"})
    T = horizon / 2 if quick else horizon
    n = len(system.coordinates)
    t_eval = np.linspace(0.0, T, int(200 * T) + 1)
    y0 = np.concatenate([q0, np.zeros(n)])
    ref, _ = solve(second_order(Dynamics(system, scene, "symbolic"), n), (0, T), y0, t_eval=t_eval)
    y1 = y0.copy()
    y1[0] += DELTA0
    pert, _ = solve(second_order(Dynamics(system, scene, "symbolic"), n), (0, T), y1, t_eval=t_eval)
    sep = np.max(np.abs(pert.y - ref.y), axis=0)
    over = np.nonzero(sep > ENGINE_TOL)[0]
    t_star = float(t_eval[over[0]]) if over.size else T
    window = (t_eval > 0.2) & (t_eval <= t_star)
    lam = float(np.polyfit(t_eval[window], np.log(np.maximum(sep[window], 1e-300)), 1)[0]) if window.sum() > 3 else 0.0
    r.numbers["largest Lyapunov exponent (fit) [1/s]"] = lam
    r.numbers["justified horizon T* [s]"] = t_star
    r.numbers["ln(ENGINE_TOL/DELTA0)/lambda [s]"] = float(np.log(ENGINE_TOL / DELTA0) / lam) if lam > 0 else None
    r.check("the motion is chaotic (T* shorter than the long horizon)", "symbolic", 0.0 if t_star < T else 1.0, 0.0)
    energy = energy_function(system, scene.effects, {})
    E0 = energy(ref.y[:n, 0], ref.y[n:, 0])
    scale = max(abs(E0), max(abs(energy(ref.y[:n, k], np.zeros(n)) - E0) for k in range(0, len(t_eval), 10)))
    long_errors, runs = {}, {"symbolic": ref.y}
    for source in SOURCES:
        tol = 1e-12 if source == "symbolic" else 1e-10
        y = ref.y if source == "symbolic" else solve(second_order(Dynamics(system, scene, source), n), (0, T), y0,
                                                     rtol=tol, atol=tol, t_eval=t_eval)[0].y
        runs[source] = y
        E = np.array([energy(y[:n, k], y[n:, k]) for k in range(0, y.shape[1], 5)])
        r.check(f"energy constant over {T:g} s (DOP853 {tol:g})", source, np.max(np.abs(E - E0)) / scale,
                ENERGY_TOL[source], "per-step tolerance grown over the long horizon")
        if source != "symbolic":
            short = t_eval <= t_star
            r.check(f"pointwise up to T* = {t_star:.3g} s", source,
                    float(np.max(np.abs(y[:, short] - ref.y[:, short])))
                    / max(1.0, float(np.max(np.abs(ref.y[:, short]))))
                    if finite(y) else np.inf, ENGINE_TOL, derived=HORIZON)
            long_errors[source] = float(np.max(np.abs(y - ref.y))) / max(1.0, float(np.max(np.abs(ref.y))))
    r.numbers["pointwise error over the long horizon (not a check)"] = long_errors
    r.naive = {"what": f"pointwise comparison over the long horizon {T:g} s",
               "metric": "largest relative state difference of an engine (of order 1: chaos, not error)",
               "value": max(long_errors.values())}
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(10, 3.6))
    ax[0].semilogy(t_eval, np.maximum(sep, 1e-17), label=f"perturbation {DELTA0:g}")
    for source in ENGINES:
        ax[0].semilogy(t_eval, np.maximum(np.max(np.abs(runs[source] - ref.y), axis=0), 1e-17), label=source)
    ax[0].axvline(t_star, color="k", ls=":", label="T*")
    ax[0].axhline(ENGINE_TOL, color="grey", ls=":")
    ax[0].set_xlabel("t [s]")
    ax[0].set_title(f"difference to the reference (λ ≈ {lam:.2f} 1/s)")
    ax[0].legend(fontsize=8)
    for source in SOURCES:
        y = runs[source]
        E = [energy(y[:n, k], y[n:, k]) for k in range(0, y.shape[1], 5)]
        ax[1].semilogy(t_eval[::5], np.maximum(np.abs(np.array(E) - E0) / scale, 1e-17), label=source)
    ax[1].set_title("energy error |E - E0| / scale")
    ax[1].set_xlabel("t [s]")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    r.figure = fig
    return r


def double_pendulum(catalogue, quick: bool = False) -> CaseResult:
    return _chaos_case(catalogue, "double_pendulum_chaos", "Double pendulum (planar manipulator, gravity only): chaos",
                       "planar_manipulator", np.array([2.0, 1.5]), 20.0, quick)


def planar_robot(catalogue, quick: bool = False) -> CaseResult:
    return _chaos_case(catalogue, "planar_robot_chaos", "Planar robot (A.123), gravity only: chaos", "planar_robot",
                       np.array([1.2, 2.5, -2.0]), 20.0, quick)
