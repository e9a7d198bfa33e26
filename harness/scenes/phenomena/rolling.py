"""Rolling or slipping, Exercise 3.17: a sphere on an inclined plane in MuJoCo's contact.

The sphere rolls if ``mu_H ≥ 2/7 tan(alpha)`` and slips otherwise. MuJoCo simulates it as a body with a normal, a
tangential and a rolling joint in contact with a plane (contact and friction switched on, an elliptic friction
cone); the rolling constraint of the model is *not* imposed: the contact has to produce it. Checked: MuJoCo's sphere
rolls or slips as predicted, its rolling run converges to the reference as a soft constraint
(:func:`harness.scenes.base.soft_convergence`), and the threshold it shows, located by bisection on the friction
coefficient to 1e-3, lies within ``THRESHOLD_TOL = 1e-2`` (relative) of the predicted ``2/7 tan(alpha)``: the soft
contact lets the sphere creep by a small slip velocity, which the rolling criterion (slip ≤ 1e-6 of the rolling
velocity) tolerates only near the threshold.
"""

from __future__ import annotations

import time

import numpy as np

from harness.checks import Bound
from harness.engines import simulating
from harness.engines.mujoco_engine import ContactSphere, MujocoModel, Options
from harness.export.numeric import instantiate
from harness.modeling.events import RollSlip
from harness.modeling.system import value_at
from harness.scenes import simulate as sim
from harness.scenes.base import Phenomenon, SceneRun, soft_convergence

THRESHOLD = Bound("rolling threshold", 1e-2, "MuJoCo's rolling threshold (bisection to 1e-3) against 2/7 tan(alpha), "
                  "relative: the soft contact lets the sphere creep")
THRESHOLD_TOL = THRESHOLD.value


def _rolling_model(system, scene, event: RollSlip, mu: float, dt: float):
    dyn = sim.Dynamics(system, scene, "symbolic")
    params = dyn.params
    rpy = tuple(value_at(a, params) for a in event.plane_rpy)
    tree = instantiate(dyn.system, params)
    mm = MujocoModel(tree, transforms=[
        Options(timestep=dt, integrator="implicitfast", enable=("contact", "constraint"), elliptic=True),
        ContactSphere(event.link, params[event.radius], rpy, mu, (2 * dt, 1.0))],
        where="MjSpec.compile (contact scene)")
    return mm, dyn


def mujoco_rolling(system, scene, event: RollSlip, dt: float, mu: float | None = None) -> sim.HybridTrajectory:
    """The sphere on the plane in MuJoCo's contact; ``q`` is the rolling angle; the slip velocity
    ``ẋ − R ω`` is in ``notes['slip']`` over time."""
    mu = event.mu if mu is None else mu
    mm, dyn = _rolling_model(system, scene, event, mu, dt)
    slide, roll = mm.address(event.slide_joint), mm.address(event.roll_joint)
    R = dyn.params[event.radius]
    mm.set_joint(roll, scene.q0[0], scene.qd0[0])
    mm.set_joint(slide, R * scene.q0[0], R * scene.qd0[0])
    steps = int(round(scene.horizon / dt))
    every = max(1, steps // 200)

    def sample(k):
        (x, v), (_, slide_v) = mm.joint_state(roll), mm.joint_state(slide)
        return mm.time, x, v, slide_v - R * v

    start = time.perf_counter()
    out = np.array(mm.rollout(steps, every, sample))
    tr = sim.HybridTrajectory(f"mujoco (contact, mu={mu:.4g}, implicitfast, dt={dt:g})", out[:, 0], out[:, 1:2],
                              out[:, 2:3], time.perf_counter() - start, steps, energy_of=dyn.energy)
    tr.notes["slip"] = out[:, 3]
    return tr


ROLLING_SLIP = 1e-6  # slip velocity at the end / the motion's velocity scale below which the sphere rolls
ROLLING = Bound("rolling criterion", ROLLING_SLIP, "the slip velocity at the end of a rolling scene relative to the "
                "motion's velocity scale (rolls())")
SLIPPING = Bound("slipping criterion", 1.0, "the rolling criterion 1e-6 relative to the measured slip of a slipping "
                 "scene: slipping makes the slip grow linearly in time")


def rolls(tr: sim.HybridTrajectory, scale: float) -> bool:
    """Rolling: at the end of the scene the slip velocity is below 1e-6 of the motion's velocity scale (slipping
    makes it grow linearly in time; the first steps, while MuJoCo's soft contact builds up its force from zero
    penetration, may show a transient slip of ~1e-4 that rolling then removes)."""
    return abs(float(tr.notes["slip"][-1])) <= ROLLING_SLIP * scale


def mujoco_threshold(system, scene, event: RollSlip, dt: float, rel: float = 1e-3) -> float:
    """The smallest friction coefficient at which MuJoCo's sphere rolls, by bisection (to ``rel``)."""
    params = {**system.default_parameters(), **scene.params}
    predicted = event.predicted(params)
    lo, hi = 0.5 * predicted, 2.0 * predicted
    scale = float(np.max(np.abs(mujoco_rolling(system, scene, event, dt, hi).qd))) * params[event.radius]
    while hi - lo > rel * predicted:
        mid = 0.5 * (lo + hi)
        if rolls(mujoco_rolling(system, scene, event, dt, mid), scale):
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


class RollingContact(Phenomenon):
    name = "rolling or slipping in MuJoCo's contact (Exercise 3.17)"
    event = RollSlip

    @staticmethod
    def mujoco_run(system, scene, event, dt):
        return mujoco_rolling(system, scene, event, dt)

    def applies(self, run: SceneRun) -> bool:
        return bool(run.events(RollSlip)) and not run.motion.switches and bool(simulating(run.engines, "contact"))

    def check(self, run: SceneRun) -> None:
        """MuJoCo's sphere in contact: rolls or slips as the predicted threshold says; its threshold located."""
        for event in run.events(RollSlip):
            _roll_slip(run, event)


def _roll_slip(run: SceneRun, event: RollSlip) -> None:
    system, scene, result, ref = run.system, run.scene, run.result, run.reference
    params = {**system.default_parameters(), **scene.params}
    predicted = event.predicted(params)
    dt = scene.horizon / sim.grid_steps(scene, 1000)
    mujoco_contact = mujoco_rolling(system, scene, event, dt / 4)
    scale = float(np.max(np.abs(ref.qd))) * params[event.radius]
    expect_roll = event.mu >= predicted
    slip = abs(float(mujoco_contact.notes["slip"][-1])) / scale
    result.notes["MuJoCo contact: slip velocity at the end / rolling velocity scale"] = slip
    at = f"at mu = {event.mu / predicted:.2f} x 2/7 tan(alpha)"
    if expect_roll:   # the measured slip against the rolling criterion (rolls(): slip <= ROLLING_SLIP)
        result.add(ROLLING.check(f"MuJoCo contact rolls {at}: slip / velocity scale", "mujoco", slip))
    else:             # a lower bound on the slip, recorded as the criterion's share of it
        result.add(SLIPPING.check(f"MuJoCo contact slips {at}: 1e-6 / (slip / velocity scale)", "mujoco",
                                  ROLLING_SLIP / slip if slip > 0 else np.inf))
    if expect_roll:
        fine, _ = soft_convergence(result, "MuJoCo contact", lambda h: mujoco_rolling(system, scene, event, h), ref, dt)
        result.trajectories["mujoco contact"] = fine
    threshold = mujoco_threshold(system, scene, event, dt)
    result.notes["rolling threshold mu: MuJoCo (bisection) / predicted 2/7 tan(alpha)"] = threshold / predicted
    result.add(THRESHOLD.check("MuJoCo's rolling threshold vs 2/7 tan(alpha), relative", "mujoco",
                               abs(threshold / predicted - 1)))


PLUGIN = RollingContact()
