"""Work-precision of the scenes: error against a reference versus wall time and right-hand-side evaluations.

* **reference** (per scene): our symbolic model, DOP853 at ``rtol = atol = 1e-12``, confirmed by Radau at the
  same tolerance (:data:`harness.scenes.simulate.REFERENCE`, the check of :mod:`harness.scenes.phenomena.smooth`): both must
  agree to :data:`harness.scenes.base.REFERENCE_TOL`. A stiff variant (:data:`STIFF`) takes Radau at 1e-12,
  confirmed by LSODA (BDF) at 1e-12: there an explicit method's global error grows with its many
  stability-limited steps (measured on the quarter car's: DOP853 at 1e-12 is 1.4e-8 off after 51 807
  evaluations, Radau at 1e-12 and 1e-13 agree to 4.8e-13, LSODA to 1.6e-10).
* **configurations**: ``symbolic`` and ``pinocchio`` (q̈ from :class:`harness.scenes.simulate.Dynamics`) with scipy's
  RK45, DOP853, Radau, LSODA (``solve_ivp``) over ``rtol`` (``atol = rtol``), and LSODA with its stepping loop in
  Fortran (``odeint``, :data:`harness.scenes.simulate.ODEINT`); ``symbolic-numba``: our ẏ in machine code (numba, opt-in,
  :attr:`harness.derivation.compile.CompiledModel.native_state_derivative`) with DOP853 and ``odeint``, and with
  DOP853 stepping in machine code too (:data:`harness.scenes.native.METHOD`: no evaluation leaves it); ``pinocchio`` also
  with fixed-step classical RK4 and semi-implicit (symplectic) Euler; ``mujoco`` with its own integrators
  (``mj_step``: Euler, implicitfast, implicit, RK4) over time steps; a closed chain's tree under MuJoCo's soft
  equality constraints with implicitfast (:func:`harness.scenes.phenomena.closures.mujoco_constrained`). Our path is
  the fastest of ``symbolic`` and ``symbolic-numba`` (:data:`OURS`); the engines' is the fastest of ``pinocchio`` and
  ``mujoco``. Fixed steps are ``Δ/k`` with ``Δ`` the sample spacing of the scene
  (:func:`harness.scenes.simulate.sample_times`), so that every run is sampled at the same times; MuJoCo's ``Δ`` is
  shorter where an input jumps between samples (:func:`fixed_dt`).
* **error**: :func:`harness.scenes.simulate.max_error` (largest state difference at the 201 sample times, relative to
  the state's scale, at least 1); a run that diverges or fails has error ``inf`` and a note.
* **cost**: the median wall time of repeated runs (the model is built before the clock starts) and the number of
  right-hand-side evaluations (``q̈`` calls; a MuJoCo step counts its integrator's stages: 4 for RK4, 1 otherwise).
* **stiff variants**: :data:`STIFF` scales a stiffness of a scene by a factor via the scene's parameters.
* **scenes with events** (:mod:`harness.scenes.phenomena`): stick-slip (3.80) and the lift-off are simulated with their
  events located (their motion's ``simulate``, :func:`harness.scenes.phenomena.motion_of`) by ``solve_ivp``'s methods, with our and Pinocchio's q̈;
  MuJoCo runs them with its own dry friction (stick-slip) at its ``implicitfast`` integrator over time steps. The
  rolling sphere is smooth in our model; MuJoCo's sphere rolls in its contact (``implicitfast``). Whatever cannot
  locate an event (``odeint``, fixed steps) or has no event of its own is skipped with its reason
  (:func:`event_note`); the sphere that slips has no reference (our model, Ex. 3.17, rolls).
"""

from __future__ import annotations

import dataclasses
import math
import statistics
import time

import numpy as np

from harness.engines import ENGINES, steps_itself
from harness.engines.mujoco_engine import STAGES
from harness.errors import EngineError, NotApplicable
from harness.scenes import native, simulate as sim
from harness.modeling.events import RollSlip
from harness.modeling.scenes import Scene
from harness.scenes.base import REFERENCE_TOL
from harness.scenes.phenomena import motion_of, mujoco_own
from harness.scenes.phenomena.closures import constrained, mujoco_constrained
from harness.scenes.phenomena.pruning import REPEATS, judged_at_most, paired, undecided

SCIPY_METHODS = ("RK45", "DOP853", "Radau", "LSODA")
ADAPTIVE = (*SCIPY_METHODS, sim.ODEINT)
OURS = ("symbolic", "symbolic-numba")   # our symbolic model: Python floats, or machine code
NATIVE_METHODS = ("DOP853", sim.ODEINT, native.METHOD)   # native.METHOD: the stepping in machine code too
FIXED_METHODS = ("RK4", "semi-implicit Euler")
MUJOCO_INTEGRATORS = ("Euler", "implicitfast", "implicit", "RK4")
ACCURACY = 1e-6           # the accuracy at which the engines are compared (the goal)
SLIPS = ("the sphere slips: our model (Ex. 3.17) rolls, so there is no reference; MuJoCo's slipping contact is "
         "checked against the predicted threshold by harness check")
_STAGES = {**STAGES, "semi-implicit Euler": 1}   # right-hand-side evaluations of a step (RK4 also Pinocchio's)


@dataclasses.dataclass(frozen=True)
class Stiff:
    """A stiff variant of a scene: parameters scaled by ``factors``, started from the rest state
    ``rest(params)`` of the stiffer model (else the fast mode starts fully excited)."""

    scene: str
    factors: tuple        # ((parameter, factor), ...)
    rest: object = None   # params -> q0

    @property
    def label(self) -> str:
        return self.scene + "".join(f"_{p}_x{f:g}" for p, f in self.factors)


def _quarter_car_rest(p: dict) -> tuple:
    """Static deflections (A.41), (A.42) for x_U = 0."""
    x_R = -(p["m_A"] + p["m_R"]) * p["g"] / p["c_R"]
    return (x_R, x_R - p["m_A"] * p["g"] / p["c_A"])


# The tyre 1000 times stiffer *and* 1000 times more damped: a fast (≈ 360 Hz), well damped (ζ ≈ 0.56) tyre mode
# beside the slow body mode, the classic stiff case (explicit methods are held to the fast mode's stability
# limit, implicit ones are not). Stiffness alone (ζ ≈ 6e-4) gives a lightly damped 360 Hz oscillation that
# every method has to resolve: not stiff, only oscillatory.
STIFF = {"quarter_car": [Stiff("bump", (("c_R", 1000.0), ("d_R", 1000.0)), _quarter_car_rest)]}


@dataclasses.dataclass(frozen=True)
class Grid:
    """The sweep: tolerances of the adaptive methods, fixed-step refinements ``k`` (``dt = Δ/k``)."""

    rtols: tuple
    fixed_k: tuple
    mujoco_k: tuple
    repeats: int
    budget: int          # right-hand-side evaluations a single run may spend before it is abandoned
    pinocchio_methods: tuple = ADAPTIVE

    @staticmethod
    def make(quick: bool) -> "Grid":
        if quick:
            return Grid((1e-4, 1e-7), (1, 4), (1, 4, 16), 1, 10_000, ("DOP853", "LSODA", sim.ODEINT))
        return Grid(tuple(10.0 ** -e for e in range(3, 13)), (1, 2, 4, 8, 16, 32),
                    (1, 2, 4, 8, 16, 32, 64, 128, 256), 3, 60_000)

    def settings(self, engine: str, method: str) -> tuple:
        """Pinocchio's q̈ equals ours to round-off, so a scipy method takes the same steps with either: its
        error and evaluations repeat ours and only the time per evaluation differs. In the full grid Pinocchio
        runs every other tolerance (the full set for ours) to halve the sweep."""
        if engine in ENGINES and method in ADAPTIVE and len(self.rtols) > 4:
            return self.rtols[::2]
        return self.rtols


# --------------------------------------------------------------------------- scenes (with stiff variants)
def scene_cases(catalogue, systems=None) -> list[tuple[str, str]]:
    """``(system, scene label)`` of every scene of ``catalogue`` (or of ``systems``), stiff variants after."""
    names = systems or list(catalogue.systems())
    out = []
    for name in names:
        labels = [s.name for s in catalogue.scenes(name)]
        out += [(name, label) for label in labels]
        out += [(name, v.label) for v in STIFF.get(name, []) if v.scene in labels]
    return out


def get_scene(catalogue, system_name: str, label: str):
    system = catalogue.get(system_name)
    by_name = {s.name: s for s in catalogue.scenes(system_name)}
    if label in by_name:
        return system, by_name[label]
    for v in STIFF.get(system_name, []):
        if v.label == label:
            base = by_name[v.scene]
            params = {**system.default_parameters(), **base.params}
            for name, factor in v.factors:
                params[name] *= factor
            q0 = tuple(v.rest(params)) if v.rest else base.q0
            scaled = ", ".join(f"{name} × {factor:g}" for name, factor in v.factors)
            return system, dataclasses.replace(
                base, name=label, q0=q0, params={**base.params, **{name: params[name] for name, _ in v.factors}},
                description=f"{base.description} — stiff: {scaled}, from its rest state")
    raise KeyError(f"{system_name}: no scene {label!r}")


def _trajectory(source, t, q, qd, seconds=0.0, evaluations=0) -> sim.Trajectory:
    return sim.Trajectory(source, np.asarray(t), np.asarray(q), np.asarray(qd), seconds, evaluations)


# --------------------------------------------------------------------------- tasks (run in workers)
def reference_methods(system: str, scene: str) -> tuple[str, str]:
    """``(reference, confirmation)``: DOP853 and Radau; Radau and LSODA for a stiff variant (module docstring)."""
    stiff = any(v.label == scene for v in STIFF.get(system, []))
    return ("Radau", "LSODA") if stiff else (sim.REFERENCE["method"], "Radau")


def reference_task(catalogue, system: str, scene: str) -> dict:
    """The reference trajectory at 1e-12, confirmed by a method of another family (:func:`reference_methods`)."""
    s, sc = get_scene(catalogue, system, scene)
    if _slips(s, sc):
        return {"system": system, "scene": scene, "description": sc.description, "skipped": SLIPS}
    kw = {k: v for k, v in sim.REFERENCE.items() if k != "method"}
    method, confirmation = reference_methods(system, scene)
    ref, other = (_simulate(s, sc, "symbolic", m, kw["rtol"], catalogue) for m in (method, confirmation))
    agreement = sim.max_error(other, ref)
    return {"system": system, "scene": scene, "description": sc.description, "horizon": sc.horizon,
            "effects": sorted(sc.effects), "params": dict(sc.params),
            "method": f"{method} rtol=atol={kw['rtol']:g}", "confirmed_by": f"{confirmation} rtol=atol={kw['rtol']:g}",
            "agreement": agreement, "tolerance": REFERENCE_TOL, "confirmed": agreement <= REFERENCE_TOL,
            "seconds": ref.seconds, "evaluations": ref.evaluations,
            "confirmation_seconds": other.seconds, "confirmation_evaluations": other.evaluations,
            "t": ref.t.tolist(), "q": ref.q.tolist(), "qd": ref.qd.tolist()}


class _Budget(Exception):
    pass


def _not_applicable(s, engine: str) -> str | None:
    return ENGINES[engine].applies(s) if engine in ENGINES else None


def _slips(s, sc: Scene) -> bool:
    roll = _roll(sc)
    return roll is not None and roll.mu < roll.predicted({**s.default_parameters(), **sc.params})


def _roll(sc: Scene):
    return next((e for e in sc.events if type(e) is RollSlip), None)


def _simulate(s, sc: Scene, source: str, method: str, rtol: float, catalogue=None) -> sim.Trajectory:
    """``source``'s q̈ integrated by ``solve_ivp``'s ``method`` by the scene's motion (events located where it
    switches; a lift-off's phase 2 from ``catalogue``)."""
    motion, event = motion_of(sc)
    return motion.simulate(s, sc, event, source, method=method, rtol=rtol, atol=rtol, catalogue=catalogue)


def event_note(sc: Scene, engine: str, method: str) -> str | None:
    """Why a configuration does not apply to a scene with events (None: it applies)."""
    motion, _ = motion_of(sc)
    if steps_itself(engine):
        if mujoco_own(sc) is not None:
            return None if method == "implicitfast" else ("MuJoCo's dry friction and contact runs use implicitfast "
                                                          "(harness.scenes.phenomena)")
        return motion.mujoco_note
    if not motion.switches:
        return None
    if engine == "symbolic-numba":
        return "the event simulations (harness.scenes.phenomena) call the Python q̈"
    if method not in SCIPY_METHODS:
        return f"{method} does not locate events"
    return None


SOFT_EQUALITIES = ("MuJoCo steps a closed chain's tree under its soft equality constraints with implicitfast "
                   "(harness.scenes.phenomena.closures)")


def _constrained_note(s, sc: Scene, engine: str, method: str) -> str | None:
    """Why MuJoCo's ``method`` does not step a closed chain (:data:`SOFT_EQUALITIES`; None: it does, or it is no
    closed chain)."""
    if steps_itself(engine) and constrained(s) and mujoco_own(sc) is None and method != "implicitfast":
        return SOFT_EQUALITIES
    return None


def soft_equalities(scene: dict) -> bool:
    """Whether a scene of the sweep (its record) had MuJoCo step the tree under soft equality constraints: its
    other integrators skipped for it (:func:`_constrained_note`)."""
    return any(r.get("skipped") == SOFT_EQUALITIES for r in scene.get("runs", ()))


def run_task(catalogue, system: str, scene: str, engine: str, method: str, setting: float, repeats: int,
             budget: int, reference: dict) -> dict:
    """One configuration: ``setting`` is ``rtol`` (adaptive) or ``k`` (fixed step ``dt = Δ/k``)."""
    s, sc = get_scene(catalogue, system, scene)
    adaptive = method in (*ADAPTIVE, native.METHOD) and not steps_itself(engine)
    out = {"system": system, "scene": scene, "engine": engine, "method": method,
           "rtol": setting if adaptive else None,
           "dt": None if adaptive else fixed_dt(sc, engine, len(reference["t"]), int(setting))}
    note = _not_applicable(s, engine) or event_note(sc, engine, method) or _constrained_note(s, sc, engine, method)
    if note:
        return {**out, "skipped": note}
    ref = _trajectory("reference", reference["t"], reference["q"], reference["qd"])
    if not adaptive and not steps_itself(engine):
        steps = int(setting) * (len(reference["t"]) - 1) * _STAGES[method]
        if steps > budget:
            return {**out, "skipped": f"over the budget of {budget} evaluations ({steps})"}
    if motion_of(sc)[0].switches and not steps_itself(engine):
        _simulate(s, sc, engine, method, 1e-3, catalogue)  # warm-up: the compiled functions are built lazily, not timed
    times, first = [], None
    for _ in range(max(1, repeats)):
        try:
            tr = _one_run(s, sc, engine, method, setting, out["dt"], budget, reference["t"], catalogue)
        except NotApplicable as exc:  # MuJoCo's own integrator does not apply
            return {**out, "skipped": str(exc)}
        except _Budget:
            return {**out, "skipped": f"over the budget of {budget} evaluations"}
        except (RuntimeError, FloatingPointError, np.linalg.LinAlgError, EngineError) as exc:  # EngineError: an
            return {**out, "error": math.inf, "failed": str(exc).splitlines()[0][:200]}  # unstable MuJoCo run
        times.append(tr.seconds)
        first = first or tr
        if sum(times) > 1.0:  # long runs: fewer repeats
            break
    err = sim.max_error(first, ref) if np.all(np.isfinite(first.q)) and np.all(np.isfinite(first.qd)) else math.inf
    if not err <= 1.0:  # larger than the state's own scale: beyond the method's stability limit
        out["failed"] = "diverged"
    return {**out, "error": err, "seconds": statistics.median(times), "repeats": len(times),
            "evaluations": first.evaluations}   # the median only: 6149 runs' every repeat took bench.json over 2 MB


def fixed_dt(sc: Scene, engine: str, samples: int, k: int) -> float:
    """The step of a fixed-step run refined ``k`` times: ``Δ / k`` (``Δ`` the sample interval) where we integrate
    (:func:`fixed_step` splits an interval at an input's jump); MuJoCo's own steps are all alike, so its ``k = 1``
    is the longest step at most ``Δ`` whose grid holds every sample time and input jump
    (:func:`~harness.scenes.simulate.grid_steps`): a jump between grid points is seen within a step, and the error is
    first order (spring_mass_damper's load step at 1 s of 3 s with ``Δ = 15 ms``: 3.9e-2 at ``k = 1``, 1.2e-3 at
    ``k = 32``, halving with the step, against RK4's order 4)."""
    if steps_itself(engine):
        return sc.horizon / (sim.grid_steps(sc, samples - 1) * k)
    return sc.horizon / (samples - 1) / k


def _one_run(s, sc: Scene, engine, method, setting, dt, budget, t_eval, catalogue=None) -> sim.Trajectory:
    t_eval = np.asarray(t_eval)
    own, motion = mujoco_own(sc), motion_of(sc)[0]
    if steps_itself(engine) and own:  # MuJoCo's dry friction / contact (implicitfast, event_note)
        with np.errstate(all="ignore"):
            return own[0].mujoco_run(s, sc, own[1], dt)
    if motion.switches:  # solve_ivp with the events located (event_note)
        return _simulate(s, sc, engine, method, setting, catalogue)
    if steps_itself(engine) and constrained(s):  # the tree under soft equality constraints (_constrained_note)
        with np.errstate(all="ignore"):
            return mujoco_constrained(s, sc, dt)
    if steps_itself(engine):
        with np.errstate(all="ignore"):
            tr = sim.mujoco_native(s, sc, dt, method)
        tr.evaluations *= _STAGES[method]
        return tr
    dyn = sim.Dynamics(s, sc, "symbolic" if engine in OURS else engine)
    n = len(s.coordinates)

    y0 = np.concatenate([sc.q0, sc.qd0]).astype(float)
    if method == native.METHOD:  # ẏ and the stepping in machine code; the inputs held over each piece
        native.warm(dyn.c, y0, dyn.p, dyn.inputs(0.0))
        start = time.perf_counter()
        try:
            with np.errstate(all="ignore"):
                t, y, dyn.evaluations = native.solve_piecewise(dyn.c, sc, y0, setting, setting, t_eval, dyn.p,
                                                               dyn.inputs, dyn.hold, budget)
        except native.OverBudget:
            raise _Budget from None
        seconds = time.perf_counter() - start
        return _trajectory(f"{engine} {method}", t, y[:n].T, y[n:].T, seconds, dyn.evaluations)
    if engine == "symbolic-numba":  # the integrator calls the machine code of ẏ; only the inputs are Python
        f, p, inputs, u0 = dyn.c.native_state_derivative, dyn.p, bool(sc.inputs), sc.u(0.0, dyn.system)

        def rhs(t, y):
            dyn.evaluations += 1
            if dyn.evaluations > budget:
                raise _Budget
            return f(t, y, p, dyn.inputs(t) if inputs else u0)
    else:
        def rhs(t, y):
            if dyn.evaluations >= budget:
                raise _Budget
            return np.concatenate([y[n:], dyn(t, y[:n], y[n:])])

    rhs(0.0, y0)  # warm-up (first call of every compiled function), not timed
    dyn.evaluations = 0
    start = time.perf_counter()
    with np.errstate(all="ignore"):
        if method == sim.ODEINT:
            t, y, _ = sim.odeint_piecewise(rhs, sc, y0, setting, setting, t_eval, on_piece=dyn.hold)
        elif method in SCIPY_METHODS:
            t, y, _ = sim.solve_piecewise(rhs, sc, y0, method, setting, setting, t_eval, on_piece=dyn.hold)
        else:
            t, y = fixed_step(rhs, sc, y0, method, int(setting), t_eval, on_piece=dyn.hold)
    seconds = time.perf_counter() - start
    return _trajectory(f"{engine} {method}", t, y[:n].T, y[n:].T, seconds, dyn.evaluations)


# --------------------------------------------------------------------------- ours against the fastest engine
CLOSE = 1.3       # a configuration within 1.3 × of its side's fastest in the sweep is a candidate (duel_task)
PICK = 5          # rounds that time the candidates of a side, each once a round, to pick its fastest


def duel_task(catalogue, system: str, scene: str, ours, engine, reference: dict, budget: int,
              repeats: int = REPEATS) -> dict:
    """Our fastest configuration at :data:`ACCURACY` (``ours``, a run of the sweep) against the engines' fastest
    (``engine``), timed again in ``repeats`` alternating pairs in one process, more while the verdict is undecided
    (:func:`~harness.scenes.phenomena.pruning.paired`; ``"repeats"``: the pairs taken). The sweep's times are
    medians of 3 runs taken by different tasks at different times, beside another worker: their single ratio
    flipped the goal's verdict from one bench run to the next (tower_crane/slew 1.07 ×, then 0.67 ×, the same
    code). A pair's two runs share the machine's state, so its ratio cancels what drifts between pairs.
    ``{"ratio": the median of the pairs' ours / engine, "ratio_low", "ratio_high": its ≥ 99.5 % interval
    (:func:`~harness.scenes.phenomena.pruning.ratio_interval`), "ours_all", "engine_all": every run's seconds,
    "verdict"}`` (:func:`~harness.scenes.phenomena.pruning.at_most` 1 ×).

    ``ours`` and ``engine`` may each be a list of candidates (:func:`candidates`): which of them is fastest the sweep's
    medians decide no better than they decide the ratio (tower_crane/slew: our LSODA at rtol 1e-8, 358 evaluations,
    took 1.94 ms in one sweep and 2.58 ms in the next, where rtol 1e-9, 414 evaluations, took 2.45 ms and was chosen:
    ours / MuJoCo 0.82 × then 0.92 ×). Each side's candidates are timed in :data:`PICK` rounds, each once a round, and
    the one of the least time duels; ``"symbolic_configuration"``, ``"fastest_engine_configuration"``: the two."""
    s, sc = get_scene(catalogue, system, scene)
    t_eval = np.asarray(reference["t"])

    def timing(run: dict):
        # a fixed step's k: where we integrate, Δ / dt (MuJoCo steps by its dt alone, fixed_dt)
        setting = run["rtol"] if run.get("rtol") is not None else round(sc.horizon / (len(t_eval) - 1) / run["dt"])
        return lambda: _one_run(s, sc, run["engine"], run["method"], setting, run.get("dt"), budget, t_eval,
                                catalogue).seconds

    def fastest(runs) -> tuple[dict, object]:
        runs = runs if isinstance(runs, list) else [runs]
        timings = [timing(run) for run in runs]
        for time_it in timings:
            time_it()   # warm-up: the compiled functions and models are built lazily, not timed
        if len(runs) == 1:
            return runs[0], timings[0]
        least = [min(t) for t in zip(*([time_it() for time_it in timings] for _ in range(PICK)))]
        k = int(np.argmin(least))
        return runs[k], timings[k]

    (our_run, mine), (their_run, theirs) = fastest(ours), fastest(engine)
    ours_all, engine_all = paired(mine, theirs, repeats, undecided(1.0, at_most=True))
    return judged_at_most(ours_all, engine_all, 1.0) | {"ours_all": ours_all, "engine_all": engine_all,
                                                         "repeats": len(ours_all),
                                                         "symbolic_configuration": label(our_run),
                                                         "fastest_engine_configuration": label(their_run)}


# --------------------------------------------------------------------------- fixed-step integrators
def rk4_step(rhs, t, y, h):
    """Classical Runge-Kutta of order 4."""
    k1 = rhs(t, y)
    k2 = rhs(t + h / 2, y + h / 2 * k1)
    k3 = rhs(t + h / 2, y + h / 2 * k2)
    k4 = rhs(t + h, y + h * k3)
    return y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)


def semi_implicit_euler_step(rhs, t, y, h):
    """Symplectic Euler: ``q̇ ← q̇ + h q̈(q, q̇)``, then ``q ← q + h q̇`` with the new velocity."""
    n = len(y) // 2
    qdd = rhs(t, y)[n:]
    qd = y[n:] + h * qdd
    return np.concatenate([y[:n] + h * qd, qd])


_STEPPERS = {"RK4": rk4_step, "semi-implicit Euler": semi_implicit_euler_step}


def fixed_step(rhs, scene: Scene, y0, method: str, k: int, t_eval, on_piece=None):
    """``k`` equal steps per sample interval; an interval holding an input breakpoint is split there; ``on_piece(lo,
    hi)`` before the steps of each part (``on_piece(None)`` at the end: :meth:`~harness.scenes.simulate.Dynamics.hold`:
    a step ending on a breakpoint holds its own piece's inputs)."""
    step = _STEPPERS[method]
    y = np.asarray(y0, dtype=float)
    ys = [y]
    try:
        for a, b in zip(t_eval[:-1], t_eval[1:]):
            edges = [a, *[t for t in scene.breakpoints if a < t < b], b]
            for lo, hi in zip(edges[:-1], edges[1:]):
                if on_piece is not None:
                    on_piece(lo, hi)
                m = max(1, math.ceil(k * (hi - lo) / (b - a) - 1e-9))
                h = (hi - lo) / m
                for j in range(m):
                    y = step(rhs, lo + j * h, y, h)
            if not np.all(np.isfinite(y)):
                raise FloatingPointError("diverged")
            ys.append(y)
    finally:
        if on_piece is not None:
            on_piece(None)
    return np.asarray(t_eval), np.array(ys).T


# --------------------------------------------------------------------------- effect pruning
def pruning_task(catalogue, system: str, scene: str, repeats: int = REPEATS) -> dict:
    """Idle against pruned by every source (:func:`harness.scenes.phenomena.pruning.measure`: symbolic and
    Pinocchio forward dynamics by odeint 1e-10 (:data:`~harness.scenes.phenomena.pruning.RUN_METHOD`), MuJoCo's own
    RK4 with the pruned effects' disable flags), ``repeats`` alternating pairs of runs in this process
    (:data:`~harness.scenes.phenomena.pruning.REPEATS`); the effects inferred beside the declared ones
    (:func:`harness.scenes.effects.infer`)."""
    from harness.scenes.effects import infer
    from harness.scenes.phenomena.pruning import measure, measure_rows

    s, sc = get_scene(catalogue, system, scene)
    found = infer(s, sc)
    motion, event = motion_of(sc)
    row = {"system": system, "scene": scene, "declared": sorted(found.declared), "inferred": sorted(found.acting),
           "inferred_idle": dict(sorted(found.idle.items())), "idle_elements": dict(sorted(found.idle_elements.items())),
           "declared_idle": sorted(found.declared_idle), "undeclared_acting": sorted(found.undeclared_acting),
           "repeats": repeats}
    if found.rows is not None:  # a constrained tree: its rows inactive (the proof) or needed (the counterexample)
        row["constraint_rows"] = {"inactive": found.rows[0], "why": found.rows[1]}
    rows = measure_rows(s, sc, found, repeats)   # the constraint rows of its tree, where proved inactive
    return {**row, **measure(s, sc, motion, event, catalogue, repeats=repeats)} | ({"rows": rows} if rows else {})


# --------------------------------------------------------------------------- sweep definition and analysis
def configurations(grid: Grid) -> list[tuple[str, str, float]]:
    """``(engine, method, setting)`` of the sweep."""
    out = [("symbolic", m, r) for m in ADAPTIVE for r in grid.rtols]
    out += [("symbolic-numba", m, r) for m in NATIVE_METHODS for r in grid.rtols]
    out += [("pinocchio", m, r) for m in grid.pinocchio_methods for r in grid.settings("pinocchio", m)]
    out += [("pinocchio", m, k) for m in FIXED_METHODS for k in grid.fixed_k]
    out += [("mujoco", m, k) for m in MUJOCO_INTEGRATORS for k in grid.mujoco_k]
    return out


def pareto(runs: list[dict]) -> list[dict]:
    """The runs no other run beats in both wall time and error (sorted by time)."""
    ok = sorted((r for r in runs if math.isfinite(r.get("error", math.inf)) and "seconds" in r),
                key=lambda r: (r["seconds"], r["error"]))
    front, best = [], math.inf
    for r in ok:
        if r["error"] < best:
            front.append(r)
            best = r["error"]
    return front


def fastest_at(runs: list[dict], accuracy: float = ACCURACY) -> dict | None:
    ok = [r for r in runs if r.get("error", math.inf) <= accuracy and "seconds" in r]
    return min(ok, key=lambda r: r["seconds"]) if ok else None


def label(run: dict) -> str:
    setting = f"rtol={run['rtol']:g}" if run.get("rtol") is not None else f"dt={run['dt']:.3g}"
    return f"{run['engine']} {run['method']} {setting}"


def summarize_scene(runs: list[dict], accuracy: float = ACCURACY) -> dict:
    """Pareto frontier per engine and the fastest configuration per engine reaching ``accuracy``."""
    engines = sorted({r["engine"] for r in runs})
    fronts = {e: [label(r) for r in pareto([r for r in runs if r["engine"] == e])] for e in engines}
    best = {e: fastest_at([r for r in runs if r["engine"] == e], accuracy) for e in engines}
    out = {"pareto": fronts,
           "fastest_at_accuracy": {e: (None if b is None else {"configuration": label(b), "seconds": b["seconds"],
                                                                "error": b["error"], "evaluations": b["evaluations"]})
                                   for e, b in best.items()}}
    pair = contenders(runs, accuracy)
    if pair:
        mine, fastest = pair
        out["symbolic_vs_fastest_engine"] = {"ratio": mine["seconds"] / fastest["seconds"],
                                             "symbolic_configuration": label(mine),
                                             "fastest_engine_configuration": label(fastest)}
    return out


def candidates(runs: list[dict], accuracy: float = ACCURACY) -> tuple[list, list]:
    """``(ours, the engines')``: each side's runs reaching ``accuracy`` within :data:`CLOSE` × of its fastest in the
    sweep, fastest first, at most three, and for each of them the run of its family (the same engine and method)
    that reaches ``accuracy`` with the fewest evaluations: what :func:`duel_task` picks from. The sweep's medians
    are three runs beside another worker, the evaluations are the same in every run, and within a family fewer
    evaluations are less work: lightweight_robot's numba LSODA at rtol 1e-9 (479 evaluations, 3.9 ms when timed
    alone) read 6.6 ms in one sweep, out of 1.3 × of rtol 1e-10 (561, 4.6 ms), and the duel took the slower."""
    def close(side):
        fastest = fastest_at(side, accuracy)
        if not fastest:
            return []
        reach = [r for r in side if r.get("error", math.inf) <= accuracy and "seconds" in r]
        near = [r for r in reach if r is not fastest and r["seconds"] <= CLOSE * fastest["seconds"]]
        picked = ([fastest] + sorted(near, key=lambda r: r["seconds"]))[:3]
        for run in list(picked):
            family = [r for r in reach if (r["engine"], r["method"]) == (run["engine"], run["method"])]
            least = min(family, key=lambda r: (r.get("evaluations", math.inf), r["seconds"]))
            if all(least is not r for r in picked):
                picked.append(least)
        return picked
    return close([r for r in runs if r["engine"] in OURS]), close([r for r in runs if r["engine"] not in OURS])


def contenders(runs: list[dict], accuracy: float = ACCURACY) -> tuple[dict, dict] | None:
    """``(ours, the engines')``: the fastest run of our path (:data:`OURS`) and of the engines reaching
    ``accuracy`` (:func:`fastest_at`), or None where either has none: the pair the goal compares (the sweep's ratio,
    then :func:`duel_task`)."""
    ours = fastest_at([r for r in runs if r["engine"] in OURS], accuracy)
    others = fastest_at([r for r in runs if r["engine"] not in OURS], accuracy)
    return (ours, others) if ours and others else None
