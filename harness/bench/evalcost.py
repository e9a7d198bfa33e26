"""Evaluation cost of ``M``, ``C·q̇``, ``g`` and ``q̈`` per state, all measured in one process and one run.

* **symbolic, one call**: :meth:`CompiledModel.terms_array`, the one compiled function of plain floats that
  returns the entries of ``M``, ``C·q̇``, ``g`` (and ``f_np``) of a state together in one array, the function every
  simulation calls (splitting the array into four, :meth:`CompiledModel.terms`, is ``split``); ``q̈`` is
  :meth:`CompiledModel.forward_dynamics` (``terms``, then one ``eigh`` of ``M`` that checks and solves).
  Where the time goes: the generated arithmetic alone (``terms_arithmetic``, on lists of floats), the ``eigh``; and
  the NumPy function of one quantity each that the conformance checks call (``symbolic_numpy``, ``C·q̇`` = ``C``
  times ``q̇``; ``symbolic_wrapper``: through ``CompiledModel.__call__``).
* **symbolic, machine code** (opt-in): the same function compiled by numba (``terms(native=True)``), ``q̈`` with
  it, and the terms at ``N`` states in a compiled loop (``batched_terms``, per state); the compilation time
  (``native_compile_seconds``) beside.
* **symbolic, batched**: :meth:`CompiledModel.batched` over ``N`` states (default 10⁴), time divided by ``N``.
* **Pinocchio, per call**: ``crba`` (M), ``nonLinearEffects`` (C·q̇ + g; C·q̇ needs it *and* the next),
  ``computeGeneralizedGravity`` (g), ``aba`` (q̈), on the model loaded from our URDF, in tree coordinates.
* **MuJoCo, per call**: ``mj_fwdPosition + mj_fullM`` (M), ``mj_fwdPosition + mj_fwdVelocity`` (``qfrc_bias``
  = C·q̇ + g), ``mj_forward`` (q̈).

The engines' calls are the raw calls their adapters name at one state (``kernels``,
:meth:`harness.engines.pinocchio_engine.PinocchioModel.kernels`,
:meth:`harness.engines.mujoco_engine.MujocoModel.kernels`): what is timed is the engine, not the adapter's
mapping to our coordinates.

Each time is the median over 5 repeats of a loop long enough to take ≳ 20 ms. The goals of the issue compare the
sum ``M + C·q̇ + g``: batched compiled per state ≤ 0.2 × Pinocchio per call, one compiled call ≤ 2 ×; each goal's
ratio is timed again in 21 alternating pairs of our loop and Pinocchio's three calls (``paired``,
:func:`paired_ratio`): its median, interval and verdict (met, undecided, not met) are what the goals read.
"""

from __future__ import annotations

import statistics
import time
import timeit

import numpy as np

from harness.derivation.compile import compiled
from harness.engines import ENGINES
from harness.export.numeric import instantiate
from harness.scenes.phenomena.pruning import judged_at_most, paired, undecided

GOAL_BATCHED = 0.2
GOAL_ONE_CALL = 2.0
QUICK = ("pendulum", "planar_manipulator", "planar_robot")     # --quick: a representative set
TIMED = ("pinocchio", "mujoco")                                   # the engines whose calls are timed


def per_call(fn, min_seconds: float = 0.02, repeats: int = 5) -> float:
    """Median seconds per call of ``fn()``."""
    timer = timeit.Timer(fn)
    number = _loop_length(timer, min_seconds)
    return statistics.median(timer.repeat(repeats, number)) / number


def _loop_length(timer: timeit.Timer, min_seconds: float = 0.02) -> int:
    """Calls per timing loop: the first power of 4 whose loop takes at least ``min_seconds``."""
    number = 1
    while timer.timeit(number) < min_seconds and number < 10**6:
        number *= 4
    return number


PAIRS = 21   # alternating pairs of our loop and Pinocchio's per goal and system (pruning.REPEATS: [r_(4), r_(18)])


def paired_ratio(ours, theirs, target: float, per: int = 1, pairs: int = PAIRS) -> dict:
    """Seconds per state of ``ours()`` (one call covers ``per`` states) against seconds per call of ``theirs()``,
    timed in ``pairs`` alternating pairs of loops of ≳ 20 ms each (:func:`~harness.scenes.phenomena.pruning.paired`):
    ``{"ratio": the median of the pairs' ratios, "ratio_low", "ratio_high": its ≥ 99.5 % interval
    (:func:`~harness.scenes.phenomena.pruning.ratio_interval`), "verdict"}`` against ``target`` (≤, widened by the
    resolution: :func:`~harness.scenes.phenomena.pruning.at_most`). The goals' ratios of two medians taken one after
    the other moved a system across its target from one run to the next (tower_crane batched 0.195 ×, 0.22 ×)."""
    def loop(fn, states: int):
        timer = timeit.Timer(fn)
        number = _loop_length(timer)
        return lambda: timer.timeit(number) / number / states

    return judged_at_most(*paired(loop(ours, per), loop(theirs, 1), pairs, undecided(target, at_most=True)), target)


def measure(catalogue, system: str, states: int = 10_000, seed: int = 0) -> dict:
    """Every time of the module docstring for one system of ``catalogue`` (seconds per state)."""
    s = catalogue.get(system)
    c = compiled(s)
    n, m = len(s.q), len(s.u)
    params = s.default_parameters()
    p = np.array(list(params.values()))
    rng = np.random.default_rng(seed)
    Q, QD = rng.uniform(-1, 1, (states, n)), rng.uniform(-1, 1, (states, n))
    U = np.zeros((states, m))
    q, qd, u = Q[0], QD[0], U[0]
    f = c._functions
    out: dict = {"system": system, "dof": n, "states": states, "symbolic": {}, "symbolic_wrapper": {},
                 "symbolic_batched": {}}
    sym = out["symbolic"]
    M0, Cqd0, g0, _ = c.terms(q, qd, p, u)
    # the one function returns what the per-quantity NumPy functions return (guards against timing a wrong one)
    for got, want in ((M0, f["M"](q, qd, p, u)), (Cqd0, f["C"](q, qd, p, u) @ qd), (g0, f["g"](q, qd, p, u))):
        assert np.allclose(got, np.reshape(want, np.shape(got)), rtol=1e-12, atol=1e-12)
    # what the goals compare (:func:`_ratios`), each timed by itself and again in pairs with Pinocchio (``paired``)
    def one_call():
        return c.terms_array(q, qd, p, u)

    def one_call_native():
        return c.terms_array(q, qd, p, u, native=True)

    def batched_native():
        return c.batched_terms(Q, QD, p, U)

    batched = {"M": lambda: c.batched("M", Q, QD, p, U),
               "Cqd": lambda: np.einsum("nij,nj->ni", c.batched("C", Q, QD, p, U), QD),
               "g": lambda: c.batched("g", Q, QD, p, U)}
    sym["terms"] = per_call(one_call)
    sym["qdd"] = per_call(lambda: c.forward_dynamics(q, qd, p, u))
    ql, qdl, pl, ul = q.tolist(), qd.tolist(), p.tolist(), u.tolist()
    start = time.perf_counter()
    # compiles the terms and q̈: a first call of per_call's that compiled would set its loop to single calls,
    # each timed with the timer's own overhead (the arm's q̈ read 18 µs a call, 3.5 µs in a loop)
    c.terms(q, qd, p, u, native=True)
    c.forward_dynamics(q, qd, p, u, native=True)
    out["native_compile_seconds"] = time.perf_counter() - start
    sym["terms_native"] = per_call(one_call_native)
    sym["qdd_native"] = per_call(lambda: c.forward_dynamics(q, qd, p, u, native=True))
    out["qdd_parts"] = {"terms_arithmetic": per_call(lambda: c._terms_function(ql, qdl, pl, ul)),
                        "terms": sym["terms"], "split": per_call(lambda: c.terms(q, qd, p, u)) - sym["terms"],
                        "eigh": per_call(lambda: np.linalg.eigh(M0))}
    num = out["symbolic_numpy"] = {}
    num["M"] = per_call(lambda: f["M"](q, qd, p, u))
    num["Cqd"] = per_call(lambda: f["C"](q, qd, p, u) @ qd)
    num["g"] = per_call(lambda: f["g"](q, qd, p, u))
    wrap = out["symbolic_wrapper"]
    wrap["M"] = per_call(lambda: c("M", q, qd, p, u))
    wrap["Cqd"] = per_call(lambda: c("C", q, qd, p, u) @ qd)
    wrap["g"] = per_call(lambda: c("g", q, qd, p, u))
    bat = out["symbolic_batched"]
    for key, fn in (*batched.items(), ("qdd", lambda: c.batched_forward_dynamics(Q, QD, p, U))):
        fn()  # compiles the batched function once, untimed
        bat[key] = per_call(fn, repeats=3) / states
    c.batched_terms(Q[:2], QD[:2], p, U[:2])  # compiles
    bat["terms_native"] = per_call(batched_native, repeats=3) / states
    tree = instantiate(s, params)
    theta = np.asarray(c("phi", q, qd, p, u), dtype=float).ravel()
    theta_dot = np.asarray(c("J_phi", q, qd, p, u), dtype=float) @ qd
    for engine in TIMED:
        note = ENGINES[engine].applies(s)
        if note:
            out[engine] = {"skipped": note}
            continue
        kernels = ENGINES[engine](tree).kernels(theta, theta_dot)
        out[engine] = {key: per_call(call) for key, call in kernels.items()}
        if engine == "pinocchio":
            three = kernels["M"], kernels["nle"], kernels["g"]

            def pinocchio():
                return [call() for call in three]

            def broadcast():
                return [fn() for fn in batched.values()]

            out["paired"] = {  # the goals' four ratios (:func:`_ratios`' keys) from alternating pairs
                "one_call_vs_pinocchio": paired_ratio(one_call, pinocchio, GOAL_ONE_CALL),
                "one_call_native_vs_pinocchio": paired_ratio(one_call_native, pinocchio, GOAL_ONE_CALL),
                "batched_vs_pinocchio": paired_ratio(broadcast, pinocchio, GOAL_BATCHED, per=states),
                "batched_native_vs_pinocchio": paired_ratio(batched_native, pinocchio, GOAL_BATCHED, per=states)}
    if "nle" in out["pinocchio"]:
        out["pinocchio"]["Cqd"] = out["pinocchio"]["nle"] + out["pinocchio"]["g"]
    _ratios(out)
    return out


def pinocchio_sum(pin: dict) -> float:
    """Pinocchio's time for M, C·q̇ and g of one state: ``crba + nonLinearEffects + computeGeneralizedGravity``."""
    return pin["M"] + pin["nle"] + pin["g"]


def _ratios(out: dict) -> None:
    """The goals: (M + C·q̇ + g) of ours against Pinocchio's three calls."""
    if "M" not in out.get("pinocchio", {}):
        return
    pin_sum = pinocchio_sum(out["pinocchio"])
    one = out["symbolic"]["terms"]
    native = out["symbolic"]["terms_native"]
    batched = sum(out["symbolic_batched"][k] for k in ("M", "Cqd", "g"))
    out["ratios"] = {"one_call_vs_pinocchio": one / pin_sum, "batched_vs_pinocchio": batched / pin_sum,
                     "qdd_one_call_vs_aba": out["symbolic"]["qdd"] / out["pinocchio"]["qdd"],
                     "qdd_batched_vs_aba": out["symbolic_batched"]["qdd"] / out["pinocchio"]["qdd"],
                     "one_call_goal": GOAL_ONE_CALL, "batched_goal": GOAL_BATCHED,
                     "one_call_met": one / pin_sum <= GOAL_ONE_CALL, "batched_met": batched / pin_sum <= GOAL_BATCHED,
                     "one_call_native_vs_pinocchio": native / pin_sum,
                     "batched_native_vs_pinocchio": out["symbolic_batched"]["terms_native"] / pin_sum}
    if "qdd" in out.get("mujoco", {}):
        out["ratios"]["qdd_one_call_vs_mj_forward"] = out["symbolic"]["qdd"] / out["mujoco"]["qdd"]


def task(catalogue, system: str, states: int = 10_000) -> dict:
    return measure(catalogue, system, states)
