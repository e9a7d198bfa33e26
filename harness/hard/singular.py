"""Singular coordinates: the spherical pendulum through its pole (5.81), the centrifugal governor at alpha → 0
(A.67), the toggle press at its dead point (A.100), the tower crane with its rope reeled in (s_5 → 0)."""

from __future__ import annotations

import math

import numpy as np

from harness.derivation.compile import compiled
from harness.errors import HarnessError, ModelError
from harness.hard.charts import integrate_charts, pendulum_charts, toggle_press_chart_phi2, Chart, SWITCH
from harness.hard.common import (CaseResult, ENGINES, SOURCES, Terms, finite, scene_for, second_order, solve)
from harness.hard.common import reference_error as _rel
from harness.scenes.simulate import Dynamics

ENGINE_TOL = 1e-6     # engines' forward dynamics integrated at rtol = atol = 1e-10 (as harness/scenes/trajectories.py)
REFERENCE_TOL = 1e-8  # the reference (DOP853 1e-12) confirmed by Radau 1e-12 (as harness/scenes/trajectories.py)
INVARIANT_TOL = 1e-8  # energy / momentum of a conservative motion, relative to their scale


def _raises_singularity(fn, expect: str) -> tuple[float, str]:
    """0 when ``fn()`` raises a ModelError whose message contains ``expect``; 1 otherwise (with what it gave)."""
    try:
        with np.errstate(all="ignore"):
            out = fn()
    except ModelError as why:
        return (0.0 if expect in str(why) else 1.0), str(why)
    return 1.0, f"no error; returned {np.asarray(out).tolist()}"


def _naive_solve(system, scene, q0, qd0, horizon, t_eval, source="symbolic", guarded=False, rtol=1e-10):
    """The naive run: one chart, DOP853 at ``rtol`` (as the engines are run), ``M`` factorized as it comes
    (``guarded=False``: no singularity check; what the forward dynamics did before the check)."""
    n = len(system.coordinates)
    if source == "symbolic" and not guarded:
        s = Dynamics(system, scene, "symbolic")
        c, p = s.c, s.p

        def f(t, q, qd):
            u = scene.u(t, s.system)
            rhs = c.generalized_forces(q, qd, p, u) - c.coriolis_matrix(q, qd, p) @ qd - c.potential_forces(q, p)
            return np.linalg.solve(c.mass_matrix(q, p), rhs)
    else:
        f = Dynamics(system, scene, source)
    try:
        with np.errstate(all="ignore"):
            sol, cpu = solve(second_order(f, n), (0.0, horizon), np.concatenate([q0, qd0]), "DOP853", rtol, rtol,
                             t_eval=t_eval)
        return sol, None
    except (HarnessError, np.linalg.LinAlgError, RuntimeError, ValueError) as why:
        return None, f"{type(why).__name__}: {why}"


# ----------------------------------------------------------------------------- spherical pendulum
def spherical_pendulum_pole(catalogue, quick: bool = False) -> CaseResult:
    r = CaseResult(
        "spherical_pendulum_pole", "Spherical pendulum through and near the pole theta = 0", ["spherical_pendulum"],
        "chart switch",
        "(5.81d) divides by sin²(theta): near the pole the azimuth rate phi_dot = L/(m l² sin² theta) explodes "
        "(L the conserved angular momentum about the vertical); an adaptive integrator in (theta, phi) needs ever "
        "smaller steps, and at sin² theta ≈ 1e-13 the solve of M q̈ = … returns round-off.",
        "Two spherical charts of the same pendulum, each its own System and tree for the engines: the lecture's "
        "(theta, phi) (pole at the bottom) and (psi, chi) (pole along e_z). The integration switches chart where "
        f"the regularity |sin theta| or |cos chi| falls to {SWITCH} (event location); the state is carried over "
        "through the bob's Cartesian position and velocity. Exactly at the pole the forward dynamics raises "
        "'coordinate singularity at theta = 0 in spherical_pendulum'.")
    charts = pendulum_charts(catalogue.get("spherical_pendulum"), 1.0)
    scene = scene_for("pole", {"gravity"})
    T = 4.0 if quick else 8.0
    t_eval = np.linspace(0.0, T, 401)
    q0 = np.array([0.6, 0.0])
    rates = (1e-3, 1e-5, 1e-7)
    hardest = rates[-1]
    ref_dyn = {c.name: Dynamics(c.system, scene, "symbolic") for c in charts}
    t, ref, switches, nfev, _ = integrate_charts(charts, ref_dyn, 0, q0, np.array([0.0, hardest]), T, t_eval)
    radau = integrate_charts(charts, ref_dyn, 0, q0, np.array([0.0, hardest]), T, t_eval, method="Radau")[1]
    r.check("reference confirmed (Radau vs DOP853, chart switch)", "symbolic", _rel(radau, ref), REFERENCE_TOL,
            "both at rtol = atol = 1e-12")
    energy = 0.5 * np.sum(ref[:, 3:] ** 2, axis=1) + 9.81 * ref[:, 1]      # per unit mass, l = 1
    momentum = ref[:, 2] * ref[:, 3] - ref[:, 0] * ref[:, 5]              # about e_y, per unit mass
    r.check("energy constant (chart switch)", "symbolic", np.ptp(energy) / 9.81, INVARIANT_TOL, "scale m g l")
    r.check("angular momentum about e_y constant", "symbolic", np.ptp(momentum) / math.sqrt(9.81), INVARIANT_TOL,
            "scale m l sqrt(g l)")
    r.numbers["switches"] = [(round(a, 6), b, c) for a, b, c in switches]
    r.numbers["nfev chart switch (symbolic, 1e-12)"] = nfev
    engine_runs = {}
    for source in ENGINES:
        dyn = {c.name: Dynamics(c.system, scene, source) for c in charts}
        te, x, sw, nf, cpu = integrate_charts(charts, dyn, 0, q0, np.array([0.0, hardest]), T, t_eval, rtol=1e-10,
                                             atol=1e-10)
        engine_runs[source] = x
        r.numbers["nfev chart switch (engines, 1e-10)"] = nf
        r.check("chart switch trajectory (DOP853 1e-10) vs reference", source, _rel(x, ref) if finite(x) else np.inf,
                ENGINE_TOL, "integrator error as in harness/scenes/trajectories.py")
    # naive: the lecture's chart only
    naive = {}
    for rate in rates:
        tr = integrate_charts(charts, ref_dyn, 0, q0, np.array([0.0, rate]), T, t_eval)[1]
        sol, failure = _naive_solve(charts[0].system, scene, q0, np.array([0.0, rate]), T, t_eval)
        if failure or sol is None or sol.status != 0:
            naive[rate] = {"failure": failure or sol.message}
            continue
        x = np.array([charts[0].to_common(y[:2], y[2:]) for y in sol.y.T])
        naive[rate] = {"nfev": sol.nfev, "error": _rel(x, tr[:len(x)]) if finite(x) else float("inf")}
    for source in () if quick else ENGINES:
        sol, failure = _naive_solve(charts[0].system, scene, q0, np.array([0.0, hardest]), T, t_eval, source=source)
        if failure or sol is None or sol.status != 0:
            naive[f"{source} {hardest:g}"] = {"failure": failure or sol.message}
        else:
            x = np.array([charts[0].to_common(y[:2], y[2:]) for y in sol.y.T])
            naive[f"{source} {hardest:g}"] = {"nfev": sol.nfev, "error": _rel(x, ref[:len(x)]) if finite(x) else
                                             float("inf")}
    r.numbers["naive (theta, phi) only, DOP853 1e-10, by initial phi_dot"] = {str(k): v for k, v in naive.items()}
    worst = naive[hardest]
    r.naive = {"what": f"integrating in (theta, phi) only, DOP853 at 1e-10, phi_dot(0) = {hardest:g} rad/s "
                       "(MuJoCo: see numbers)",
               "metric": "function evaluations relative to the chart switch (same accuracy)",
               "value": worst.get("nfev", float("inf")) / r.numbers["nfev chart switch (engines, 1e-10)"]}
    # exactly at the pole
    c = compiled(charts[0].system)
    p = np.array([1.0, 1.0, 9.81])
    value, message = _raises_singularity(lambda: c.forward_dynamics(np.array([0.0, 0.3]), np.array([0.5, 1.0]), p,
                                                                    np.zeros(1)), "coordinate singularity at theta = 0")
    r.check("clear error exactly at the pole (forward dynamics)", "symbolic", value, 0.0, message)
    r.numbers["error message at the pole"] = message
    at_pole = {}
    for source in ENGINES:
        d = Dynamics(charts[0].system, scene, source)
        with np.errstate(all="ignore"):
            try:
                at_pole[source] = np.asarray(d(0.0, np.array([0.0, 0.3]), np.array([0.5, 1.0]))).tolist()
            except Exception as why:  # noqa: BLE001 - what the engine does is the finding
                at_pole[source] = f"{type(why).__name__}: {why}"
    r.numbers["engines' q̈ exactly at the pole (no check; for the record)"] = at_pole
    r.figure = _pendulum_figure(t, ref, engine_runs, charts, scene, q0, hardest, T, t_eval)
    return r


def _pendulum_figure(t, ref, engine_runs, charts, scene, q0, rate, T, t_eval):
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(10, 3.6))
    theta = np.arccos(np.clip(-ref[:, 1], -1, 1))
    ax[0].semilogy(t, np.abs(np.sin(theta)), label="|sin theta| (lecture chart)")
    ax[0].axhline(SWITCH, color="k", ls=":", label="switch level")
    ax[0].set_xlabel("t [s]")
    ax[0].set_title(f"near the pole: phi_dot(0) = {rate:g} rad/s")
    ax[0].legend(fontsize=8)
    sol, failure = _naive_solve(charts[0].system, scene, q0, np.array([0.0, rate]), T, t_eval)
    if sol is not None and sol.y.size:
        x = np.array([charts[0].to_common(y[:2], y[2:]) for y in sol.y.T])
        ax[1].semilogy(sol.t, np.maximum(np.max(np.abs(x - ref[:len(x)]), axis=1), 1e-17), label="naive (theta, phi)")
    for source, x in engine_runs.items():
        ax[1].semilogy(t, np.maximum(np.max(np.abs(x - ref), axis=1), 1e-17), label=f"chart switch, {source}")
    ax[1].axhline(ENGINE_TOL, color="k", ls=":", label="bound")
    ax[1].set_xlabel("t [s]")
    ax[1].set_title("position error / l against the reference")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    return fig


# ----------------------------------------------------------------------------- governor
def governor_pole(catalogue, quick: bool = False) -> CaseResult:
    r = CaseResult(
        "governor_pole", "Centrifugal governor at alpha → 0", ["governor"], "reduction (conserved momentum)",
        "M = diag(2 m l² sin² alpha, 2 m l²) is singular at alpha = 0 (A.67a divides by sin² alpha): with the arms "
        "swinging through the axis phi_dot is 0/0, and near it phi_dot = p_phi/(2 m l² sin² alpha) explodes.",
        "With tau = 0 the angle phi is cyclic: p_phi = M_phiphi(alpha) phi_dot is conserved, phi_dot is eliminated "
        "(Routh's reduction, the argument behind (A.68), (A.69)) and only alpha is integrated, with "
        "alpha_ddot = (f - C q̇ - g)_alpha / M_alphaalpha taken from each source's M, C q̇, g (never factorizing "
        "the singular M; M is diagonal, checked). Regular through alpha = 0 for p_phi = 0 and, for p_phi != 0, "
        "kept off the axis by the centrifugal barrier.")
    system = catalogue.get("governor")
    scene = scene_for("pole", {"gravity"})
    T = 3.0 if quick else 6.0
    t_eval = np.linspace(0.0, T, 301)
    alpha0 = 0.5
    RATES = (0.0, 1e-3)
    nfev_reduced = {}
    c = compiled(system)
    p = np.array([system.default_parameters()[x.name] for x in system.parameters])

    def reduced(source, momentum):
        d = Terms(system, scene, source)

        def rhs(t, y):
            phi, alpha, alpha_dot = y
            m_pp = c.mass_matrix(np.array([phi, alpha]), p)[0, 0]
            phi_dot = momentum / m_pp if momentum else 0.0
            M, Cqd, g, f = d.terms(t, np.array([phi, alpha]), np.array([phi_dot, alpha_dot]))
            return [phi_dot, alpha_dot, (f[1] - Cqd[1] - g[1]) / M[1, 1]]
        return rhs

    results = {}
    for rate in RATES:
        momentum = c.mass_matrix(np.array([0.0, alpha0]), p)[0, 0] * rate
        ref, _ = solve(reduced("symbolic", momentum), (0, T), [0.0, alpha0, 0.0], t_eval=t_eval)
        radau, _ = solve(reduced("symbolic", momentum), (0, T), [0.0, alpha0, 0.0], "Radau", t_eval=t_eval)
        r.check(f"reference confirmed (Radau vs DOP853), phi_dot(0) = {rate:g}", "symbolic",
                _rel(radau.y[1:], ref.y[1:]), REFERENCE_TOL, "alpha, alpha_dot; rtol = atol = 1e-12")
        energy = [float(c("T", np.array([a, b]), np.array([momentum / c.mass_matrix(np.array([a, b]), p)[0, 0]
                                                         if momentum else 0.0, ad]), p))
                  + float(c("V", np.array([a, b]), p=p)) for a, b, ad in ref.y.T]
        r.check(f"energy constant (reduced), phi_dot(0) = {rate:g}", "symbolic",
                np.ptp(energy) / (2 * 2.0 * 9.81 * 0.5), INVARIANT_TOL, "scale 2 m g l")
        results[rate] = ref
        nfev_reduced[str(rate)] = ref.nfev
        for source in ENGINES:
            try:
                sol, _ = solve(reduced(source, momentum), (0, T), [0.0, alpha0, 0.0], rtol=1e-10, atol=1e-10,
                               t_eval=t_eval)
            except HarnessError as why:
                r.notes.append(f"{source}, phi_dot(0) = {rate:g}: {why}")
                r.check(f"reduced trajectory (DOP853 1e-10), phi_dot(0) = {rate:g}", source, np.inf, ENGINE_TOL,
                        str(why)[:200])
                continue
            r.check(f"reduced trajectory (DOP853 1e-10), phi_dot(0) = {rate:g}", source,
                    _rel(sol.y[1:], ref.y[1:]) if sol.success and finite(sol.y) else np.inf, ENGINE_TOL,
                    "integrator error as in harness/scenes/trajectories.py")
        r.numbers[f"smallest sampled |alpha|, phi_dot(0) = {rate:g}"] = float(np.min(np.abs(ref.y[1])))
    M0 = c.mass_matrix(np.array([0.0, 0.3]), p)
    r.check("M diagonal (the reduction's premise)", "symbolic", abs(M0[0, 1]) / np.max(np.abs(M0)), 1e-15)
    naive = {}
    for rate in RATES:
        for source in SOURCES:
            sol, failure = _naive_solve(system, scene, np.array([0.0, alpha0]), np.array([rate, 0.0]), T, t_eval,
                                        source=source, guarded=source != "symbolic")
            if failure or sol is None or sol.status != 0:
                naive[f"{source}, phi_dot(0) = {rate:g}"] = {"failure": (failure or sol.message)[:200]}
                continue
            naive[f"{source}, phi_dot(0) = {rate:g}"] = {
                "nfev": sol.nfev, "alpha error": _rel(sol.y[1], results[rate].y[1][:sol.y.shape[1]])
                if finite(sol.y) else float("inf")}
    for source in ("symbolic", "mujoco"):
        sol, failure = _naive_solve(system, scene, np.array([0.0, alpha0]), np.array([1e-7, 0.0]), T, t_eval,
                                    source=source, guarded=True)
        naive[f"{source} (guarded), phi_dot(0) = 1e-07"] = (
            {"failure": (failure or sol.message)[:240]} if failure or sol is None or sol.status != 0 else
            {"nfev": sol.nfev})
    r.numbers["naive full (phi, alpha), DOP853 1e-10"] = naive
    r.numbers["nfev reduced (symbolic, 1e-12)"] = nfev_reduced
    r.naive = {"what": "integrating the full (phi, alpha) equations (A.67) past alpha ≈ 0, phi_dot(0) = 1e-3 rad/s "
                       "(at 1e-7 rad/s: see numbers)",
               "metric": "function evaluations of the full equations (DOP853 1e-10) / of the reduction (DOP853 1e-12)",
               "value": naive["symbolic, phi_dot(0) = 0.001"].get("nfev", np.inf) / nfev_reduced[str(RATES[-1])]}
    value, message = _raises_singularity(lambda: c.forward_dynamics(np.array([0.0, 0.0]), np.array([1.0, 0.5]), p,
                                                                    np.zeros(1)), "coordinate singularity at")
    r.check("clear error at alpha = 0 (forward dynamics)", "symbolic", value, 0.0, message)
    r.numbers["error message at alpha = 0"] = message
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(10, 3.6))
    for rate, sol in results.items():
        ax[0].plot(sol.t, sol.y[1], label=f"reduced, phi_dot(0) = {rate:g}")
    ax[0].set_xlabel("t [s]")
    ax[0].set_ylabel("alpha [rad]")
    ax[0].legend(fontsize=8)
    ax[0].set_title("arms swinging through the axis")
    names = list(naive)
    vals = [naive[k].get("alpha error", np.nan) for k in names]
    ax[1].barh(range(len(names)), [v if np.isfinite(v) else 1.0 for v in vals],
               color=["tab:red" if not np.isfinite(v) else "tab:blue" for v in vals])
    ax[1].set_yticks(range(len(names)), names, fontsize=7)
    ax[1].set_xscale("log")
    ax[1].set_title("naive full equations: alpha error (red: failed)")
    fig.tight_layout()
    r.figure = fig
    return r


# ----------------------------------------------------------------------------- toggle press
def toggle_press_dead_point(catalogue, quick: bool = False) -> CaseResult:
    r = CaseResult(
        "toggle_press_dead_point", "Toggle press through the dead point of the arcsin map", ["toggle_press"],
        "chart switch",
        "phi_2 = arcsin(L_1/L_2 sin q) (A.100) and d phi_2/dq = L_1 cos q/(L_2 cos phi_2) blow up where leg 2 "
        "stands perpendicular to the guide (L_1 sin q = L_2; reachable when L_1 > L_2). There q_dot → 0 while leg 2 "
        "keeps turning: the lecture's coordinate q cannot describe the motion beyond (the arcsin leaves its "
        "domain, NaN). Full extension q = 0 itself is regular (d phi_2/dq = L_1/L_2), see models/toggle_press.py.",
        "Chart switch to phi_2 as the coordinate (q = arcsin(L_2/L_1 sin phi_2), regular for L_1 > L_2 away from "
        f"cos q = 0), located as the event |cos phi_2| = {SWITCH}; both engines simulate the phi_2 chart through "
        "its own nonlinear map theta = phi(phi_2). Beyond the map's domain the forward dynamics raises a clear "
        "error instead of returning NaN.")
    lecture = catalogue.get("toggle_press")
    chart_b = toggle_press_chart_phi2(lecture)
    params = {"L_1": 0.7, "L_2": 0.6}
    k = params["L_1"] / params["L_2"]
    scene = scene_for("dead_point", {"gravity"}, params=params)
    T = 1.0 if quick else 2.0
    t_eval = np.linspace(0.0, T, 401)

    def common_a(q, qd):
        s = k * math.sin(q[0])
        phi2 = math.asin(max(-1.0, min(1.0, s)))
        return np.array([q[0], phi2, qd[0], k * math.cos(q[0]) * qd[0] / max(math.cos(phi2), 1e-300)])

    def common_b(q, qd):
        qq = math.asin(math.sin(q[0]) / k)
        return np.array([qq, q[0], math.cos(q[0]) * qd[0] / (k * math.cos(qq)), qd[0]])

    charts = [Chart("q", lecture, lambda q: math.sqrt(max(0.0, 1 - (k * math.sin(q[0])) ** 2)), common_a,
                    lambda x: (np.array([x[0]]), np.array([x[2]]))),
              Chart("phi_2", chart_b, lambda q: math.sqrt(max(0.0, 1 - (math.sin(q[0]) / k) ** 2)), common_b,
                    lambda x: (np.array([x[1]]), np.array([x[3]])))]
    q0, qd0 = np.array([0.6]), np.array([0.0])
    dyn = {c.name: Dynamics(c.system, scene, "symbolic") for c in charts}
    t, ref, switches, nfev, _ = integrate_charts(charts, dyn, 0, q0, qd0, T, t_eval)
    r.numbers["switches"] = [(round(a, 6), b, c) for a, b, c in switches]
    r.check("the motion reaches the dead point (a chart switch happened)", "symbolic", 0.0 if switches else 1.0, 0.0)
    # an independent path: the phi_2 chart from the start
    x0 = common_a(q0, qd0)
    sol, _ = solve(second_order(dyn["phi_2"], 1), (0, T), [x0[1], x0[3]], t_eval=t_eval)
    direct = np.array([common_b(y[:1], y[1:]) for y in sol.y.T])
    r.check("reference confirmed (phi_2 chart throughout vs chart switch)", "symbolic", _rel(direct, ref),
            REFERENCE_TOL, "two paths at rtol = atol = 1e-12")
    energy_b = _energy(chart_b, scene)
    E = [energy_b(np.array([x[1]]), np.array([x[3]])) for x in ref]
    r.check("energy constant", "symbolic", np.ptp(E) / max(abs(np.max(E)), 1.0), INVARIANT_TOL, "scale max |E|")
    runs = {}
    for source in ENGINES:
        d = {c.name: Dynamics(c.system, scene, source) for c in charts}
        _, x, _, _, _ = integrate_charts(charts, d, 0, q0, qd0, T, t_eval, rtol=1e-10, atol=1e-10)
        runs[source] = x
        r.check("chart switch trajectory (DOP853 1e-10) vs reference", source, _rel(x, ref) if finite(x) else np.inf,
                ENGINE_TOL, "integrator error as in harness/scenes/trajectories.py")
    naive = {}
    for source in SOURCES:
        sol, failure = _naive_solve(lecture, scene, q0, qd0, T, t_eval, source=source, guarded=True)
        if failure or sol is None or sol.status != 0:
            naive[source] = {"failure": (failure or sol.message)[:240],
                             "reached t": float(sol.t[-1]) if sol is not None and sol.t.size else None}
        else:
            x = np.array([common_a(y[:1], y[1:]) for y in sol.y.T])
            naive[source] = {"error": _rel(x, ref[:len(x)]) if finite(x) else float("inf"), "nfev": sol.nfev}
    r.numbers["naive: the lecture's chart q only, DOP853 1e-10"] = naive
    r.naive = {"what": "integrating in the lecture's coordinate q through the dead point",
               "metric": "state error (inf: no result past the dead point)",
               "value": max((v.get("error", np.inf) for v in naive.values()), default=np.inf)}
    c = compiled(lecture)
    pv = np.array([{**lecture.default_parameters(), **params}[x.name] for x in lecture.parameters])
    value, message = _raises_singularity(lambda: c.forward_dynamics(np.array([1.2]), np.array([0.1]), pv,
                                                                    np.zeros(2)), "not finite at q = 1.2")
    r.check("clear error beyond the dead point (forward dynamics)", "symbolic", value, 0.0, message)
    r.numbers["error message beyond the dead point"] = message
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(10, 3.6))
    ax[0].plot(t, ref[:, 0], label="q (leg 1)")
    ax[0].plot(t, ref[:, 1], label="phi_2 (leg 2)")
    for a, *_ in switches:
        ax[0].axvline(a, color="k", ls=":")
    ax[0].set_xlabel("t [s]")
    ax[0].legend(fontsize=8)
    ax[0].set_title(f"L_1/L_2 = {k:.3f}: leg 2 passes the perpendicular")
    for source, x in runs.items():
        ax[1].semilogy(t, np.maximum(np.max(np.abs(x - ref), axis=1), 1e-17), label=f"chart switch, {source}")
    ax[1].axhline(ENGINE_TOL, color="k", ls=":", label="bound")
    ax[1].set_title("state error against the reference")
    ax[1].set_xlabel("t [s]")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    r.figure = fig
    return r


def _energy(system, scene):
    from harness.hard.common import energy_function
    return energy_function(system, scene.effects, scene.params)


# ----------------------------------------------------------------------------- tower crane
def tower_crane_rope(catalogue, quick: bool = False) -> CaseResult:
    r = CaseResult(
        "tower_crane_rope", "Tower crane with the rope reeled in, s_5 → 0", ["tower_crane"], "event location",
        "M_33 = m_L s_5² cos² phi_4: at s_5 = 0 the rope angles move nothing and M is singular; an integration that "
        "runs on reels the rope through zero to a negative length (a meaningless state) or stops on round-off.",
        "The rope's end stop is an event: the integration stops where s_5 reaches the hook block's length "
        "s_min = 0.05 m (located by solve_ivp to 1e-12), in every source; the event time and the state there are "
        "compared. Exactly at s_5 = 0 the forward dynamics raises 'coordinate singularity at … s_5 = 0'.")
    system = catalogue.get("tower_crane")
    f_S = -(20.0 * 9.81 + 150.0)   # pulls the load up: f_S acts in the direction of increasing s_5
    from harness.modeling.scenes import Constant
    scene = scene_for("reel_in", {"gravity", "inputs"}, inputs={"f_S": Constant(f_S)})
    T = 1.5
    q0, qd0 = np.array([0.0, 1.5, 0.05, 0.0, 1.0]), np.array([0.0, 0.3, 0.0, 0.0, 0.0])
    s_min = 0.05

    def stop(_, y):
        return y[4] - s_min
    stop.terminal, stop.direction = True, -1
    events, finals = {}, {}
    for source, tol in (("symbolic", 1e-12), ("pinocchio", 1e-10), ("mujoco", 1e-10)):
        sol, _ = solve(second_order(Dynamics(system, scene, source), 5), (0, T), np.concatenate([q0, qd0]),
                       rtol=tol, atol=tol, events=stop, dense_output=True)
        events[source] = float(sol.t_events[0][0]) if sol.t_events[0].size else np.inf
        finals[source] = sol
    ref = finals["symbolic"]
    t_stop = events["symbolic"]
    r.numbers["event times s_5 = s_min [s]"] = events
    radau, _ = solve(second_order(Dynamics(system, scene, "symbolic"), 5), (0, T), np.concatenate([q0, qd0]),
                     "Radau", events=stop)
    r.check("reference event time confirmed (Radau vs DOP853)", "symbolic",
            abs(float(radau.t_events[0][0]) - t_stop) if radau.t_events[0].size else np.inf, REFERENCE_TOL, "[s]")
    t_eval = np.linspace(0.0, t_stop, 201)
    for source in ENGINES:
        r.check("event time vs reference [s]", source, abs(events[source] - t_stop), ENGINE_TOL, "[s]")
        a, b = finals[source].sol(t_eval), ref.sol(t_eval)
        r.check("trajectory up to the event vs reference", source, _rel(a, b) if finite(a) else np.inf, ENGINE_TOL,
                "integrator error as in harness/scenes/trajectories.py")
    sol, failure = _naive_solve(system, scene, q0, qd0, T, np.linspace(0, T, 401), guarded=False)
    if sol is not None:
        r.numbers["naive: smallest s_5 reached [m]"] = float(np.min(sol.y[4]))
        r.numbers["naive: status"] = sol.message
    else:
        r.numbers["naive: failure"] = failure
    r.naive = {"what": "integrating on without the end-stop event (DOP853 1e-10)",
               "metric": "smallest rope length s_5 reached [m] (below the hook block, 0.05 m: no crane gets there)",
               "value": float(np.min(sol.y[4])) if sol is not None else float("nan")}
    c = compiled(system)
    p = np.array([system.default_parameters()[x.name] for x in system.parameters])
    value, message = _raises_singularity(lambda: c.forward_dynamics(np.array([0.0, 1.5, 0.3, 0.1, 0.0]), np.zeros(5),
                                                                    p, np.zeros(3)), "s_5 = 0 in tower_crane")
    r.check("clear error at s_5 = 0 (forward dynamics)", "symbolic", value, 0.0, message)
    r.numbers["error message at s_5 = 0"] = message
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(10, 3.6))
    if sol is not None:
        ax[0].plot(sol.t, sol.y[4], "r--", label="naive: no end stop")
    te = np.linspace(0, t_stop, 200)
    ax[0].plot(te, ref.sol(te)[4], label="with the event s_5 = s_min")
    ax[0].axhline(0, color="k", lw=0.5)
    ax[0].set_xlabel("t [s]")
    ax[0].set_ylabel("s_5 [m]")
    ax[0].legend(fontsize=8)
    ax[1].plot(te, ref.sol(te)[2], label="phi_3")
    ax[1].plot(te, ref.sol(te)[3], label="phi_4")
    ax[1].set_title("rope angles up to the end stop")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    r.figure = fig
    return r
