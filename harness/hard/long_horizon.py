"""Long horizons: 10⁴ periods of the pendulum (Example 3.12), symplectic against non-symplectic integration.

A symplectic method (Störmer–Verlet; MuJoCo's default ``Euler``, which is semi-implicit, i.e. symplectic Euler)
keeps the energy error in a band of width O(hᵖ) for exponentially long times; a non-symplectic method
(RK45 with error control, MuJoCo's RK4) lets it drift secularly. The measure of drift is the *growth*: the
largest energy error over the last tenth of the run divided by that over the first tenth (≈ 1 for a band,
≈ 10 for a linear drift).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.special import ellipk

from harness.checks import Bound
from harness.derivation.compile import compiled
from harness.hard.common import CaseResult, solve
from harness.modeling.scenes import Scene
from harness.scenes.simulate import Dynamics

GROWTH_TOL = 1.5   # a band: the last tenth's largest error at most 1.5× the first tenth's (sampling scatter)
DRIFT = "no secular drift (growth - 1)"
BAND = Bound("symplectic energy band", 1.0, "a symplectic method of order p keeps the energy error within "
             "C (h omega0)^p over exponentially long times (backward error analysis), C of order 1: the bound is "
             "(h omega0)^p, which the band approaches by its nature, not by round-off", derived=True)
"""Checked as growth − 1 ≤ GROWTH_TOL − 1 (:func:`_excess`): a bounded band's growth is 1, not 0, so that its ratio to
the bound is the margin (as growth ≤ 1.5, Pinocchio's 1.0014 read as 0.67 of its bound)."""


def _excess(err) -> float:
    """How much the error band grew over the run (:func:`_growth` − 1, at least 0): a secular drift's is ~10."""
    return max(0.0, _growth(err) - 1)


def _growth(err):
    k = max(1, len(err) // 10)
    return float(np.max(err[-k:]) / max(np.max(err[:k]), 1e-300))


def verlet(accel, q0, v0, h, steps, sample_every):
    """Störmer–Verlet (velocity form): symplectic, second order; returns sampled (k, q, v)."""
    q, v, a = float(q0), float(v0), accel(q0)
    out = []
    for k in range(steps + 1):
        if k % sample_every == 0:
            out.append((k, q, v))
        v_half = v + 0.5 * h * a
        q = q + h * v_half
        a = accel(q)
        v = v_half + 0.5 * h * a
    return np.array(out)


def pendulum_energy_drift(catalogue, quick: bool = False) -> CaseResult:
    periods = 1000 if quick else 10000
    r = CaseResult(
        "pendulum_long_horizon", f"Pendulum over {periods} periods: energy drift, symplectic vs non-symplectic",
        ["pendulum"], "symplectic integrator",
        "An error-controlled non-symplectic method (RK45) makes a small energy error every period and it adds up: "
        "the energy drifts secularly over long horizons (MuJoCo's RK4 likewise).",
        "Störmer–Verlet (symplectic) with h = T/64 on the symbolic model and on Pinocchio's forward dynamics, and "
        "MuJoCo's semi-implicit Euler (symplectic Euler) at the same step: the energy error stays in a band "
        "(growth ≤ 1.5) whose width is O((h ω0)²) resp. O(h ω0).")
    system = catalogue.get("pendulum")
    phi0 = 1.0472
    g, l = 9.81, 1.0
    omega0 = math.sqrt(g / l)
    period = 4 * math.sqrt(l / g) * float(ellipk(math.sin(phi0 / 2) ** 2))
    h = period / 64
    steps = 64 * periods
    # the swing and what acts in it, one period long: this case steps it over ``periods`` periods itself (a scene's
    # horizon is bounded, harness.limits.SCENE_HORIZON; 10⁴ periods are 21 529 s)
    scene = Scene("long", "60° swing, one period (stepped here over many)", (phi0,), (0.0,), period,
                  frozenset({"gravity"}))
    c = compiled(Dynamics(system, scene, "symbolic").system)
    p = np.array([1.0, l, g])
    E_scale = g * l * (1 - math.cos(phi0))   # m g l (1 - cos phi0), m = 1

    def energy(q, v):
        return 0.5 * l * l * v * v + g * l * (1 - math.cos(q))

    def energy_error(qs, vs):
        return np.abs(np.array([energy(a, b) for a, b in zip(qs, vs)]) - E_scale) / E_scale

    results = {}
    # symbolic Verlet: q̈ = -g(q)/M(q), the lecture's derivation
    def accel(q):
        return -float(c("g", np.array([q]), p=p)[0, 0]) / float(c("M", np.array([q]), p=p)[0, 0])
    sym = verlet(accel, phi0, 0.0, h, steps, 61)
    err = energy_error(sym[:, 1], sym[:, 2])
    results["symbolic Verlet"] = {"max": float(np.max(err)), "growth": _growth(err), "final": float(err[-1])}
    r.check("Verlet energy error band (symbolic)", "symbolic", float(np.max(err)), (h * omega0) ** 2,
            "O((h omega0)^2) for a second-order symplectic method", derived=BAND)
    r.check(f"Verlet: {DRIFT}", "symbolic", _excess(err), GROWTH_TOL - 1)
    # Pinocchio Verlet over a tenth of the periods (its forward dynamics costs ~0.1 ms a call)
    pin = Dynamics(system, scene, "pinocchio")
    steps_pin = steps // 10
    pv = verlet(lambda q: float(pin(0.0, np.array([q]), np.array([0.0]))[0]), phi0, 0.0, h, steps_pin, 61)
    err_pin = energy_error(pv[:, 1], pv[:, 2])
    results[f"pinocchio Verlet ({periods // 10} periods)"] = {"max": float(np.max(err_pin)),
                                                              "growth": _growth(err_pin)}
    r.check(f"Verlet energy error band (Pinocchio, {periods // 10} periods)", "pinocchio", float(np.max(err_pin)),
            (h * omega0) ** 2, "O((h omega0)^2)", derived=BAND)
    r.check(f"Verlet: {DRIFT}", "pinocchio", _excess(err_pin), GROWTH_TOL - 1)
    # MuJoCo: its own integrators at the same step
    mj = {}
    for integrator in ("Euler", "RK4"):
        ks, qs, vs, seconds = mujoco_steps(system, scene, h, steps, integrator, 61)
        e = energy_error(qs, vs)
        mj[integrator] = (ks, e)
        results[f"mujoco mj_step {integrator}"] = {"max": float(np.max(e)), "growth": _growth(e[1:]),
                                                   "final": float(e[-1]), "seconds": seconds}
        if integrator == "Euler":
            r.check("semi-implicit Euler energy error band (MuJoCo)", "mujoco", float(np.max(e)), h * omega0,
                    "O(h omega0) for a first-order symplectic method", derived=BAND)
            r.check(f"semi-implicit Euler: {DRIFT}", "mujoco", _excess(e[1:]), GROWTH_TOL - 1)
    # naive: RK45 with error control (non-symplectic)
    t_eval = np.linspace(0.0, steps * h, 4001)
    sol, cpu = solve(lambda t, y: [y[1], accel(y[0])], (0.0, steps * h), [phi0, 0.0], "RK45", 1e-6, 1e-9,
                     t_eval=t_eval)
    err_rk = energy_error(sol.y[0], sol.y[1])
    results["symbolic RK45 rtol 1e-6"] = {"max": float(np.max(err_rk)), "growth": _growth(err_rk),
                                          "final": float(err_rk[-1]), "cpu": cpu, "evaluations": sol.nfev}
    r.numbers["energy error |E - E0| / (m g l (1 - cos phi0))"] = results
    r.numbers["period [s]"] = period
    r.numbers["step h [s]"] = h
    r.naive = {"what": f"RK45 (rtol 1e-6) over {periods} periods", "metric": "final relative energy error",
               "value": float(err_rk[-1])}
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(8, 3.6))
    ax.loglog(*_envelope(sym[1:, 0] * h / period, err[1:]), label="Verlet (symbolic)")
    ax.loglog(*_envelope(sol.t[1:] / period, err_rk[1:]), label="RK45 rtol 1e-6")
    for integrator, (ks, e) in mj.items():
        ax.loglog(*_envelope(ks[1:] * h / period, e[1:]), label=f"MuJoCo {integrator}, h = T/64")
    ax.set_xlabel("periods")
    ax.set_ylabel("|E - E0| / E")
    ax.legend(fontsize=8)
    ax.set_title("energy error over the periods")
    fig.tight_layout()
    r.figure = fig
    return r


def mujoco_steps(system, scene, h, steps, integrator, sample_every):
    """MuJoCo's own ``mj_step`` at step ``h`` (identity map: tree coordinates are the lecture's), sampled every
    ``sample_every`` steps (not a divisor of the 64 steps of a period: the samples sweep the phase)."""
    import time

    from harness.engines.mujoco_engine import Options
    model = Dynamics(system, scene, "mujoco").model
    model.configure(Options(timestep=h, integrator=integrator))
    model.reset()
    model.set_state(scene.q0, scene.qd0)
    start = time.perf_counter()
    out = model.rollout(steps, sample_every,
                        lambda k: (k, float(model.theta()[0]), float(model.theta_dot()[0])),
                        check=f"{system.name} {integrator}")
    ks, qs, vs = (np.array(x) for x in zip(*out))
    return ks, qs, vs, time.perf_counter() - start


def _envelope(x, y, bins: int = 400):
    """The largest ``y`` in each of ``bins`` log-spaced ``x`` intervals: the error band as plotted on log axes,
    from ~10⁶ samples (a figure of every sample is megabytes of SVG)."""
    x, y = np.asarray(x, dtype=float), np.maximum(np.asarray(y, dtype=float), 1e-17)
    if len(x) <= 2 * bins:
        return x, y
    edges = np.searchsorted(x, np.geomspace(x[0], x[-1], bins + 1))
    keep = [a + int(np.argmax(y[a:b])) for a, b in zip(edges[:-1], edges[1:]) if b > a]
    return x[keep], y[keep]
