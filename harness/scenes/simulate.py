"""Trajectories of a scene: our compiled symbolic right-hand side, and the forward dynamics of an engine of the
registry (:data:`harness.engines.ENGINES`), each integrated with scipy's ``solve_ivp``; MuJoCo also with its own
integrator (``mj_step``, :meth:`harness.engines.mujoco_engine.MujocoModel.rollout`).

Every source simulates the *pruned* system (only the scene's effects, :func:`harness.modeling.scenes.pruned`).
The reference is the symbolic model with DOP853 at ``rtol = 1e-12``; every other run is compared with it at
the scene's sample times.
"""

from __future__ import annotations

import contextlib
import math
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import odeint, solve_ivp

from harness import kept
from harness.derivation.compile import compiled
from harness.engines import SYMBOLIC, engine
from harness.engines.base import Load, evaluated_loads, load_functions, loads_read_state, to_lecture
from harness.engines.mujoco_engine import STAGES, Options
from harness.errors import EngineError, NotApplicable
from harness.export.numeric import instantiate
from harness.modeling.system import System
from harness.modeling.scenes import Constant, Scene, pruned

# atol two decades below rtol: with atol = rtol = 1e-12 a component passing through 0 is controlled to 1e-12
# absolute, and hollow_cylinder's swing amplified that to a global error of 1.2e-9 (1.4e-10 quarter_car's bump);
# with atol = 1e-14 the largest global error over the catalogue is 6e-11, for 1.16 x the evaluations.
REFERENCE = {"method": "DOP853", "rtol": 1e-12, "atol": 1e-14}


@dataclass
class Trajectory:
    source: str
    t: np.ndarray
    q: np.ndarray        # (len(t), n)
    qd: np.ndarray
    seconds: float
    evaluations: int
    energy: np.ndarray | None = None    # E = T + V at the samples (read it with energies())
    notes: dict = field(default_factory=dict)
    energy_of: Callable | None = field(default=None, repr=False)  # E(q, q̇) of the source, for energies()

    def energies(self) -> np.ndarray | None:
        """``E = T + V`` at the samples, or None: the given ``energy``, else computed from ``energy_of`` at the
        first call (a run whose energy no one reads, a confirmation or a pruning proof, does not pay for it)."""
        if self.energy is None and self.energy_of is not None:
            self.energy = np.array([self.energy_of(a, b) for a, b in zip(self.q, self.qd)])
        return self.energy


@dataclass(frozen=True)
class Event:
    """A switching of a hybrid motion: at ``time`` the branch ``before`` ends and ``after`` begins."""

    time: float
    before: str
    after: str


@dataclass
class HybridTrajectory(Trajectory):
    """A trajectory whose branches switch at ``events`` (:mod:`harness.scenes.phenomena`)."""

    events: list = field(default_factory=list)


def solve(A, b):
    """``x`` of ``A x = b``, the small systems of a map at every evaluation (5.58–5.60): one coordinate is one
    division, written as such (bit for bit LAPACK's 1 × 1 solve, without the 3–5 µs of checks around it)."""
    return b / A[0, 0] if len(b) == 1 else np.linalg.solve(A, b)


class Dynamics:
    """``q̈ = f(t, q, q̇)`` of one scene from one source (``"symbolic"`` or an engine of the registry), in lecture
    coordinates. ``model`` is the engine's adapter (None for the symbolic model)."""

    def __init__(self, system: System, scene: Scene, source: str):
        self.system = pruned(system, scene.effects)
        self.scene = scene
        self.source = source
        self.params = {**system.default_parameters(), **scene.params}
        self.p = np.array([self.params[p.name] for p in self.system.parameters])
        self.c = compiled(self.system)
        self.input_names = [i.name for i in self.system.inputs]
        self.load_functions = load_functions(self.system)  # looked up once: hashing a System walks its expressions
        self.loads_read_state = loads_read_state(self.system)
        self.evaluations = 0
        self.held = None      # the inputs held over the piece being integrated (:meth:`hold`); None: u(t)
        self.no_inputs = None if self.input_names else np.zeros(0)   # u(t) of a system without inputs, made once
        self.model = None if source == SYMBOLIC else engine(source)(instantiate(self.system, self.params))
        # (φ(0), J, J⁻¹) of a constant square map (the identity too), evaluated once: :meth:`at`, mujoco_native
        self.affine = self.c.affine_map(self.p, np.zeros(len(self.input_names))) \
            if self.model is not None and self.c.affine else None

    def __call__(self, t: float, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        self.evaluations += 1
        return self.at(self.inputs(t), q, qd)

    def inputs(self, t: float) -> np.ndarray:
        """``u(t)``: the scene's inputs, or those held over the piece being integrated (:meth:`hold`)."""
        if self.held is not None:
            return self.held
        return self.no_inputs if self.no_inputs is not None else self.scene.u(t, self.system)

    def hold(self, a: float | None, b: float | None = None) -> None:
        """The ``on_piece`` of :func:`solve_piecewise` and :func:`odeint_piecewise`: over the piece ``[a, b]``
        between two of the scene's breakpoints, inputs that are all piecewise constant (steps, constants) are held
        at their value inside the piece (at its midpoint), evaluated once. At ``t = b`` a step already gives the
        next piece's value, and an integrator evaluates there within this piece (a last stage at the step's end,
        LSODA past it): the next piece's input would leak into this one's last step. ``a`` None: ``u(t)`` again."""
        self.held = None
        if a is not None and not self.scene.inputs_vary_within_steps:
            self.held = self.scene.u(0.5 * (a + b), self.system)

    def at(self, u: np.ndarray, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        """``q̈`` at the inputs ``u`` (the scene's at some time, or any other values)."""
        if self.model is None:
            return self.c.forward_dynamics(q, qd, self.p, u)
        inputs = dict(zip(self.input_names, u))
        if self.c.identity_map:  # θ = q, θ̇ = q̇: the engine's forward dynamics is q̈ (no map to evaluate)
            return self.model.forward_dynamics(q, qd, inputs, self.loads(q, qd, u))
        if self.affine is not None:  # θ = φ(0) + J q, J̇ = 0: q̈ = J⁻¹ θ̈ (5.58), J⁻¹ computed once
            phi0, J, J_inv = self.affine
            return J_inv @ self.model.forward_dynamics(phi0 + J @ q, J @ qd, inputs, self.loads(q, qd, u))
        theta, J, J_dot = self.c.map_at(q, qd, self.p, u)
        if J.shape[0] == J.shape[1]:
            # only the engine's forward dynamics: θ̈ of the tree, then q̈ = J⁻¹ (θ̈ − J̇ q̇) (5.58)
            theta_dd = self.model.forward_dynamics(theta, J @ qd, inputs, self.loads(q, qd, u))
            return solve(J, theta_dd - J_dot @ qd)
        # more tree joints than lecture coordinates: M_q q̈ = Jᵀ (h − M J̇ q̇) with M_q = Jᵀ M J (5.58–5.60), the
        # engine's h − M J̇ q̇ (its inverse dynamics at θ̈ = J̇ q̇)
        M, h = self.model.mass_and_forces(theta, J @ qd, inputs, self.loads(q, qd, u), J_dot @ qd)
        return solve(J.T @ M @ J, J.T @ h)

    def loads(self, q, qd, u) -> list[Load]:
        """The external loads (PointForce, BodyTorque) at one state, each engine turns them into forces."""
        return evaluated_loads(self.load_functions, q, qd, self.p, u)

    def mass_matrix(self, t: float, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        """``M(q)`` in lecture coordinates from this source (the symbolic one or the engine's, mapped)."""
        if self.model is None:
            return self.c("M", q, qd, self.p, self.scene.u(t, self.system))
        return self.lecture(t, q, qd).M

    def lecture(self, t: float, q: np.ndarray, qd: np.ndarray):
        """The engine's quantities at one state in lecture coordinates (:func:`to_lecture`)."""
        return to_lecture(self.source, *self._tree_at(self.scene.u(t, self.system), q, qd))

    def _tree_at(self, u, q, qd) -> tuple:
        """The map at one state and the engine's quantities of the tree there (no Christoffel symbols)."""
        theta, J, J_dot = self.c.map_at(q, qd, self.p, u)
        inputs = dict(zip(self.input_names, u))
        tree_quantities = self.model.quantities(theta, J @ qd, inputs, self.loads(q, qd, u), christoffel=False)
        return _MapAt(J, J_dot, qd), tree_quantities

    def energy(self, q: np.ndarray, qd: np.ndarray) -> float:
        """``E = T + V`` of the pruned system (our derivation)."""
        u = np.zeros(len(self.system.inputs))
        return float(self.c("T", q, qd, self.p, u)) + float(self.c("V", q, qd, self.p, u))


@dataclass(frozen=True)
class _MapAt:
    """What :func:`to_lecture` needs of a state: the map's Jacobian, its rate and q̇."""

    J: np.ndarray
    J_dot: np.ndarray
    qd: np.ndarray


SAMPLES = 201


def sample_times(scene: Scene, samples: int = SAMPLES) -> np.ndarray:
    return np.linspace(0.0, scene.horizon, samples)


def grid_steps(scene: Scene, at_least: int) -> int:
    """The fewest steps ``N ≥ at_least`` over the horizon that put every sample time (:func:`sample_times`) and
    every input breakpoint on the step grid ``k · horizon / N`` (and on every grid refined by halving). An input
    jump between two grid points is seen by a fixed-step integrator at a position within its step that depends
    on ``dt``: the error is then first order with a constant that oscillates between neighbouring ``dt``
    (drive_train's load step at 1 s of 3 s falls after 1333⅓ steps of h/4000), which defeats convergence ratios
    and extrapolation."""
    from fractions import Fraction
    from math import lcm

    denominators = [Fraction(b / scene.horizon).limit_denominator(10_000).denominator for b in scene.breakpoints]
    unit = lcm(SAMPLES - 1, *denominators)
    return unit * -(-at_least // unit)


def solve_piecewise(rhs, scene: Scene, y0, method: str, rtol: float, atol: float, t_eval, end: float | None = None,
                    max_step: float = np.inf, jac=None, on_piece=None):
    """``solve_ivp`` restarted at the scene's input breakpoints, from 0 to ``end`` (the horizon by default), steps
    of at most ``max_step``; returns ``(t, y, nfev)`` at ``t_eval``. A piece's end state, where the next piece
    starts, is one more sample time of the piece: read from its last step's interpolant, bit for bit what the
    piece's dense output gives at ``b``, without the dense output of every step (DOP853: 3 more evaluations of
    ``rhs`` a step). ``jac``: the Jacobian an implicit method takes (``solve_ivp``'s). ``on_piece(a, b)``
    before each piece (``on_piece(None)`` at the end): :meth:`Dynamics.hold`."""
    end = scene.horizon if end is None else end
    t_eval = t_eval[t_eval <= end]
    edges = [0.0, *[b for b in scene.breakpoints if b < end], end]
    ts, ys, nfev, y = [], [], 0, np.asarray(y0, dtype=float)
    for k, (a, b) in pieces(edges, on_piece):
        last = k == len(edges) - 2
        inside = piece_samples(t_eval, a, b, last)
        sol = solve_ivp(rhs, (a, b), y, method=method, rtol=rtol, atol=atol,
                        t_eval=inside if last else np.append(inside, b), max_step=max_step,
                        **({} if jac is None else {"jac": jac}))
        if not sol.success:
            raise RuntimeError(f"{scene.name}: integration failed on [{a}, {b}]: {sol.message}")
        ts.append(sol.t[:len(inside)])
        ys.append(sol.y[:, :len(inside)])
        nfev += sol.nfev
        y = sol.y[:, -1].copy()
    return np.concatenate(ts), np.concatenate(ys, axis=1), nfev


def piece_samples(t_eval, a: float, b: float, last: bool) -> np.ndarray:
    """The sample times integrated in the piece ``[a, b)``, ``[a, b]`` if it is the last one (the next piece starts
    at ``b`` and samples it)."""
    return t_eval[(t_eval >= a) & ((t_eval <= b) if last else (t_eval < b))]


def pieces(edges, on_piece):
    """``(k, (a, b))`` of the pieces between ``edges``, with ``on_piece(a, b)`` before each and ``on_piece(None)``
    after the last (also where the integration of a piece failed)."""
    try:
        for k, (a, b) in enumerate(zip(edges[:-1], edges[1:])):
            if on_piece is not None:
                on_piece(a, b)
            yield k, (a, b)
    finally:
        if on_piece is not None:
            on_piece(None)


ODEINT = "LSODA (odeint)"  # scipy's odeint: the same LSODA, its stepping loop in Fortran instead of Python


def odeint_piecewise(rhs, scene: Scene, y0, rtol: float, atol: float, t_eval, max_steps: int = 100_000,
                     on_piece=None):
    """``scipy.integrate.odeint`` (ODEPACK's LSODA, stepping in Fortran; ``solve_ivp``'s LSODA steps in Python)
    restarted at the scene's input breakpoints, each piece's end its critical time (``tcrit``: LSODA steps past the
    last output time and interpolates back, and would integrate the next piece's input); returns ``(t, y, nfev)`` at
    ``t_eval`` like :func:`solve_piecewise`, ``on_piece`` as there."""
    edges = [0.0, *scene.breakpoints, scene.horizon]
    ys, nfev, y = [], 0, np.asarray(y0, dtype=float)
    for k, (a, b) in pieces(edges, on_piece):
        last = k == len(edges) - 2
        inside = piece_samples(t_eval, a, b, last)
        times = np.unique(np.concatenate([[a], inside, [b]]))  # sorted: a first, b last
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # a failure is read from its message below
            out, info = odeint(rhs, y, times, rtol=rtol, atol=atol, tfirst=True, full_output=True,
                               mxstep=max_steps, tcrit=[b])
        if info["message"] != "Integration successful.":
            raise RuntimeError(f"{scene.name}: odeint failed on [{a}, {b}]: {info['message']}")
        ys.append(out[np.searchsorted(times, inside)])
        nfev += int(info["nfe"][-1])
        y = out[-1]
    return np.asarray(t_eval), np.concatenate(ys).T, nfev


def integrate(system: System, scene: Scene, source: str, method: str = "DOP853", rtol: float = 1e-12,
              atol: float = 1e-12, t_eval=None, keep: bool = False) -> Trajectory:
    """The scene's trajectory from ``source``, integrated by ``method`` at the sample times ``t_eval`` (by default
    :func:`sample_times`). ``keep``: a trajectory of our symbolic model is kept for the next run
    (:func:`kept_solution`; its ``seconds`` and ``evaluations`` are then those of the run that computed it)."""
    n = len(system.coordinates)
    t_eval = sample_times(scene) if t_eval is None else t_eval
    made: list = []

    def solve() -> dict:
        dyn = Dynamics(system, scene, source)
        made.append(dyn)

        def rhs(t, y):
            return np.concatenate([y[n:], dyn(t, y[:n], y[n:])])

        start = time.perf_counter()
        y0 = np.concatenate([scene.q0, scene.qd0])
        if method == ODEINT:
            t, y, _ = odeint_piecewise(rhs, scene, y0, rtol, atol, t_eval, on_piece=dyn.hold)
        else:
            t, y, _ = solve_piecewise(rhs, scene, y0, method, rtol, atol, t_eval, on_piece=dyn.hold)
        return {"t": t, "y": y, "seconds": time.perf_counter() - start, "evaluations": dyn.evaluations}

    how = f"{method}, rtol={rtol!r}, atol={atol!r}"
    run = kept_solution(system, scene, how, t_eval, solve) if keep and source == SYMBOLIC else solve()

    def energy(q, qd) -> float:  # E of the pruned system (a run read back makes its dynamics on the first call)
        if not made:
            made.append(Dynamics(system, scene, source))
        return made[0].energy(q, qd)

    y = run["y"]
    return Trajectory(f"{source} ({method}, rtol={rtol:g})", run["t"], y[:n].T, y[n:].T, run["seconds"],
                      run["evaluations"], energy_of=energy)


def scene_identity(scene: Scene) -> str | None:
    """What of ``scene`` decides a trajectory of it (:class:`Dynamics`, :func:`sample_times`): the initial state,
    the horizon, the effects, the parameter values and the inputs. None where an input is not one of the signals of
    :mod:`harness.modeling.scenes` (a function of a model's own: its text does not say what it computes)."""
    from harness.modeling import scenes as signals

    if any(type(signal).__module__ != signals.__name__ for signal in scene.inputs.values()):
        return None
    return repr((tuple(scene.q0), tuple(scene.qd0), scene.horizon, sorted(scene.effects),
                 sorted(scene.inputs.items()), sorted(scene.params.items())))


def kept_solution(system: System, scene: Scene, how: str, t_eval, solve) -> dict:
    """``solve()`` (a dict of arrays and numbers, ``y`` among them) of our symbolic model of ``system`` in
    ``scene``, kept for the next run (:mod:`harness.kept`, ``trajectories/``) under a hash of our installation,
    the numeric environment variables, the model (:meth:`System.fingerprint`: every expression and default), the
    scene (:func:`scene_identity`), the method and tolerances ``how`` and the sample times: read back, every
    number has the bits it was computed with. Computed every run where the scene has an input of a model's own.
    The engines' trajectories are integrated on every run."""
    identity = scene_identity(scene)
    if identity is None:
        return solve()
    where = kept.path("trajectories", f"{system.name}.{scene.name}", kept.numeric_environment(),
                      system.fingerprint(), identity, how, np.asarray(t_eval, dtype=float).tobytes().hex())
    doc = kept.read_kept(where)
    if isinstance(doc, dict) and "y" in doc:
        return {k: np.array(v, dtype=float) if isinstance(v, list) else v for k, v in doc.items()}
    run = solve()
    kept.keep(where, {k: v.tolist() if isinstance(v, np.ndarray) else v for k, v in run.items()})
    return run


def held_inputs(scene: Scene, names, k: int, timestep: float) -> dict:
    """The inputs (by name) MuJoCo holds over step ``k``: each at the step's midpoint ``(k + ½) dt`` — on the
    right side of an input's jump that falls on the step grid (``MjData.time`` accumulates round-off and may
    sit just before it), and second-order accurate for a smooth input (the midpoint rule)."""
    t = (k + 0.5) * timestep
    return {name: scene.inputs[name](t) if name in scene.inputs else 0.0 for name in names}


def input_setter(scene: Scene, model, timestep: float, names=None, steps: int | None = None):
    """``(before, changes)`` of a MuJoCo rollout (:meth:`~harness.engines.mujoco_engine.MujocoModel.rollout`):
    ``before(k)`` holds the scene's inputs of ``names`` (the model's actuators) over step ``k``
    (:func:`held_inputs`), ``changes`` the steps at which their held values change (:func:`input_changes`: where
    every one is piecewise constant, MuJoCo steps in its own loop between them; None: every step). ``(None,
    None)`` where every one of them is a constant (or not driven: 0), set here once — the values every step would
    set —, so that MuJoCo steps in its own loop and a run's time is MuJoCo's, not a Python call per step (measured
    on cart_pendulum: 4.65 µs a step with ``mj_step(nstep)``, about 1.5 µs more with a callback)."""
    names = list(model.driven if names is None else names)
    if all(isinstance(scene.inputs.get(name), (Constant, type(None))) for name in names):
        if names:
            model.set_inputs(held_inputs(scene, names, 0, timestep))
        return None, None
    changes = None if steps is None else input_changes(scene, names, steps, timestep)
    return (lambda k: model.set_inputs(held_inputs(scene, names, k, timestep))), changes


def input_changes(scene: Scene, names, steps: int, timestep: float) -> list[int] | None:
    """The steps ``k < steps`` at which the inputs of ``names`` held over a step (:func:`held_inputs`, at the
    midpoint ``(k + ½) dt``) change, 0 first: where each is piecewise constant (a step, a constant), the first step
    whose midpoint is at or past each of its breakpoints, tested as the signal tests it; None where one varies
    between its breakpoints (a sine, a bump: every step)."""
    signals = [scene.inputs[name] for name in names if name in scene.inputs]
    if not all(getattr(signal, "piecewise_constant", False) for signal in signals):
        return None
    out = {0}
    for signal in signals:
        for b in getattr(signal, "breakpoints", ()):
            k = max(0, math.ceil(b / timestep - 0.5))
            while k > 0 and (k - 1 + 0.5) * timestep >= b:
                k -= 1
            while (k + 0.5) * timestep < b:
                k += 1
            if k < steps:
                out.add(k)
    return sorted(out)


def loads_held(model, loads, reads_state: bool) -> bool:
    """Whether MuJoCo's ``model`` holds the external ``loads`` (:func:`~harness.engines.base.load_functions`' entries)
    between input changes (:func:`held_loads`): there are loads, none reads the state (``reads_state``:
    :func:`~harness.engines.base.loads_read_state` of their system) and each is a constant ``xfrc_applied``
    (:meth:`~harness.engines.mujoco_engine.MujocoModel.holds`: a torque, or a force at its body's centre of mass, in
    world axes), which MuJoCo applies through each stage's Jacobian."""
    return bool(loads) and not reads_state and all(model.holds(kind, where, frame) for kind, where, frame in loads)


def load_actuators(system: System, params: dict):
    """The external loads of ``system`` as MuJoCo's site actuators (:class:`~harness.engines.mujoco_engine.
    LoadActuators`; ``params`` the parameter values by name), where each load is a force in world axes linear in the
    inputs with constant directions, ``f = Σᵢ uᵢ dᵢ``, ``dᵢ = ∂f/∂uᵢ`` of parameters alone: one actuator per input of a
    load, named ``load:input``. None where a load is not such a force (a torque, a force in a link's axes, one that
    reads the state or the time, or one not 0 at zero inputs)."""
    import sympy as sp

    from harness.engines.mujoco_engine import LoadActuators
    from harness.export.numeric import point_name
    from harness.modeling.system import WORLD, BodyTorque, PointForce, value_at

    inputs = {u.name: sp.Symbol(u.name, real=True) for u in system.inputs}
    constants = {p.name for p in system.parameters}
    entries = []
    for f in system.forces:
        if isinstance(f, BodyTorque) or (isinstance(f, PointForce) and f.frame != WORLD):
            return None
        if not isinstance(f, PointForce):
            continue
        force = sp.Matrix(f.force)
        directions = {name: force.diff(u) for name, u in inputs.items()}
        rest = force - sum((d * inputs[name] for name, d in directions.items()), sp.zeros(3, 1))
        if sp.expand(rest) != sp.zeros(3, 1):
            return None   # not linear in the inputs: a term without one, or one that is a product of them
        for name, d in directions.items():
            if d == sp.zeros(3, 1):
                continue
            if any(x.name not in constants for x in d.free_symbols):
                return None   # a direction that turns with the state or the time
            entries.append((f"{f.name}:{name}", name, point_name(f.point), tuple(value_at(c, params) for c in d)))
    return LoadActuators(tuple(entries))


def held_loads(scene: Scene, model, loads, p, names, timestep: float, steps: int):
    """``(hold, changes)`` of a MuJoCo rollout whose ``loads`` it holds (:func:`loads_held`; ``names``: the inputs
    of their system, their arguments, ``p`` its parameter values): ``hold(k)`` evaluates them at the inputs held over
    step ``k`` (:func:`held_inputs`) and sets them as ``xfrc_applied``, ``changes`` the steps at which those inputs
    change (:func:`input_changes`): MuJoCo steps in its own loop in between, no Python call per step. None where an
    input varies within steps (every step would set them)."""
    changes = input_changes(scene, names, steps, timestep)
    if changes is None:
        return None
    at_rest = np.zeros(len(scene.q0))   # what the loads are evaluated at: they read no state

    def hold(k: int) -> None:
        u = np.fromiter(held_inputs(scene, names, k, timestep).values(), float)
        model.hold_loads(evaluated_loads(loads, at_rest, at_rest, p, u))
    return hold, changes


def lecture_state(phi0, J_inv):
    """``(θ, θ̇) -> (q, q̇)`` of an affine map ``θ = φ(0) + J q`` (5.58): ``q = J⁻¹ (θ − φ(0))``, ``q̇ = J⁻¹ θ̇``; what
    :func:`own_rollout` evaluates loads at."""
    return lambda theta, theta_dot: (J_inv @ (theta - phi0), J_inv @ theta_dot)


def own_rollout(model, scene: Scene, timestep: float, integrator: str, steps: int, actuated, loads, p, names,
                holding: bool, at_lecture, check: str) -> tuple[list, float]:
    """MuJoCo's own stepping of ``model`` (configured, at its start state) over ``steps`` steps with the scene's
    inputs and external loads, sampled at :func:`sample_times`: ``(samples (time, θ, θ̇), seconds)``. Inputs of the
    ``actuated`` joints held at each step's midpoint (:func:`input_setter`); ``loads``
    (:func:`~harness.engines.base.load_functions`' entries, ``p`` their system's parameter values, ``names`` its
    inputs) set where the inputs change and held with ``holding`` (:func:`loads_held`; :func:`held_loads`), else
    evaluated at every stage of a step at the lecture state ``at_lecture(θ, θ̇) -> (q, q̇)``, their inputs held as the
    actuators' are (:meth:`~harness.engines.mujoco_engine.MujocoModel.loads_at_each_stage`: the model's
    ``actuation`` flag is cleared for it, MuJoCo's control callback runs only with it). Without a Python call at
    every stage or step, the run is stepped and recorded in MuJoCo's own loop
    (:meth:`~harness.engines.mujoco_engine.MujocoModel.recorded`), not stopped at every sample."""
    every = max(1, int(round(steps / (SAMPLES - 1))))
    holder = held_loads(scene, model, loads, p, names, timestep, steps) if holding else None
    staged = bool(loads) and holder is None
    if staged:
        if at_lecture is None:
            raise NotApplicable(f"{check}: MuJoCo's own stepping with these external loads evaluates them at every "
                                "stage at the lecture state: it needs an affine map θ = φ(0) + J q")
        model.configure(Options(enable=("actuation",)))
    set_inputs, changes = input_setter(scene, model, timestep, actuated, steps=steps)
    before = set_inputs
    if holder is not None:
        hold, changes = holder

        def before(k: int) -> None:
            if set_inputs is not None:
                set_inputs(k)
            hold(k)

    def loads_at(k: int, theta, theta_dot) -> list:   # at a stage's state, the inputs held over step k
        u = np.fromiter(held_inputs(scene, names, k, timestep).values(), float)
        return evaluated_loads(loads, *at_lecture(theta, theta_dot), p, u)
    start = time.perf_counter()
    if staged or (before is not None and changes is None):   # a Python call at every stage, or at every step
        with model.loads_at_each_stage(loads_at, integrator) if staged else contextlib.nullcontext() as calls:
            out = model.rollout(steps, every, lambda k: (model.time, model.theta(), model.theta_dot()),
                                before=before, changes=changes, check=check)  # unstable: a failure
        seconds = time.perf_counter() - start
    else:   # stepped and recorded in MuJoCo's own loop, Python only where the inputs change
        out = model.recorded(steps, every, before, changes, check=check)
        seconds = time.perf_counter() - start
        out = list(zip(*out))
    if staged and calls[0] != steps * STAGES[integrator]:
        raise EngineError(f"{check}: MuJoCo's {integrator} called the loads' callback {calls[0]} times in {steps} "
                          f"steps, not {STAGES[integrator]} a step")
    return out, seconds


def mujoco_native(system: System, scene: Scene, timestep: float, integrator: str = "RK4") -> Trajectory:
    """MuJoCo's own integrator on the exported MJCF of the pruned system, in lecture coordinates: its tree
    coordinates an affine image of them (``θ = φ(0) + J q``, a constant square ``J``: the identity, a relative
    angle), inputs on joints held at each step's midpoint (``ctrl``), external loads of inputs alone that MuJoCo
    holds set where the inputs change (:func:`loads_held`, :func:`held_loads`), other loads evaluated at every stage
    of a step from its state, their inputs held as the actuators' are
    (:meth:`~harness.engines.mujoco_engine.MujocoModel.loads_at_each_stage`); a map that is not affine is a
    ``ValueError``."""
    dyn = Dynamics(system, scene, "mujoco")
    model, loads = dyn.model, dyn.load_functions
    if not dyn.c.affine:
        raise NotApplicable(f"{system.name}: MuJoCo's own integrator here needs tree coordinates that are an affine "
                            "image of the lecture's (θ = φ(0) + J q with a constant square J)")
    phi0, J, J_inv = dyn.affine
    model.configure(Options(timestep=timestep, integrator=integrator))
    model.reset()
    model.set_state(phi0 + J @ np.asarray(scene.q0, float), J @ np.asarray(scene.qd0, float))
    steps = int(round(scene.horizon / timestep))
    holding = loads_held(model, loads, dyn.loads_read_state)
    out, seconds = own_rollout(model, scene, timestep, integrator, steps, None, loads, dyn.p, dyn.input_names,
                               holding, lecture_state(phi0, J_inv),
                               f"{system.name} scene {scene.name}")
    q, qd = np.array([x[1] for x in out]), np.array([x[2] for x in out])
    if not dyn.c.identity_map:
        q, qd = (q - phi0) @ J_inv.T, qd @ J_inv.T
    return Trajectory(f"mujoco (mj_step {integrator}, dt={timestep:g})", np.array([x[0] for x in out]), q, qd,
                      seconds, steps, energy_of=dyn.energy)


def max_error(a: Trajectory, b: Trajectory) -> float:
    """Largest difference at common sample times, each state component (q_i, q̇_i) relative to its own scale
    over the trajectory ``b`` (at least 1 in SI units: a coordinate resting near 0 is compared absolutely), so
    that a large coordinate (an altitude of 39 km) does not hide the error of a small one (its velocity)."""
    t = np.intersect1d(np.round(a.t, 9), np.round(b.t, 9))
    ia = np.isin(np.round(a.t, 9), t)
    ib = np.isin(np.round(b.t, 9), t)
    ya, yb = np.hstack([a.q[ia], a.qd[ia]]), np.hstack([b.q[ib], b.qd[ib]])
    scale = np.maximum(1.0, np.max(np.abs(yb), axis=0))
    return float(np.max(np.abs(ya - yb) / scale))
