"""Our right-hand side and its integrator, both in machine code: DOP853 stepping in numba around
:attr:`~harness.derivation.compile.CompiledModel.native_state_derivative`.

scipy's ``solve_ivp`` steps in Python and its ``odeint`` in Fortran, and both call ``ẏ`` through Python: about
3.4 µs a call around a ẏ that costs 0.9 µs in machine code (tower_crane, measured at its slew's start). Here the
stepping loop is compiled with the system's ẏ, so no evaluation leaves machine code. The algorithm is scipy's
DOP853 (Hairer, Nørsett, Wanner, *Solving ODEs I*, II.5 and II.6; scipy's coefficient tables,
``scipy.integrate._ivp.dop853_coefficients``): the same initial step, error norm (the 5th- and 3rd-order
estimates), step-size control (safety 0.9, factors 0.2–10, exponent −1/8) and dense output (3 more stages in a step
that holds a sample time), so it takes scipy's steps to rounding (tests/test_native.py). Inputs are held over each
piece between the scene's breakpoints (:meth:`~harness.scenes.simulate.Dynamics.hold`), as by scipy's piecewise
runs; a scene whose inputs vary within a step calls ``u(t)`` in Python and is not for this path.
"""

from __future__ import annotations

import math
import weakref

import numpy as np
from scipy.integrate._ivp import dop853_coefficients as tableau

from harness.errors import NotApplicable
from harness.modeling.scenes import Scene
from harness.scenes.simulate import piece_samples, pieces

METHOD = "DOP853 (machine code)"   # its name in the work-precision sweep, beside scipy's "DOP853"
SAFETY, MIN_FACTOR, MAX_FACTOR = 0.9, 0.2, 10.0   # scipy's step-size control (scipy.integrate._ivp.rk)
EXPONENT = -1.0 / 8.0                               # −1 / (error estimator order 7 + 1)
FINISHED, TOO_SMALL_STEP, OVER_BUDGET = 0, 1, 2

_integrators: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def integrator(compiled_model):
    """The DOP853 of ``compiled_model``'s ẏ in machine code (compiled on its first call, kept with the model):
    ``integrate(a, b, y0, times, rtol, atol, p, u, budget) -> (values at times, nfev, status)`` from ``a`` to ``b``
    with the inputs ``u`` held, ``times`` sorted within ``[a, b]``; ``status`` :data:`FINISHED`,
    :data:`TOO_SMALL_STEP` or :data:`OVER_BUDGET` (more than ``budget`` evaluations)."""
    f = compiled_model.native_state_derivative   # a numba dispatcher: hashable (the model is a dataclass: not)
    if f not in _integrators:
        _integrators[f] = _build(f)
    return _integrators[f]


def _build(f):
    import numba

    stages, extended = tableau.N_STAGES, tableau.N_STAGES_EXTENDED
    A, B, C, E3, E5, D = (np.ascontiguousarray(x, dtype=float) for x in (tableau.A, tableau.B, tableau.C,
                                                                      tableau.E3, tableau.E5, tableau.D))
    powers = tableau.INTERPOLATOR_POWER

    @numba.njit(error_model="numpy")
    def rms(x):
        return math.sqrt(np.sum(x * x) / x.size)

    @numba.njit(error_model="numpy")
    def integrate(a, b, y0, times, rtol, atol, p, u, budget):
        n = y0.size
        out = np.empty((times.size, n))
        K = np.empty((extended, n))
        F = np.empty((powers, n))
        y, t = y0.copy(), a
        f0 = f(t, y, p, u)
        nfev = 1
        # the initial step (scipy.integrate._ivp.common.select_initial_step, order 7)
        interval = b - a
        scale = atol + np.abs(y) * rtol
        d0, d1 = rms(y / scale), rms(f0 / scale)
        h0 = 1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1
        h0 = min(h0, interval)
        f1 = f(t + h0, y + h0 * f0, p, u)
        nfev += 1
        d2 = rms((f1 - f0) / scale) / h0
        h1 = max(1e-6, h0 * 1e-3) if d1 <= 1e-15 and d2 <= 1e-15 else (0.01 / max(d1, d2)) ** (1.0 / 8.0)
        h_abs = min(100.0 * h0, h1, interval)
        fy = f0
        i = 0                                    # the next sample time
        while True:
            min_step = 10.0 * abs(np.nextafter(t, np.inf) - t)
            if h_abs < min_step:
                h_abs = min_step
            rejected = False
            while True:                          # one accepted step (scipy.integrate._ivp.rk.RungeKutta._step_impl)
                if h_abs < min_step:
                    return out, nfev, TOO_SMALL_STEP
                t_new = t + h_abs
                if t_new > b:
                    t_new = b
                h = t_new - t
                h_abs = abs(h)
                K[0] = fy
                for s in range(1, stages):
                    dy = np.zeros(n)
                    for j in range(s):
                        dy += K[j] * A[s, j]
                    K[s] = f(t + C[s] * h, y + dy * h, p, u)
                dy = np.zeros(n)
                for j in range(stages):
                    dy += K[j] * B[j]
                y_new = y + h * dy
                f_new = f(t + h, y_new, p, u)
                K[stages] = f_new
                nfev += stages
                scale = atol + np.maximum(np.abs(y), np.abs(y_new)) * rtol
                err5, err3 = np.zeros(n), np.zeros(n)
                for j in range(stages + 1):
                    err5 += K[j] * E5[j]
                    err3 += K[j] * E3[j]
                e5, e3 = np.sum((err5 / scale) ** 2), np.sum((err3 / scale) ** 2)
                error = 0.0 if e5 == 0.0 and e3 == 0.0 else abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * n)
                if error < 1.0:
                    factor = MAX_FACTOR if error == 0.0 else min(MAX_FACTOR, SAFETY * error ** EXPONENT)
                    if rejected:
                        factor = min(1.0, factor)
                    h_abs *= factor
                    break
                factor = SAFETY * error ** EXPONENT
                h_abs *= factor if factor > MIN_FACTOR else MIN_FACTOR   # also nan: scipy's max(0.2, nan)
                rejected = True
            if i < times.size and times[i] <= t_new:   # dense output (rk.DOP853._dense_output_impl)
                for s in range(stages + 1, extended):
                    dy = np.zeros(n)
                    for j in range(s):
                        dy += K[j] * A[s, j]
                    K[s] = f(t + C[s] * h, y + dy * h, p, u)
                nfev += extended - stages - 1
                F[0] = y_new - y
                F[1] = h * K[0] - F[0]
                F[2] = 2.0 * F[0] - h * (f_new + K[0])
                for r in range(powers - 3):
                    acc = np.zeros(n)
                    for j in range(extended):
                        acc += D[r, j] * K[j]
                    F[3 + r] = h * acc
                while i < times.size and times[i] <= t_new:
                    x = (times[i] - t) / h
                    value = np.zeros(n)
                    for r in range(powers):
                        value += F[powers - 1 - r]
                        value *= x if r % 2 == 0 else 1.0 - x
                    out[i] = value + y
                    i += 1
            t, y, fy = t_new, y_new, f_new
            if t >= b:
                return out, nfev, FINISHED
            if nfev > budget:
                return out, nfev, OVER_BUDGET

    return integrate


def warm(compiled_model, y0, p, u) -> None:
    """Compile :func:`integrator` for these arguments' types (its first call compiles, 3.4 s a system) by a run over
    a nanosecond, so that no timed run pays for it."""
    integrator(compiled_model)(0.0, 1e-9, np.ascontiguousarray(y0, dtype=float), np.empty(0), 1e-6, 1e-6,
                               np.ascontiguousarray(p, dtype=float), np.ascontiguousarray(u, dtype=float), 100)


class OverBudget(Exception):
    """A run of :func:`solve_piecewise` took more evaluations than its budget."""


def solve_piecewise(compiled_model, scene: Scene, y0, rtol: float, atol: float, t_eval, p, inputs, on_piece=None,
                    budget: int = 10**9) -> tuple[np.ndarray, np.ndarray, int]:
    """:func:`harness.scenes.simulate.solve_piecewise` with :func:`integrator`: DOP853 restarted at the scene's
    breakpoints, each piece's end state read from its last step's interpolant; ``inputs(t)`` the piece's inputs
    (held by ``on_piece(a, b)``, :meth:`~harness.scenes.simulate.Dynamics.hold`), read once a piece. Returns
    ``(t, y, nfev)`` at ``t_eval``."""
    if scene.inputs and scene.inputs_vary_within_steps:
        raise NotApplicable(f"{scene.name}: its inputs vary within a step: u(t) is evaluated in Python, not in "
                            "machine code")
    integrate = integrator(compiled_model)
    p = np.ascontiguousarray(p, dtype=float)
    edges = [0.0, *[b for b in scene.breakpoints if b < scene.horizon], scene.horizon]
    ys, nfev, y = [], 0, np.ascontiguousarray(y0, dtype=float)
    for k, (a, b) in pieces(edges, on_piece):
        last = k == len(edges) - 2
        inside = piece_samples(t_eval, a, b, last)
        times = np.ascontiguousarray(inside if last else np.append(inside, b), dtype=float)
        u = np.ascontiguousarray(inputs(0.5 * (a + b)), dtype=float)
        values, used, status = integrate(a, b, y, times, rtol, atol, p, u, budget - nfev)
        nfev += used
        if status == OVER_BUDGET:
            raise OverBudget(f"{scene.name}: over the budget of {budget} evaluations")
        if status == TOO_SMALL_STEP:
            raise RuntimeError(f"{scene.name}: integration failed on [{a}, {b}]: the step size fell below its "
                               "minimum")
        ys.append(values[:len(inside)])
        if not last:
            y = values[-1].copy()   # at b
    return t_eval, np.concatenate(ys).T, nfev
