"""The smooth motion: a scene without switching events, by every source.

The reference (our symbolic model, DOP853) confirmed by LSODA (``odeint``), each engine's forward dynamics
integrated by DOP853, and MuJoCo's own RK4 (``mj_step``) at a pair ``dt``, ``dt/2`` (tolerances and reasons:
:mod:`harness.scenes.base`).
"""

from __future__ import annotations

import numpy as np

from harness.checks import Bound
from harness.engines import simulating
from harness.errors import NotApplicable
from harness.scenes import simulate as sim
from harness.scenes.base import (CONFIRMATION, CONFIRMATION_RTOL, ENGINE, REFERENCE, Motion, SceneRun, order_gap)

RK4_ORDER = Bound("RK4 order", 1.0, "order deficit p − log2(|x(dt) − x(dt/2)| / |x(dt/2) − x(dt/4)|) of MuJoCo's RK4 "
                  "against its own finer steps (p = 4, or 2 with a midpoint-held input): at most 1, i.e. the observed "
                  "order is at least p − 1 before the asymptotic regime", derived=True)
RK4_START = 500          # steps of the first, coarse mj_step run
RK4_TARGET = 1e-8        # predicted error of the finer run: ENGINE_TOL / 100, >= 100 x the reference's own error
RK4_FLOOR = 1e-9         # a coarse error below this is coarsened: the pair must stay above the reference's error
RK4_REFINEMENTS = 3      # halvings of dt at most while the observed order has not settled (a violent motion: the
                         # coarse run's prediction of dt assumes the asymptotic regime it may not be in)


class Smooth(Motion):
    name = "smooth motion"

    def simulate(self, system, scene, event, source, method="DOP853", rtol=1e-12, atol=1e-12, t_eval=None,
                 catalogue=None) -> sim.Trajectory:
        return sim.integrate(system, scene, source, method=method, rtol=rtol, atol=atol, t_eval=t_eval)

    def check(self, run: SceneRun) -> None:
        system, scene, result = run.system, run.scene, run.result
        # our symbolic model's trajectories are kept for the next run (sim.kept_solution), the engines' made again
        ref = sim.integrate(system, scene, "symbolic", keep=True,
                            **{k: v for k, v in sim.REFERENCE.items() if k != "method"})
        result.trajectories["reference"] = ref
        second = sim.integrate(system, scene, "symbolic", method=sim.ODEINT, rtol=CONFIRMATION_RTOL,
                               atol=CONFIRMATION_RTOL, keep=True)
        result.add(REFERENCE.check(f"reference confirmed ({CONFIRMATION} vs DOP853)", "symbolic",
                                   sim.max_error(second, ref)))
        for engine in run.engines:
            tr = sim.integrate(system, scene, engine, rtol=1e-10, atol=1e-10)
            result.trajectories[engine] = tr
            result.add(ENGINE.check("trajectory (DOP853 1e-10)", engine, sim.max_error(tr, ref)))
        if simulating(run.engines, "stepping"):
            mj_step(run)


def mj_step(run: SceneRun) -> None:
    """MuJoCo's own RK4 (:mod:`harness.scenes.base`): a coarse run at ``RK4_START`` grid steps predicts, with the
    method's order ``p`` (4; 2 with a midpoint-held input that varies within steps), the step whose error is
    ``RK4_TARGET``; the run at ``dt/2`` there gives the error against our reference (``<= ENGINE_TOL``), and the runs
    at ``dt``, ``dt/2``, ``dt/4`` the observed order against MuJoCo's own finer steps, its deficit
    ``p - log2(|x(dt) - x(dt/2)| / |x(dt/2) - x(dt/4)|) <= 1`` (order >= p - 1 before the asymptotic regime). Against
    its own steps, not our reference: a model difference between MuJoCo's and ours is no error of its integrator, and
    against the reference it is a floor the pair's errors meet. Our export's stand-in inertia on a slender rod
    (:func:`~harness.export.mjcf.exported_inertia`), amplified by the unstable motion of a double inverted pendulum,
    put one at 1.7e-9: MuJoCo's errors 6.9e-9 and 2.2e-9 at dt, dt/2 read as order 1.6, where its own steps converge
    at order 4. Where the observed order falls short by more than the bound, the steps are halved (at most
    :data:`RK4_REFINEMENTS` times) and the order taken again: the coarse run's prediction of ``dt`` assumes the
    asymptotic regime, which a violent motion reaches only at finer steps (a double inverted pendulum whirled by a
    follower force to 22 rad/s: its own steps' differences went 5.2e-7, 2.1e-7, 1.9e-8 from 2000 to 16000 steps,
    orders 1.3, then 3.5, also with the force as MuJoCo's own site actuator). A true order below ``p − 1`` stays
    below it."""
    system, scene, result, ref, mujoco_dt = run.system, run.scene, run.result, run.reference, run.mujoco_dt
    held = scene.inputs_vary_within_steps
    order = 2 if held else 4
    try:
        if mujoco_dt:
            dt = mujoco_dt
            coarse = sim.mujoco_native(system, scene, dt)
        else:
            n = sim.grid_steps(scene, RK4_START)
            coarse = sim.mujoco_native(system, scene, scene.horizon / n)
            while sim.max_error(coarse, ref) < RK4_FLOOR and n % 2 == 0 and sim.grid_steps(scene, n // 2) == n // 2:
                n //= 2
                coarse = sim.mujoco_native(system, scene, scene.horizon / n)
            e0 = sim.max_error(coarse, ref)
            k = 0 if held else max(0, int(np.ceil(np.log2(e0 / RK4_TARGET) / order - 1)))
            dt = scene.horizon / (n * 2 ** k)
            if k:
                coarse = sim.mujoco_native(system, scene, dt)
        fine = sim.mujoco_native(system, scene, dt / 2)
        finer = sim.mujoco_native(system, scene, dt / 4)
        d1, d2 = sim.max_error(coarse, fine), sim.max_error(fine, finer)       # against its own finer steps
        halved = 0
        while halved < RK4_REFINEMENTS and order_gap(d1, d2, order, floor=RK4_FLOOR / 10) > RK4_ORDER.value:
            dt, coarse, fine, halved = dt / 2, fine, finer, halved + 1       # not yet where the order settles
            finer = sim.mujoco_native(system, scene, dt / 4)
            d1, d2 = d2, sim.max_error(fine, finer)
        if halved:
            result.notes["mj_step RK4 steps halved: the order had not settled"] = halved
    except NotApplicable as why:
        result.notes["mujoco mj_step"] = str(why)
        return
    e1, e2 = sim.max_error(coarse, ref), sim.max_error(fine, ref)              # against our reference
    result.trajectories["mujoco mj_step"] = fine
    result.notes["mj_step RK4 error against the reference at dt, dt/2"] = [e1, e2]
    result.notes["mj_step RK4 observed order log2(|x(dt) - x(dt/2)| / |x(dt/2) - x(dt/4)|)"] = \
        np.log2(d1 / d2) if d2 > 0 else np.inf
    name = "order deficit {} - log2(|x(dt) - x(dt/2)| / |x(dt/2) - x(dt/4)|)"
    if held:
        result.notes[f"mj_step RK4 error at dt={dt / 2:g} (midpoint-held input)"] = e2
        result.add(RK4_ORDER.check("mj_step RK4 midpoint-held input: " + name.format(2), "mujoco",
                                   order_gap(d1, d2, order, floor=RK4_FLOOR / 10)))
    else:
        result.add(ENGINE.check("mj_step RK4", "mujoco", e2, detail=f"dt={dt / 2:g}"))
        result.add(RK4_ORDER.check("mj_step RK4 " + name.format(4), "mujoco",
                                   order_gap(d1, d2, order, floor=RK4_FLOOR / 10)))
