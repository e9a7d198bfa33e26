"""Hard cases stay numerically stable (harness/hard/): the default tests run the strategies at short horizons
and the whole catalogue with its report at its shortened horizons (``harness hard --quick``, ~60 CPU s: a case
that no longer runs was found only by the full ``harness hard``, which no test ran — the pendulum's 10⁴ periods
as one scene's horizon, after scene horizons were bounded)."""

import json
import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import models
from harness.checks import MARGIN
from harness.cli import main
from harness.derivation.compile import compiled
from harness.errors import ModelError
from harness.hard import CASES
from harness.hard.charts import integrate_charts, pendulum_charts
from harness.hard.common import reference_error, scene_for, second_order, solve
from harness.hard.long_horizon import GROWTH_TOL, _growth, mujoco_steps, verlet
from harness.hard.stiff import (REFERENCE_RTOL, REFERENCE_TOL, a05_error, a05_scene, stiff_tyre_run,
                                 stiff_tyre_scene)
from harness.modeling.scenes import Scene
from harness.scenes.simulate import Dynamics

ENGINE_TOL = 1e-6
INVARIANT_TOL = 1e-8
MACHINE_CODE = pytest.mark.xdist_group("machine-code")   # numba's compilations shared in one process (conftest.py)


def _p(system, **over):
    values = {**system.default_parameters(), **over}
    return np.array([values[x.name] for x in system.parameters])


@pytest.mark.parametrize("name, q, expect", [
    ("spherical_pendulum", [0.0, 0.3], "coordinate singularity at theta = 0, phi = 0.3 in spherical_pendulum"),
    ("governor", [0.2, 0.0], "coordinate singularity at phi = 0.2, alpha = 0 in governor"),
    ("tower_crane", [0.0, 1.5, 0.3, 0.1, 0.0], "s_5 = 0 in tower_crane"),
])
@pytest.mark.parametrize("native", [False, pytest.param(True, marks=MACHINE_CODE)], ids=["python", "numba"])
def test_singular_mass_matrix_is_a_clear_error(name, q, expect, native):
    system = models.get(name)
    c = compiled(system)
    with pytest.raises(ModelError, match="coordinate singularity") as info:
        c.forward_dynamics(np.array(q), np.ones(len(q)), _p(system), np.zeros(len(system.inputs)), native=native)
    assert expect in str(info.value)
    if native:  # the first-order right-hand side an integrator calls: an error, not a q̈ of round-off
        with pytest.raises(ModelError, match=f"{name}: M is singular"):
            c.native_state_derivative(0.0, np.concatenate([q, np.ones(len(q))]), _p(system),
                                      np.zeros(len(system.inputs)))


@st.composite
def mass_matrices(draw):
    """A symmetric positive definite ``M`` of 1–7 coordinates with a chosen spectrum: largest eigenvalue 1e-3–1e3,
    smallest/largest 1e-16–1e-6 (across :data:`~harness.derivation.compile.SINGULAR_M`), in random axes."""
    n = draw(st.integers(1, 7))
    top = 10.0 ** draw(st.floats(-3.0, 3.0))
    ratio = 10.0 ** draw(st.floats(-16.0, -6.0))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    w = top * np.sort(np.concatenate([[ratio, 1.0], ratio ** rng.uniform(0.0, 1.0, max(n - 2, 0))]))[-n:]
    V, _ = np.linalg.qr(rng.normal(size=(n, n)))
    M = (V * w) @ V.T
    return 0.5 * (M + M.T)


@settings(max_examples=300, deadline=None)
@given(mass_matrices())
def test_the_cholesky_bound_proves_only_what_the_eigenvalues_confirm(M):
    """The machine code's q̈ solves by Cholesky where ``λ_min / λ_max ≥ 1 / (tr M tr M⁻¹) > 2 SINGULAR_M`` proves
    M regular (:func:`~harness.derivation.compile.cholesky_solve`): wherever it proves so, the eigenvalue test of
    every other path agrees; it proves every M whose ``n² cond(M)`` is well inside the bound; its q̈ is LAPACK's to
    ``cond(M) ε``."""
    from harness.derivation.compile import SINGULAR_M, cholesky_solve, regular_spectrum

    n = len(M)
    rhs = np.linspace(1.0, 2.0, n)
    solution, proved = cholesky_solve(M.ravel(), rhs, n)
    w = np.linalg.eigvalsh(M)
    if proved:
        assert regular_spectrum(w)
        condition = w[-1] / w[0]
        assert np.allclose(solution, np.linalg.solve(M, rhs), rtol=0.0,
                           atol=100 * n * condition * np.finfo(float).eps * np.max(np.abs(np.linalg.solve(M, rhs))))
    if w[0] > 0.0 and n * n * w[-1] < w[0] * 0.1 / SINGULAR_M:
        assert proved


@pytest.mark.parametrize("native", [False, pytest.param(True, marks=MACHINE_CODE)], ids=["python", "numba"])
def test_outside_the_map_is_a_clear_error_not_nan(native):
    system = models.get("toggle_press")
    c = compiled(system)
    with pytest.raises(ModelError, match="not finite at q = 1.2 in toggle_press"):
        c.forward_dynamics(np.array([1.2]), np.array([0.1]), _p(system, L_1=0.7, L_2=0.6), np.zeros(2), native=native)


ONE_DOF = [name for name in models.catalogue() if len(models.get(name).coordinates) == 1]


@pytest.mark.parametrize("name", ONE_DOF)
def test_one_degree_of_freedom_solves_as_the_eigendecomposition_bit_for_bit(name):
    """q̈ of a 1-DoF system is solved without LAPACK (eigh of a 1 × 1 M is w = M, V = [[1]]): the same float64 as
    the general path, at random states and parameters, and the same clear error where that path raises."""
    from harness.derivation.compile import regular_spectrum

    system = models.get(name)
    c = compiled(system)
    rng = np.random.default_rng(7)
    p0 = _p(system)
    for _ in range(50):
        q, qd, u = rng.uniform(-2, 2, 1), rng.uniform(-2, 2, 1), rng.uniform(-2, 2, len(system.inputs))
        p = p0 * rng.uniform(0.5, 1.5, len(p0))
        M, Cqd, g, f_np = c.terms(q, qd, p, u)
        if not np.all(np.isfinite(M)):  # outside the map's domain: the clear error of the general path
            with pytest.raises(ModelError, match="not finite"):
                c.forward_dynamics(q, qd, p, u)
            continue
        w, V = np.linalg.eigh(M)
        assert regular_spectrum(w)
        assert c.forward_dynamics(q, qd, p, u).tobytes() == (V @ ((V.T @ (f_np - Cqd - g)) / w)).tobytes()


def test_one_degree_of_freedom_without_mass_is_a_clear_error():
    system = models.get("pendulum")
    c = compiled(system)
    massless = _p(system, **{x.name: 0.0 for x in system.parameters if x.name.startswith(("m", "I", "J"))})
    with pytest.raises(ModelError, match="coordinate singularity .* the mass matrix M is singular"):
        c.forward_dynamics(np.array([0.3]), np.array([0.1]), massless, np.zeros(len(system.inputs)))


def test_chart_switch_through_the_pole_in_both_engines():
    """phi_dot(0) = 1e-7: the bob passes within ~1e-7 of the pole; the chart switch keeps energy and angular
    momentum and the engines' runs agree with the reference."""
    charts = pendulum_charts(models.get("spherical_pendulum"), 1.0)
    scene = scene_for("pole", {"gravity"})
    T, t_eval = 1.5, np.linspace(0.0, 1.5, 151)
    q0, qd0 = np.array([0.6, 0.0]), np.array([0.0, 1e-7])
    dyn = {c.name: Dynamics(c.system, scene, "symbolic") for c in charts}
    _, ref, switches, _, _ = integrate_charts(charts, dyn, 0, q0, qd0, T, t_eval)
    assert switches and np.all(np.isfinite(ref))
    energy = 0.5 * np.sum(ref[:, 3:] ** 2, axis=1) + 9.81 * ref[:, 1]
    momentum = ref[:, 2] * ref[:, 3] - ref[:, 0] * ref[:, 5]
    assert np.ptp(energy) / 9.81 <= INVARIANT_TOL
    assert np.ptp(momentum) / math.sqrt(9.81) <= INVARIANT_TOL
    for source in ("pinocchio", "mujoco"):
        d = {c.name: Dynamics(c.system, scene, source) for c in charts}
        _, x, _, _, _ = integrate_charts(charts, d, 0, q0, qd0, T, t_eval, rtol=1e-10, atol=1e-10)
        assert np.all(np.isfinite(x))
        assert np.max(np.abs(x - ref)) <= ENGINE_TOL, source


def test_governor_reduction_through_the_axis():
    """The arms swing through alpha = 0 (p_phi = 0): the reduced alpha equation, from MuJoCo's M, C q̇, g, agrees
    with the symbolic one; the full equations would factorize a singular M there."""
    from harness.hard.common import Terms
    system = models.get("governor")
    scene = scene_for("pole", {"gravity"})
    t_eval = np.linspace(0.0, 1.0, 101)

    def reduced(source):
        d = Terms(system, scene, source)

        def rhs(t, y):
            M, Cqd, g, f = d.terms(t, np.array([0.0, y[0]]), np.array([0.0, y[1]]))
            return [y[1], (f[1] - Cqd[1] - g[1]) / M[1, 1]]
        return rhs
    ref, _ = solve(reduced("symbolic"), (0, 1.0), [0.5, 0.0], t_eval=t_eval)
    assert np.min(ref.y[0]) < 0 < np.max(ref.y[0])           # it does pass through the axis
    sol, _ = solve(reduced("mujoco"), (0, 1.0), [0.5, 0.0], rtol=1e-10, atol=1e-10, t_eval=t_eval)
    assert np.max(np.abs(sol.y - ref.y)) <= ENGINE_TOL


def test_flyball_a05_reaches_both_precision_levels():
    """A05 over its first 0.3 s (the stiff transient): Radau reaches 1e-3 and 1e-6 in s(t) against a
    Radau 1e-10 reference; the full 10 s with CPU times per source is ``harness hard flyball_governor_a05``."""
    from harness.hard.flyball_governor import SYSTEM as system
    scene = a05_scene(0.3)
    y0 = np.concatenate([scene.q0, scene.qd0])
    t_eval = np.linspace(0.0, 0.3, 121)
    rhs = second_order(Dynamics(system, scene, "symbolic"), 4)
    ref, _ = solve(rhs, (0, 0.3), y0, "Radau", 1e-10, 1e-10, t_eval=t_eval)
    for target, tol in ((1e-3, 1e-4), (1e-6, 1e-8)):
        sol, cpu = solve(rhs, (0, 0.3), y0, "Radau", tol, tol, t_eval=t_eval)
        assert sol.success and np.all(np.isfinite(sol.y))
        assert a05_error(sol.y[1], ref.y[1]) <= target, (target, tol)


def test_stiff_quarter_car_reference_is_two_orders_below_its_bound():
    """The stiff quarter car's DOP853 reference at :data:`REFERENCE_RTOL` against DOP853 at a quarter of it over
    the full 2 s (3 s CPU): at most a tenth of :data:`REFERENCE_TOL`. At 1e-12 it is 6.3e-9 off (0.63 of the bound,
    the wheel's velocity at 1.73 s); the case's own confirmation by Radau at 1e-12 costs 14 s CPU."""
    from harness.catalogue import repository

    catalogue = repository()
    system, scene = catalogue.get("quarter_car"), stiff_tyre_scene(catalogue)
    ref = stiff_tyre_run(system, scene, "symbolic", "DOP853", REFERENCE_RTOL)[0]
    finer = stiff_tyre_run(system, scene, "symbolic", "DOP853", REFERENCE_RTOL / 4)[0]
    error = reference_error(ref, finer)
    assert error <= 0.1 * REFERENCE_TOL, error


def test_flyball_springs_relaxed_at_the_start():
    """The relaxed springs at the benchmark's initial state (s = 0.5 m, alpha = 30°)."""
    from harness.hard.flyball_governor import SYSTEM as system
    c = compiled(system)
    q = np.array(a05_scene().q0)
    assert abs(float(c("V", q, p=_p(system, g=0.0)))) < 1e-20


def test_symplectic_energy_stays_in_a_band_and_rk_drifts():
    system = models.get("pendulum")
    c = compiled(system)
    p = _p(system)
    h, steps = 2.1528754 / 64, 64 * 200

    def accel(q):
        return -float(c("g", np.array([q]), p=p)[0, 0]) / float(c("M", np.array([q]), p=p)[0, 0])

    def rel(q, v):
        return np.abs(0.5 * v * v + 9.81 * (1 - np.cos(q)) - 9.81 * (1 - math.cos(1.0472))) / (9.81 * 0.5)
    out = verlet(accel, 1.0472, 0.0, h, steps, 61)
    assert _growth(rel(out[:, 1], out[:, 2])) <= GROWTH_TOL
    scene = Scene("long", "", (1.0472,), (0.0,), steps * h, frozenset({"gravity"}))
    _, q, v, _ = mujoco_steps(system, scene, h, 64 * 2000, "Euler", 61)
    assert _growth(rel(q, v)[1:]) <= GROWTH_TOL
    _, q, v, _ = mujoco_steps(system, scene, h, 64 * 2000, "RK4", 61)
    assert _growth(rel(q, v)[1:]) > 5        # the non-symplectic RK4 drifts (what the case shows)


def test_mujoco_point_mass_inertia_within_the_stated_bound():
    from harness.hard.mass_ratio import POINT_INERTIA, ROUND_OFF
    system = models.get("trebuchet_free")
    M_cw = system.default_parameters()["M"]
    scene = scene_for("ratio", {"gravity"}, params={"M": M_cw, "m": M_cw / 1e6})
    q, qd = np.array([0.25, 0.1, 1.2]), np.array([1.0, -0.5, 0.3])
    sym = Dynamics(system, scene, "symbolic")
    kappa = np.linalg.cond(sym.c.mass_matrix(q, sym.p))
    a = sym(0.0, q, qd)
    bound = ROUND_OFF * kappa + POINT_INERTIA / (M_cw / 1e6 * system.default_parameters()["r"] ** 2)
    for source in ("pinocchio", "mujoco"):
        b = Dynamics(system, scene, source)(0.0, q, qd)
        assert np.max(np.abs(b - a)) / np.max(np.abs(a)) <= bound, source


def test_unknown_hard_case_is_one_error_line(capsys, tmp_path):
    assert main(["hard", "no_such_case", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error: unknown hard case 'no_such_case'")
    assert not (tmp_path / "hard.json").exists()


@pytest.mark.parametrize("case", list(CASES))
def test_catalogue_report(case, tmp_path):
    """Each case of the catalogue at its shortened horizon, as ``harness hard CASE --quick`` runs it (one test a
    case: the test processes share the ~60 CPU s): every bound holds, the JSON and the figure exist; every check on
    a margin bound (a reference's confirmation by a second method, an integrator's or round-off's tolerance) uses at
    most a tenth of it (a reference closer to its bound than that could move the checks made against it: the stiff
    quarter car's DOP853 reference at 1e-12 used 0.63; its Radau runs at 1e-8 used 0.15 of theirs); only a check on
    a derived bound, named in the document's bounds, may come closer."""
    assert main(["hard", case, "--quick", "--out", str(tmp_path)]) == 0
    doc = json.loads((tmp_path / "hard.json").read_text())
    assert doc["schema"] == "hard-cases/3" and doc["passed"] and [c["id"] for c in doc["cases"]] == [case]
    for record in doc["cases"]:
        for check in record["checks"]:
            derived = (doc["bounds"].get(check["basis"]) or {}).get("derived")
            if not derived and check["bound"] > 0:
                assert check["ratio"] <= MARGIN, check
        if record["figure"]:
            assert (tmp_path / record["figure"]).exists()
        assert f"## {record['id']}: {record['title']}" in (tmp_path / "hard.md").read_text()  # its page


def test_cases_run_in_worker_processes_give_the_same_report(tmp_path):
    """``harness hard --jobs 2`` (the main job runs the hard cases on its pool): each case in a worker process, its
    figure and the derived bounds its checks name sent back (the writing process need not have imported the case's
    module); the report is the one of the cases run here, in the catalogue's order, its figures too: a process that
    drew the report's figures before (smaller fonts) drew them otherwise."""
    import matplotlib

    from harness.report.figures import _matplotlib

    cases = ["trebuchet_mass_ratio", "double_pendulum_chaos"]
    assert main(["hard", *cases, "--quick", "--jobs", "2", "--out", str(tmp_path / "two")]) == 0
    with matplotlib.rc_context():
        _matplotlib()   # this process drew the report's figures before (as the main job's workers do): the same page
        assert main(["hard", *cases, "--quick", "--out", str(tmp_path / "one")]) == 0
    two, one = (json.loads((tmp_path / name / "hard.json").read_text()) for name in ("two", "one"))
    assert [c["id"] for c in two["cases"]] == ["double_pendulum_chaos", "trebuchet_mass_ratio"]
    assert [[(k["check"], k["value"]) for k in c["checks"]] for c in two["cases"]] == \
        [[(k["check"], k["value"]) for k in c["checks"]] for c in one["cases"]]
    assert two["bounds"] == one["bounds"] and two["bounds"]["justified horizon"]["derived"]
    assert (tmp_path / "two" / "hard" / "double_pendulum_chaos.svg").read_text() == \
        (tmp_path / "one" / "hard" / "double_pendulum_chaos.svg").read_text()
