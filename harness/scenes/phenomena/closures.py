"""Closed chains and couplings simulated with their constraints inside the engines.

A map ``θ = φ(q)`` with more tree joints than lecture coordinates constrains the tree. Besides integrating the
mapped forward dynamics (:mod:`harness.scenes.simulate`), each engine simulates the *tree* — every joint its own
coordinate — and imposes the constraints itself:

* **couplings**: a tree joint that is an affine function of another, read off the linear rows of the map
  (gears, ropes, rolling, symmetric arms): ``θ_d = a₀ + a₁ θ_i``.
  MuJoCo: ``<equality><joint joint1=d joint2=i polycoef="a₀ a₁ 0 0 0">``; Pinocchio: the row ``e_d − a₁ e_i``
  of the constraint Jacobian.
* **closures** (``System.closures``): a point held on a plane by a massless guide, ``nᵀ p = value`` — the closed
  chain behind a nonlinear map (the toggle press's slide, the trebuchet's ground in phase 1).
  Pinocchio: the row ``nᵀ J_point`` of the point's frame Jacobian and its drift ``nᵀ a_point(q, v, 0)`` from
  ``pin.getFrameClassicalAcceleration``, both from Pinocchio's own kinematics. MuJoCo: a guide body on two slide
  joints spanning the plane, joined to the point's site by ``<equality><connect>``. The guide's mass is
  ``GUIDE_MASS_RATIO = 1e-5`` of the system's: MuJoCo needs a mass on a moving body, and its constraint solver
  loses the connect force when the guide is many orders lighter than the rest (measured on the toggle press,
  error against the reference at dt = 2.5e-4 s: guide 1e-9 kg 1.9, 1e-6 kg 3e-2, 1e-4 kg and 1e-3 kg 2.1e-3,
  the soft constraint's own error). Its weight is compensated (``gravcomp``) and its inertia cancelled by
  ``qfrc_applied = m_guide q̈_guide`` of the previous step (an error ``m_guide ⃛q dt``): uncompensated, it left a
  ``dt``-independent error of ~11 ``GUIDE_MASS_RATIO`` (1.1e-4 on the trebuchet's throw, which no refinement of
  ``dt`` removes).

Pinocchio solves the constrained dynamics with its KKT solver ``pin.forwardDynamics(model, data, q, v, τ, J, γ)``
(``M a + b = τ + Jᵀλ``, ``J a + γ = 0``), with Baumgarte stabilization ``γ = J̇ v + 2 ω ċ + ω² c``
(``ω = BAUMGARTE_OMEGA``); integrated by DOP853 at 1e-10 as every other engine run, it must stay within
``ENGINE_TOL`` of the reference and its constraint drift below ``DRIFT``: ``max |c_k|`` relative to the scale of
the terms that form the constraint, ``Σ_j |∂c_k/∂θ_j| max(1, max_t |θ_j|)`` (the same policy as every trajectory
check: an error relative to the state's scale, at least 1 in SI units). Why relative: DOP853 controls each step's
local error to ``rtol`` of the state (an RMS over its 2n components, so up to ``√(2n) rtol`` in one of them), and
the constraint sums such errors over its terms; the cable pulley's drum turns by 41 rad while its load moves 4 m,
so an absolute 1e-8 would ask the integrator for 2.4e-10 of the state, below its own 1e-10 per step. Baumgarte's
critically damped error dynamics forget what lies more than a few ``1/ω`` back, so the drift stays within a few
steps' errors: ``DRIFT = 100 rtol`` relative. That holds when the integrator resolves those error dynamics: DOP853's
error control watches the state, not the constraint (a small difference of states), and on a slow motion it took
steps of 0.12 s = 2.5/ω (the drawbridge's raise: 107 evaluations over 1.5 s) over which the stabilization is not
integrated faithfully: drift 6.7e-8, non-monotonic in rtol and ω (3.8e-8 at rtol 1e-9, 3e-10 at 1e-11). So steps are
limited to ``BAUMGARTE_STEP / ω`` (0.025 s).
MuJoCo steps its soft equality constraints (``solref = 2 dt``, the stiffest ``solimp``, implicitfast): its error
is first order in ``dt`` and is checked like its dry friction and contact
(:func:`harness.scenes.base.soft_convergence`).
Lecture coordinates are recovered from ``θ`` by Gauss-Newton on ``φ(q) = θ``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import sympy as sp

from harness.checks import Bound
from harness.engines import simulating
from harness.engines.mujoco_engine import ClosureGuide, JointCoupling, MujocoModel, Options
from harness.errors import ModelError
from harness.export.numeric import instantiate, point_name
from harness.modeling.system import value_at
from harness.scenes import simulate as sim
from harness.scenes.base import ENGINE, Phenomenon, SceneRun, soft_convergence
from harness.scenes.effects import scene_rows

BAUMGARTE_OMEGA = 20.0     # rad/s: constraint errors decay over ~0.1 s, far below the integrator's drift
BAUMGARTE_STEP = 0.5       # steps of at most 0.5/ω: the integrator resolves the stabilization it relies on
DRIFT = Bound("constraint drift", 1e-8, "max |c| of Pinocchio's constrained tree relative to the scale of the terms "
              "forming each constraint: 100 × the integrator's rtol 1e-10")
DRIFT_TOL = DRIFT.value
GUIDE_MASS_RATIO = 1e-5
ROWS_CHECK = "pruned = constraint rows present but idle"   # the open tree against the constrained one


@dataclass(frozen=True)
class Coupling:
    """``θ_dependent = offset + ratio θ_independent`` (an affine row of the map)."""

    dependent: str
    independent: str
    offset: float
    ratio: float


def constrained(system) -> bool:
    """Whether the map constrains the tree (more tree joints than lecture coordinates)."""
    return len(system.joints) > len(system.coordinates)


def couplings(system, dyn: sim.Dynamics) -> list[Coupling]:
    """The couplings of the map's affine rows; the nonlinear rows must be matched by ``system.closures``
    (a :class:`ModelError` saying why where the engines cannot impose the map: :func:`not_imposable`)."""
    found, why = _couplings(system, dyn)
    if why:
        raise ModelError(f"{system.name}: {why}")
    return found


def not_imposable(system, dyn: sim.Dynamics) -> str | None:
    """Why the engines cannot impose the map of ``system`` on its tree as couplings and closures (None: they can):
    its lecture coordinates are not tree joints or affine functions of them, or a joint is an affine function of
    several. The map's dynamics are checked all the same (every engine's forward dynamics mapped by (5.58)–(5.60));
    only the tree simulated with the engines' own constraint rows is not. A nonlinear row without its
    ``System.closures`` is an error of the model (:class:`ModelError`), not a reason."""
    return _couplings(system, dyn)[1]


def _couplings(system, dyn: sim.Dynamics) -> tuple[list[Coupling], str | None]:
    q = system.q
    zeros = np.zeros(len(q))
    u = np.zeros(len(system.inputs))
    A = np.asarray(dyn.c("J_phi", zeros, zeros, dyn.p, u), dtype=float)
    b = np.asarray(dyn.c("phi", zeros, zeros, dyn.p, u), dtype=float).ravel()
    affine = [all(sp.diff(sp.sympify(row), a, c) == 0 for a in q for c in q) for row in system.phi]
    names = [j.name for j in system.joints]
    # independent joints: identity rows first, then other affine rows, until A_I is invertible
    order = sorted(range(len(names)), key=lambda k: (not affine[k], not np.allclose(A[k], np.eye(len(q))[
        int(np.argmax(np.abs(A[k])))]) if np.count_nonzero(A[k]) == 1 else True))
    chosen: list[int] = []
    for k in order:
        if affine[k] and np.linalg.matrix_rank(A[chosen + [k]]) == len(chosen) + 1:
            chosen.append(k)
        if len(chosen) == len(q):
            break
    if len(chosen) < len(q):
        return [], (f"the map's affine rows do not determine the lecture coordinates ({', '.join(map(str, q))}) "
                    f"among the tree's joints ({', '.join(names)}): the engines hold a tree to a map by couplings "
                    "(a joint an affine function of another) and closures (System.closures: a point held on a "
                    "plane); make each lecture coordinate a tree joint, or an affine function of one (a revolute "
                    "joint and a massless link where a point moves on a circle)")
    inverse = np.linalg.inv(A[chosen])
    out, nonlinear = [], 0
    for k in range(len(names)):
        if k in chosen:
            continue
        if not affine[k]:
            nonlinear += 1
            continue
        row = A[k] @ inverse                       # θ_k = b_k + row (θ_I − b_I)
        nonzero = np.flatnonzero(np.abs(row) > 1e-14)
        if len(nonzero) != 1:
            return [], f"joint {names[k]} depends on several joints; not a coupling"
        i = chosen[int(nonzero[0])]
        ratio = float(row[nonzero[0]])
        out.append(Coupling(names[k], names[i], float(b[k] - ratio * b[i]), ratio))
    if nonlinear != len(system.closures):   # a closed chain the model does not declare: an error, not a note
        raise ModelError(f"{system.name}: {nonlinear} nonlinear map row(s) but {len(system.closures)} closure(s); "
                         "declare the closed chain with System.closures")
    return out, None


def rows_of(system, scene) -> list[str]:
    """The constraint rows the engines impose on the tree of ``system`` in ``scene``: its couplings and closures."""
    dyn = sim.Dynamics(system, scene, "symbolic")
    return ([f"coupling {cp.dependent} = " + (f"{cp.offset:g} + " if cp.offset else "")
             + f"{cp.ratio:g} {cp.independent}" for cp in couplings(dyn.system, dyn)]
            + [f"closure {cl.name}" for cl in dyn.system.closures])


class _Recover:
    """Lecture coordinates from tree coordinates: Gauss-Newton on ``φ(q) = θ`` from the last solution, ``q̇`` the
    least-squares solution of ``J q̇ = θ̇`` (MuJoCo's tree meets its soft constraints only approximately)."""

    def __init__(self, dyn: sim.Dynamics, q0):
        self.dyn, self.q = dyn, np.asarray(q0, dtype=float).copy()
        self.zeros, self.u = np.zeros_like(self.q), np.zeros(len(dyn.system.inputs))

    def __call__(self, theta, theta_dot):
        q = self.q.copy()
        for _ in range(20):
            phi, J = self._map(q)
            step = _least_squares(J, theta - phi)
            q += step
            if np.abs(step).max() <= 1e-15 * max(1.0, np.abs(q).max()):
                break
        self.q = q
        return q, _least_squares(self._map(q)[1], theta_dot)

    def for_loads(self, theta, theta_dot):
        """The lecture state the loads are evaluated at: recovered where a load reads it; the loads of the
        catalogue's closed chains are inputs alone (a rope's pull, a load torque), evaluated at zeros they do not
        read, with no recovery at every step."""
        if self.dyn.loads_read_state:
            return self(theta, theta_dot)
        return self.zeros, self.zeros

    def _map(self, q):
        """``φ(q)`` and ``J = ∂φ/∂q``, from one call of the compiled map (:meth:`CompiledModel.map_at`)."""
        phi, J, _ = self.dyn.c.map_at(q, self.zeros, self.dyn.p, self.u)
        return phi, J


def _least_squares(J, r):
    """``x`` minimizing ``|J x − r|`` for a ``J`` of full column rank (more tree joints than coordinates), from the
    normal equations ``JᵀJ x = Jᵀ r``: an ``n × n`` solve where ``lstsq``'s SVD cost 20 µs a call, at every
    MuJoCo step of a scene with loads; the maps' ``J`` are well conditioned (at most 10 over the catalogue), so
    squaring the condition number leaves ``x`` within round-off of ``lstsq``'s (:func:`~harness.scenes.simulate.solve`:
    one coordinate, one division)."""
    return sim.solve(J.T @ J, J.T @ r)


def _start(system, scene, dyn):
    """The tree state at the scene's start: ``θ₀ = φ(q₀)``, ``θ̇₀ = J q̇₀``."""
    q0, qd0 = np.asarray(scene.q0, dtype=float), np.asarray(scene.qd0, dtype=float)
    u = np.zeros(len(dyn.system.inputs))
    theta = np.asarray(dyn.c("phi", q0, qd0, dyn.p, u), dtype=float).ravel()
    return theta, np.asarray(dyn.c("J_phi", q0, qd0, dyn.p, u), dtype=float) @ qd0


# --------------------------------------------------------------------------------------------- Pinocchio
class PinocchioConstrained:
    """The tree in Pinocchio with the couplings and closures as rows of the KKT constraint Jacobian
    (:class:`harness.engines.pinocchio_engine.Constraints`)."""

    def __init__(self, system, scene, rows: bool = True):
        self.dyn = sim.Dynamics(system, scene, "pinocchio")
        self.pm = self.dyn.model
        self.couplings = couplings(self.dyn.system, self.dyn)
        self.constraints = self.pm.constraints(
            [(cp.dependent, cp.independent, cp.offset, cp.ratio) for cp in self.couplings],
            [(point_name(cl.point), cl.normal, value_at(cl.value, self.dyn.params)) for cl in self.dyn.system.closures])
        self.rows = rows   # False: the open tree (rows proved inactive), stepped by pin.aba; its drift still measured
        self.dynamics = self.constraints if rows else self.pm.constraints([], [])
        self.recover = _Recover(self.dyn, scene.q0)
        self.has_loads = bool(self.dyn.load_functions)
        self.evaluations = 0

    def __call__(self, t, y):
        self.evaluations += 1
        n = len(self.pm.index)
        theta, theta_dot = y[:n], y[n:]
        loads = ()
        if self.has_loads:
            lq, lqd = self.recover.for_loads(theta, theta_dot)
            loads = self.dyn.loads(lq, lqd, self.dyn.inputs(t))
        inputs = dict(zip((i.name for i in self.dyn.system.inputs), self.dyn.inputs(t)))
        return np.concatenate([theta_dot, self.dynamics.forward_dynamics(theta, theta_dot, inputs, loads,
                                                                          BAUMGARTE_OMEGA)])


def pinocchio_constrained(system, scene, rtol=1e-10, atol=1e-10, horizon=None, rows: bool = True) -> sim.Trajectory:
    """Pinocchio's constrained tree, integrated by DOP853; lecture coordinates recovered; the largest
    constraint violation, relative to its scale (see :data:`DRIFT`), in ``notes['drift']``. ``rows`` False: the
    open tree, its constraint rows proved inactive (:func:`harness.scenes.effects.constraint_rows_idle`), stepped
    by ``pin.aba`` with no stabilization to resolve (no step limit); its drift is how far it leaves the constraints
    by itself."""
    rhs = PinocchioConstrained(system, scene, rows)
    theta0, theta_dot0 = _start(system, scene, rhs.dyn)
    n = len(theta0)
    start = time.perf_counter()
    t, y, _ = sim.solve_piecewise(rhs, scene, np.concatenate([theta0, theta_dot0]), "DOP853", rtol, atol,
                                  sim.sample_times(scene), end=horizon,
                                  max_step=BAUMGARTE_STEP / BAUMGARTE_OMEGA if rows else np.inf, on_piece=rhs.dyn.hold)
    seconds = time.perf_counter() - start
    recover = _Recover(rhs.dyn, scene.q0)
    theta_scale = np.maximum(1.0, np.max(np.abs(y[:n]), axis=1))
    q, qd, residuals = [], [], []
    for theta, theta_dot in zip(y[:n].T, y[n:].T):
        a, b = recover(theta, theta_dot)
        q.append(a)
        qd.append(b)
        residuals.append(rhs.constraints.violation(theta, theta_dot, theta_scale))
    drift = max((float(np.max(c / scale)) for c, scale in residuals if len(c)), default=0.0)
    q, qd = np.array(q), np.array(qd)
    tr = sim.Trajectory("pinocchio (constrained tree, pin.forwardDynamics KKT, DOP853 1e-10)" if rows else
                        "pinocchio (open tree, rows proved inactive, pin.aba, DOP853 1e-10)", t, q, qd, seconds,
                        rhs.evaluations, energy_of=rhs.dyn.energy)
    tr.notes["drift"] = drift
    return tr


# --------------------------------------------------------------------------------------------- MuJoCo
def mujoco_transforms(system, scene, dt: float, rows: bool = True):
    """The spec transforms of the pruned system's MJCF: the couplings as joint equalities and the closures as
    guide bodies joined by connect equalities (equality and constraint flags on, stiff impedance, implicitfast at
    ``dt``); with the tree and the symbolic dynamics of the pruned system. ``rows`` False: the open tree (its rows
    proved inactive), no equality, the equality and constraint flags off."""
    dyn = sim.Dynamics(system, scene, "symbolic")
    s = dyn.system
    tree = instantiate(s, dyn.params)
    solref = (2 * dt, 1.0)
    if not rows:
        return [Options(timestep=dt, integrator="implicitfast", disable=("equality", "constraint"))], tree, dyn
    transforms = [Options(timestep=dt, integrator="implicitfast", enable=("equality", "constraint"))]
    transforms += [JointCoupling(cp.dependent, cp.independent, cp.offset, cp.ratio, solref)
                   for cp in couplings(s, dyn)]
    transforms += [ClosureGuide(cl.name, point_name(cl.point), tuple(cl.normal), value_at(cl.value, dyn.params),
                                GUIDE_MASS_RATIO * sum(link.mass for link in tree.links), solref)
                   for cl in s.closures]
    return transforms, tree, dyn


def mujoco_constrained(system, scene, dt: float, horizon=None, rows: bool = True, load_actuators=None,
                       extra=()) -> sim.Trajectory:
    """MuJoCo's own stepping of the constrained tree (inputs as ``ctrl``, loads as ``qfrc_applied`` from
    ``mj_applyFT`` at the step's kinematics, between ``mj_step1`` and ``mj_step2``); ``rows`` False: the open tree
    (:func:`mujoco_transforms`). ``load_actuators``: the system's loads as MuJoCo's site actuators instead
    (:class:`~harness.engines.mujoco_engine.LoadActuators`, :func:`~harness.scenes.simulate.load_actuators`), which
    MuJoCo applies in its own step; ``extra``: transforms applied after those (a pruning run's disable flags)."""
    transforms, tree, dyn = mujoco_transforms(system, scene, dt, rows)
    actuated = load_actuators if dyn.load_functions else None
    mm = MujocoModel(tree, transforms=[*transforms, *([actuated] if actuated else []), *extra])
    guides = [t for t in transforms if isinstance(t, ClosureGuide)]
    theta, theta_dot = _start(system, scene, dyn)
    mm.set_state(theta, theta_dot)
    for guide in guides:  # the guide starts where the point is
        guide.place(mm)
    recover = _Recover(dyn, scene.q0)
    has_loads = bool(dyn.load_functions) and actuated is None
    compensations = [guide.compensation(mm) for guide in guides]
    mm.forward()
    end = scene.horizon if horizon is None else horizon
    steps = int(round(end / dt))
    every = max(1, int(round(scene.horizon / dt / 200)))

    def sample(k):  # the tree's state; the lecture coordinates recovered after the timed run
        return mm.time, mm.theta(), mm.theta_dot()

    def between(k):
        if has_loads:
            q, qd = recover.for_loads(mm.theta(), mm.theta_dot())
            mm.apply_loads(dyn.loads(q, qd, scene.u(mm.time, dyn.system)))
        for compensate in compensations:  # the guide's inertia cancelled with its last acceleration (lag dt)
            compensate()

    before, changes = sim.input_setter(scene, mm, dt, steps=steps)
    start = time.perf_counter()  # no callback where there is nothing to do: MuJoCo's loop in C (rollout)
    out = mm.rollout(steps, every, sample, before=before, between=between if has_loads or compensations else None,
                     changes=changes)
    seconds = time.perf_counter() - start
    after = _Recover(dyn, scene.q0)   # its own Gauss-Newton chain, from the start, along the samples
    recovered = [after(theta, theta_dot) for _, theta, theta_dot in out]
    q, qd = np.array([x[0] for x in recovered]), np.array([x[1] for x in recovered])
    return sim.Trajectory(f"mujoco ({'equality constraints' if rows else 'open tree, rows proved inactive'}, "
                          f"implicitfast, dt={dt:g})", np.array([x[0] for x in out]),
                          q, qd, seconds, steps, energy_of=dyn.energy)


class Closures(Phenomenon):
    """The tree with the map's constraints imposed by the engines themselves, where the motion simulates it (up to
    a lift-off, which ends the constraint), compared in the reference's coordinates."""

    name = "closed chains and couplings in the engines"

    def applies(self, run: SceneRun) -> bool:
        return constrained(run.system) and run.motion.tree_view(run) is not None

    def check(self, run: SceneRun) -> None:
        system, scene, result, ref = run.system, run.scene, run.result, run.reference
        dyn = sim.Dynamics(system, scene, "symbolic")
        why = not_imposable(dyn.system, dyn)
        if why:   # the map's own dynamics are checked by the motion; the tree under the engines' rows is not
            result.notes["constrained tree in the engines"] = f"not simulated: {why}"
            return
        horizon, mapping = run.motion.tree_view(run)
        if horizon is not None:
            result.notes["constrained tree simulated until"] = f"{horizon:.6f} s (the event that ends the constraint)"
        if simulating(run.engines, "kkt constraints"):
            tr = mapping(pinocchio_constrained(system, scene, horizon=horizon))
            result.trajectories["pinocchio constrained"] = tr
            result.add(ENGINE.check("constrained tree (pin.forwardDynamics KKT, DOP853 1e-10)", "pinocchio",
                                    sim.max_error(tr, ref)))
            result.add(DRIFT.check("constraint drift max |c_k| / sum_j |J_kj| max(1, |theta_j|)", "pinocchio",
                                   tr.notes["drift"]))
        if simulating(run.engines, "soft constraints"):
            dt = scene.horizon / sim.grid_steps(scene, 4000)

            def simulate(h):
                return mapping(mujoco_constrained(system, scene, h, horizon=horizon))

            fine, fine_dt = soft_convergence(result, "MuJoCo equality constraints", simulate, ref, dt)
            result.trajectories["mujoco constrained"] = fine
        rows = scene_rows(system, scene)   # the inference's (harness.scenes.effects), its proof kept per tree
        if rows and rows[0]:  # proved inactive: the open tree, pruned, against the constrained one (the proof)
            result.notes["pruning: constraint rows left out"] = "; ".join(rows_of(system, scene))
            if "pinocchio constrained" in result.trajectories:
                open_tree = mapping(pinocchio_constrained(system, scene, horizon=horizon, rows=False))
                error = sim.max_error(open_tree, result.trajectories["pinocchio constrained"])
                result.add(ENGINE.check(ROWS_CHECK, "pinocchio", error,
                                        detail="the open tree by pin.aba against the constrained tree (KKT), "
                                               "DOP853 1e-10"))
            if "mujoco constrained" in result.trajectories:
                open_tree = mapping(mujoco_constrained(system, scene, fine_dt, horizon=horizon, rows=False))
                result.add(ENGINE.check(ROWS_CHECK, "mujoco", sim.max_error(open_tree, fine),
                                        detail=f"the open tree (equality and constraint flags off) against the "
                                               f"equality-constrained tree, implicitfast dt={fine_dt:g}"))


PLUGIN = Closures()
