"""Our ẏ and DOP853 both in machine code (:mod:`harness.scenes.native`): scipy's steps, scipy's samples, and the
clear errors of the Python path."""

import dataclasses

import numpy as np
import pytest

import models
from harness.bench import workprecision as wp
from harness.errors import ModelError, NotApplicable
from harness.scenes import native, simulate as sim

# The same steps with the same ẏ: the two differ only in the order in which a stage's sum is rounded, grown over the
# run (measured: at most 3.6e-12 of the state's scale over six scenes at rtol 1e-6 and 1e-9)
SAME_STEPS_TOL = 1e-10

pytestmark = pytest.mark.xdist_group("machine-code")   # numba's compilations shared in one process (conftest.py)


def _runs(name: str, label: str, rtol: float, scene=None):
    system, sc = wp.get_scene(models.CATALOGUE, name, label)
    sc = scene or sc
    dyn = sim.Dynamics(system, sc, "symbolic")
    f, p = dyn.c.native_state_derivative, dyn.p
    t_eval = sim.sample_times(sc)
    y0 = np.concatenate([sc.q0, sc.qd0]).astype(float)
    theirs = sim.solve_piecewise(lambda t, y: f(t, y, p, dyn.inputs(t)), sc, y0, "DOP853", rtol, rtol, t_eval,
                                 on_piece=dyn.hold)
    return theirs, native.solve_piecewise(dyn.c, sc, y0, rtol, rtol, t_eval, p, dyn.inputs, dyn.hold)


@pytest.mark.parametrize("name, label", [("pendulum", "swing"), ("tower_crane", "slew")])
def test_dop853_in_machine_code_takes_scipys_steps(name, label):
    """The same evaluations as scipy's DOP853 around the same ẏ (its initial step, step control and dense output),
    and the same samples to rounding; tower_crane's slew holds its inputs over two pieces (reversed at 2 s)."""
    for rtol in (1e-5, 1e-9):
        (t, y, nfev), (t_native, y_native, nfev_native) = _runs(name, label, rtol)
        assert nfev_native == nfev
        assert np.array_equal(t_native, t)
        assert np.max(np.abs(y_native - y)) <= SAME_STEPS_TOL * max(1.0, np.max(np.abs(y)))


def test_dop853_in_machine_code_stops_with_a_reason():
    """Over its budget of evaluations, inputs it would have to call in Python, a singular M on the way: each ends
    the run with its own error, as the Python path's."""
    system, scene = wp.get_scene(models.CATALOGUE, "pendulum", "swing")
    dyn = sim.Dynamics(system, scene, "symbolic")
    y0 = np.concatenate([scene.q0, scene.qd0]).astype(float)
    with pytest.raises(native.OverBudget):
        native.solve_piecewise(dyn.c, scene, y0, 1e-9, 1e-9, sim.sample_times(scene), dyn.p, dyn.inputs, dyn.hold,
                               budget=100)
    shaken = next(s for s in models.CATALOGUE.scenes("cart_pendulum") if s.inputs_vary_within_steps)
    with pytest.raises(NotApplicable, match="vary within a step"):
        native.solve_piecewise(None, shaken, y0, 1e-6, 1e-6, sim.sample_times(shaken), dyn.p, dyn.inputs)
    system, scene = wp.get_scene(models.CATALOGUE, "spherical_pendulum", "conical")
    at_the_pole = dataclasses.replace(scene, q0=(0.0, *scene.q0[1:]))
    dyn = sim.Dynamics(system, at_the_pole, "symbolic")
    y0 = np.concatenate([at_the_pole.q0, at_the_pole.qd0]).astype(float)
    with pytest.raises(ModelError, match="spherical_pendulum: M is singular"):
        native.solve_piecewise(dyn.c, at_the_pole, y0, 1e-6, 1e-6, sim.sample_times(at_the_pole), dyn.p,
                               dyn.inputs, dyn.hold)
