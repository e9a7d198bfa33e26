"""The Menagerie model test: every exported MJCF in ``urdf/`` loads from its file and steps 1 s under random
controls with zero MuJoCo warnings and a finite state. A warning counter is a failure, never silently wrong
numbers (``harness.engines.mujoco_engine.check_warnings``).

Two starts per model: a random state (θ, θ̇ uniform in (−1, 1)) and MuJoCo's default pose ``qpos0`` (θ = 0).
Some lecture coordinates have singular poses where ``M`` loses rank (the spherical pendulum at θ = 0, the
governor at α = 0, the tower crane at s_5 = 0; stated in the models' docstrings): there a point mass's
inertia is the 1e-15 stand-in and a random torque gives an acceleration beyond MuJoCo's 1e10 limit. A warning
at such a pose (``cond(M) > NEAR_SINGULAR`` just before the step) must still be *reported* — it is — and ends
the run without failing the model; a warning anywhere else fails it."""

from pathlib import Path

import mujoco
import numpy as np
import pytest

import models
from harness.files import untrusted
from harness.engines.mujoco_engine import WARNINGS, check_warnings
from harness.errors import EngineError

URDF_DIR = Path(__file__).resolve().parent.parent / "urdf"
SECONDS = 1.0
CONTROL_PERIOD = 0.01
"""Random controls, uniform in (−1, 1) in the input's SI unit, held for 10 ms (piecewise constant)."""
NEAR_SINGULAR = 1e8
"""cond(M) above which a pose counts as singular: with |M| ~ 1 and unit torques, an acceleration over MuJoCo's
1e10 limit needs a smallest eigenvalue below 1e-10; 1e8 leaves two orders of margin."""


def condition(model, qpos) -> float:
    data = mujoco.MjData(model)
    data.qpos[:] = qpos
    mujoco.mj_forward(model, data)
    M = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, M)
    return float(np.linalg.cond(M))


def step(model, data, rng, what) -> str:
    """Step 1 s; 'completed', or 'reported at a singular pose' (the EngineError raised and checked)."""
    hold = max(1, int(round(CONTROL_PERIOD / model.opt.timestep)))
    for k in range(int(round(SECONDS / model.opt.timestep))):
        if k % hold == 0:
            data.ctrl[:] = rng.uniform(-1.0, 1.0, model.nu)
        before = data.qpos.copy()
        mujoco.mj_step(model, data)
        if any(data.warning[w].number for w in WARNINGS) and condition(model, before) > NEAR_SINGULAR:
            # MuJoCo reports it as an unstable acceleration or, where a pivot of M is the point-mass stand-in
            # (1e-15, its floor mjMINVAL), as a singular inertia matrix
            with pytest.raises(EngineError, match="unstable|inertia matrix too close to singular"):
                check_warnings(model, data, what)
            return "reported at a singular pose"
    check_warnings(model, data, what)
    assert data.time == pytest.approx(SECONDS)
    assert np.all(np.isfinite(data.qpos)) and np.all(np.isfinite(data.qvel))
    return "completed"


@pytest.mark.parametrize("name", sorted(models.catalogue()))
def test_exported_mjcf_steps_one_second_without_warnings(name):
    path = URDF_DIR / f"{name}.xml"
    untrusted.read_model(path)  # our own exports pass the checks a user's file gets
    untrusted.read_model(path.with_suffix(".urdf"))
    model = mujoco.MjModel.from_xml_path(str(path))
    rng = np.random.default_rng(sum(name.encode()))

    data = mujoco.MjData(model)
    data.qpos[:] = rng.uniform(-1.0, 1.0, model.nq)
    data.qvel[:] = rng.uniform(-1.0, 1.0, model.nv)
    step(model, data, rng, f"urdf/{name}.xml from a random state")

    data = mujoco.MjData(model)
    step(model, data, rng, f"urdf/{name}.xml from qpos0")


def test_rollout_steps_alike_in_mujocos_loop_and_ours():
    """``MujocoModel.rollout`` without callbacks between the steps runs them as ``mj_step(m, d, nstep)`` to each
    sample; with a callback, one ``mj_step`` per step from Python. The same steps: the samples are equal bit for bit
    (a sample interval that does not divide the steps, a state away from rest)."""
    from harness.engines.mujoco_engine import MujocoModel
    from harness.export.numeric import instantiate

    system = models.CATALOGUE.get("planar_manipulator")
    runs = []
    for before in (None, lambda k: None):
        model = MujocoModel(instantiate(system, system.default_parameters()))
        model.set_state(np.array([0.4, -0.9]), np.array([1.5, -2.0]))
        samples = model.rollout(103, 7, lambda k: np.concatenate([[k, model.time], model.theta(), model.theta_dot()]),
                                before=before)
        samples.append(np.concatenate([[103, model.time], model.theta(), model.theta_dot()]))  # after the last step
        runs.append(np.array(samples))
    assert len(runs[0]) == 103 // 7 + 2 and runs[0][-2][0] == 98
    assert np.array_equal(runs[0], runs[1])


def test_constant_inputs_are_set_once_and_step_alike():
    """``simulate.input_setter``: constant inputs (and inputs not driven: 0) are set once, the rollout runs in
    MuJoCo's own loop, and the samples equal those of setting them before every step bit for bit; an input that
    varies is set before every step."""
    import dataclasses

    from harness.modeling.scenes import Constant, Sine
    from harness.scenes import simulate as sim

    system = models.CATALOGUE.get("cart_pendulum")
    (f_e,) = system.inputs
    runs = []
    for per_step in (False, True):
        scene = next(s for s in models.CATALOGUE.scenes("cart_pendulum") if s.name == "shaken")
        scene = dataclasses.replace(scene, inputs={f_e.name: Constant(2.5)})
        model = sim.Dynamics(system, scene, "mujoco").model
        model.set_state(np.array([0.2, 0.3]), np.zeros(2))
        before, changes = sim.input_setter(scene, model, 0.002, steps=50)
        assert before is None and changes is None and model.data.ctrl[0] == 2.5
        if per_step:
            before = lambda k: model.set_inputs(sim.held_inputs(scene, model.actuators, k, 0.002))  # noqa: E731
        runs.append(np.array(model.rollout(50, 10, lambda k: np.concatenate([model.theta(), model.theta_dot()]),
                                           before=before)))
    assert np.array_equal(runs[0], runs[1])
    shaken = next(s for s in models.CATALOGUE.scenes("cart_pendulum") if s.name == "shaken")
    assert isinstance(shaken.inputs[f_e.name], Sine)
    before, changes = sim.input_setter(shaken, sim.Dynamics(system, shaken, "mujoco").model, 0.002, steps=50)
    assert before is not None and changes is None   # a sine: set before every step


def test_piecewise_constant_inputs_are_set_where_they_change_and_step_alike():
    """A step input (planar_manipulator/detached: tau_1 steps to 5 N m at 0.6 s, tau_2 constant) is set at step 0 and
    at the first step whose midpoint is at or past 0.6 s only, MuJoCo stepping in its own loop in between; the samples
    equal those of setting the inputs before every step bit for bit, also where the step falls on the step grid, and
    a sample interval that does not divide the steps."""
    import dataclasses

    from harness.modeling.scenes import Step
    from harness.scenes import simulate as sim

    system = models.CATALOGUE.get("planar_manipulator")
    detached = next(s for s in models.CATALOGUE.scenes("planar_manipulator") if s.name == "detached")
    for jump, dt, steps in ((0.6, 0.0015, 2000), (0.3, 0.0015, 2000), (0.0105, 0.0015, 40), (1.0, 0.1, 30)):
        scene = dataclasses.replace(detached, inputs={**detached.inputs, "tau_1": Step(jump, 5.0)})
        runs = []
        for segments in (True, False):
            model = sim.Dynamics(system, scene, "mujoco").model
            model.set_state(np.array([0.3, -0.7]), np.zeros(2))
            before, changes = sim.input_setter(scene, model, dt, steps=steps)
            k_jump = changes[1]
            assert changes == [0, k_jump] and (k_jump + 0.5) * dt >= jump > (k_jump - 0.5) * dt
            seen = []
            runs.append(np.array(model.rollout(steps, 7, lambda k: np.concatenate([model.theta(), model.theta_dot()]),
                                               before=lambda k: (seen.append(k), before(k)),
                                               changes=changes if segments else None)))
            assert seen == (changes if segments else list(range(steps)))
        assert np.array_equal(runs[0], runs[1]), (jump, dt)


def test_a_run_recorded_in_mujocos_loop_is_the_sampled_run_bit_for_bit():
    """``MujocoModel.recorded`` (``mujoco.rollout``: stepped and recorded in MuJoCo's C loop, the samples picked from
    the records) takes the steps of ``rollout`` (a Python stop at every sample) bit for bit: with a step input set
    where it changes and a load held as ``xfrc_applied`` (``ctrl`` and ``xfrc_applied`` held over each stretch), a
    sample interval that does not divide the steps, no change at all; the model ends in the same state, its inputs
    as set."""
    import dataclasses

    from harness.engines.base import Load
    from harness.modeling.scenes import Step
    from harness.scenes import simulate as sim

    system = models.CATALOGUE.get("planar_manipulator")
    detached = next(s for s in models.CATALOGUE.scenes("planar_manipulator") if s.name == "detached")
    scene = dataclasses.replace(detached, inputs={**detached.inputs, "tau_1": Step(0.3, 5.0)})
    for steps, every, driven in ((2000, 7, True), (300, 10, True), (103, 7, False)):
        runs, ends = [], []
        for recorded in (False, True):
            model = sim.Dynamics(system, scene, "mujoco").model
            model.set_state(np.array([0.3, -0.7]), np.array([0.5, 1.0]))
            model.hold_loads([Load("torque", model.tree.links[-1].name, "world", np.array([0.0, 0.4, 0.0]))])
            before, changes = sim.input_setter(scene, model, 0.0015, steps=steps) if driven else (None, None)
            if recorded:
                t, theta, theta_dot = model.recorded(steps, every, before, changes)
                runs.append(np.column_stack([t, theta, theta_dot]))
            else:
                runs.append(np.array(model.rollout(
                    steps, every, lambda k: np.concatenate([[model.time], model.theta(), model.theta_dot()]),
                    before=before, changes=changes)))
            ends.append(np.concatenate([[model.time], model.theta(), model.theta_dot(), model.data.ctrl,
                                        model.data.xfrc_applied.ravel()]))
        assert runs[0].shape == (steps // every + 1, 5) and np.array_equal(runs[0], runs[1]), steps
        assert np.array_equal(ends[0], ends[1]) and np.any(ends[1][-6:] != 0), steps   # the load held to the end


def test_mujocos_own_integrator_runs_affine_maps_and_external_loads():
    """MuJoCo's own RK4 (``simulate.mujoco_native``) beyond identity maps without loads: tree coordinates an affine
    image of the lecture's (two_mass_oscillator's relative angle) with its torques held as ``xfrc_applied`` between
    the input's changes; the spherical pendulum's force at the bob, held likewise; loads that read the state or sit
    off a centre of mass evaluated at every stage of a step by MuJoCo's control callback (hollow_cylinder's friction
    force, which turns with the rod; planar_robot's push at the segment's end). Each the motion of our reference (to
    1e-5 at 1200 steps; the main job asks 1e-6 at its own), fourth order (the error more than 12 × smaller at half
    the step; held from a step's start, the friction force would make it first order); the callback is MuJoCo's no
    more after the run (its 4 calls a step are checked by ``mujoco_native``). A map that is not affine (the
    governor) is refused with its reason."""
    import mujoco

    from harness.scenes import simulate as sim

    for name, label in (("two_mass_oscillator", "twisted"), ("spherical_pendulum", "pushed"),
                        ("hollow_cylinder", "swing"), ("planar_robot", "pushed")):
        system = models.CATALOGUE.get(name)
        scene = next(s for s in models.CATALOGUE.scenes(name) if s.name == label)
        reference = sim.integrate(system, scene, "symbolic")
        dt = scene.horizon / sim.grid_steps(scene, 600)
        coarse, fine = (sim.mujoco_native(system, scene, h) for h in (dt, dt / 2))
        e1, e2 = sim.max_error(coarse, reference), sim.max_error(fine, reference)
        assert e2 < 1e-5 and e1 / e2 > 12, (name, e1, e2)
        assert mujoco.get_mjcb_control() is None
    system = models.CATALOGUE.get("governor")
    scene = models.CATALOGUE.scenes("governor")[0]
    with pytest.raises(ValueError, match="governor: MuJoCo's own integrator here .*an affine image"):
        sim.mujoco_native(system, scene, scene.horizon / 1000)
