"""The engine layer: the registry, every catalogue system loaded in every engine (as exported, joints mapped by
name), one stepping loop for MuJoCo with its spec transforms, Pinocchio's KKT constraints, the adapters built from
a model the engine already loaded (harness.files.importer)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import models
from harness.compare.roundtrip import roundtrip
from harness.engines import ENGINES, SOURCES, SYMBOLIC, engine, evaluate
from harness.engines.base import State, TreeEngine
from harness.errors import InputError
from harness.export.numeric import instantiate

SYSTEMS = list(models.catalogue())


def test_registry_names_every_engine_and_loads_none_of_them():
    assert list(ENGINES) == ["pinocchio", "mujoco", "drake"] and SOURCES == (SYMBOLIC, *ENGINES)
    code = ("import sys; from harness.engines import ENGINES, SOURCES; list(ENGINES); "
            "print(any(m in sys.modules for m in ('mujoco', 'pinocchio', 'pydrake')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.stdout.strip() == "False", out.stderr
    for name in ENGINES:
        cls = ENGINES[name]
        assert issubclass(cls, TreeEngine) and cls.name == name and cls.reads in ("URDF", "MJCF")
    assert ENGINES["mujoco"].integrators and not ENGINES["pinocchio"].integrators
    with pytest.raises(InputError, match="unknown engine 'bullet'; choose one of symbolic, pinocchio, mujoco, drake"):
        engine("bullet")


@pytest.mark.parametrize("name", list(ENGINES))
@pytest.mark.parametrize("system", SYSTEMS)
def test_every_system_loads_in_every_engine(system, name):
    """Each engine loads the exported file of each catalogue system (default parameters): every joint found by
    name, the file as loaded is what we meant (round trip), and at a state every quantity is finite and agrees with
    the symbolic model in lecture coordinates (the conformance suite checks it on hypothesis states)."""
    s = models.get(system)
    note = ENGINES[name].applies(s)
    if note:
        pytest.skip(note)
    tree = instantiate(s, s.default_parameters())
    model = ENGINES[name](tree)
    assert model.joints == [j.name for j in tree.joints]
    assert [str(f) for f in roundtrip(tree, model)] == []
    n = len(s.coordinates)
    rng = np.random.default_rng(3)
    state = State.make(s, rng.uniform(0.2, 0.6, n) * (1 + np.arange(n)), rng.uniform(-1, 1, n))
    ev, ref = model.evaluate(state), evaluate(SYMBOLIC, state)
    assert set(ev.calls) >= {"M", "Cqd", "g", "qdd"}
    for key in ("M", "Cqd", "g", "qdd", "C"):
        a, b = getattr(ev, key), getattr(ref, key)
        assert np.all(np.isfinite(a)), key
        assert np.max(np.abs(a - b)) <= 1e-9 * max(1.0, np.max(np.abs(b))), (key, a, b)


def test_drake_maps_joints_by_name_on_a_branched_tree():
    """The cable pulley's tree is branched: Drake's velocity order is not Pinocchio's, the adapters agree in ours."""
    s = models.get("cable_pulley")
    tree = instantiate(s, s.default_parameters())
    pm, dm = ENGINES["pinocchio"](tree), ENGINES["drake"](tree)
    assert pm.index != list(range(len(tree.joints))) or dm.iv != list(range(len(tree.joints)))
    theta, theta_dot = np.linspace(0.1, 0.5, len(tree.joints)), np.linspace(-1, 1, len(tree.joints))
    a = pm.quantities(theta, theta_dot, {i.name: 0.0 for i in s.inputs})
    b = dm.quantities(theta, theta_dot, {i.name: 0.0 for i in s.inputs})
    for key in ("M", "Cqd", "g_gravity", "qdd", "C"):
        x, y = getattr(a, key), getattr(b, key)
        assert np.max(np.abs(x - y)) <= 1e-12 * max(1.0, np.max(np.abs(x))), key


def test_mujoco_rollout_samples_and_hooks():
    """One stepping loop: samples at k = 0, every, …, steps; ``before`` ahead of every step, ``between`` inside
    ``mj_step1``/``mj_step2`` (which integrate by Euler); a run without it equals MuJoCo's own ``mj_step`` loop."""
    from harness.engines.mujoco_engine import MujocoModel, Options

    s = models.get("pendulum")
    tree = instantiate(s, s.default_parameters())
    runs = []
    for split in (False, True):
        mm = MujocoModel(tree)
        mm.configure(Options(timestep=1e-3, integrator="RK4"))
        mm.set_state([0.5], [0.0])
        seen = []
        out = mm.rollout(10, 4, lambda k: (k, float(mm.theta()[0])), before=seen.append,
                         between=(lambda k: None) if split else None)
        assert [k for k, _ in out] == [0, 4, 8] and seen == list(range(10))
        assert mm.time == pytest.approx(10e-3)
        runs.append([x for _, x in out])
    import mujoco

    mm = MujocoModel(tree)
    mm.configure(Options(timestep=1e-3, integrator="RK4"))
    mm.set_state([0.5], [0.0])
    for _ in range(8):
        mujoco.mj_step(mm.model, mm.data)
    assert runs[0][2] == float(mm.theta()[0])


def test_mujoco_spec_transforms_switch_effects_on():
    """Options clears the disable flags of the effects it names; DryFriction sets frictionloss; the transforms'
    compile is recorded under the scene's label."""
    import mujoco

    from harness.engines import warnings_log
    from harness.engines.mujoco_engine import DryFriction, MujocoModel, Options

    s = models.get("stick_slip")
    tree = instantiate(s, s.default_parameters())
    plain = MujocoModel(tree)
    joint = tree.joints[0].name
    mm = MujocoModel(tree, transforms=[Options(timestep=2e-3, integrator="implicitfast",
                                               enable=("frictionloss", "constraint")),
                                       DryFriction(joint, 0.7, (4e-3, 1.0))], where="MjSpec.compile (test)")
    off = mujoco.mjtDisableBit
    assert plain.model.opt.disableflags & off.mjDSBL_FRICTIONLOSS
    assert not mm.model.opt.disableflags & (off.mjDSBL_FRICTIONLOSS | off.mjDSBL_CONSTRAINT)
    assert mm.model.opt.timestep == 2e-3 and mm.model.opt.integrator == mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    assert mm.model.dof_frictionloss[mm.address(joint)[1]] == 0.7
    warnings_log.drain(tree.system)


def test_pinocchio_kkt_constraints_hold_a_coupling():
    """A coupling row θ_d = offset + ratio θ_i: the constrained acceleration satisfies J a + γ = 0."""
    s = models.get("pulley")
    tree = instantiate(s, s.default_parameters())
    pm = ENGINES["pinocchio"](tree)
    a, b = (j.name for j in tree.joints)
    constraints = pm.constraints([(b, a, 0.1, -0.5)], [])
    theta = np.array([0.3, 0.1 - 0.5 * 0.3])
    theta_dot = np.array([1.0, -0.5])
    acc = constraints.forward_dynamics(theta, theta_dot, {i.name: 0.0 for i in s.inputs}, (), omega=20.0)
    assert acc[1] == pytest.approx(-0.5 * acc[0], abs=1e-12)
    c, scale = constraints.violation(theta, theta_dot, np.ones(2))
    assert c[0] <= 1e-15 and scale[0] == pytest.approx(1.5)


def test_adapters_from_a_loaded_model_read_other_files():
    """harness.files.importer's view: a model the engine loaded, joints by name, continuous joints as cos/sin."""
    from harness.engines.mujoco_engine import MujocoModel, compile_text
    from harness.engines.pinocchio_engine import PinocchioModel, load_urdf
    from harness.files.importer import FIXTURES, without_geometry

    text = FIXTURES[0].read_text().replace('<joint name="j1" type="revolute">', '<joint name="j1" type="continuous">')
    pmodel = load_urdf(text, "fixture")
    joints = [pmodel.names[i] for i in range(1, pmodel.njoints)]
    pin_view = PinocchioModel.loaded(pmodel, joints)
    mj_view = MujocoModel.loaded(compile_text(without_geometry(text), "fixture"), joints)
    mj_view.set_gravity(pin_view.gravity)
    theta, theta_dot = np.linspace(0.2, 0.7, len(joints)), np.linspace(-1, 1, len(joints))
    (M_p, b_p), (M_m, b_m) = pin_view.mass_and_bias(theta, theta_dot), mj_view.mass_and_bias(theta, theta_dot)
    assert np.max(np.abs(M_p - M_m)) <= 1e-12 * np.max(np.abs(M_p))
    assert np.max(np.abs(b_p - b_m)) <= 1e-12 * max(1.0, np.max(np.abs(b_p)))
    assert set(pin_view.subtree_parts(theta)) == set(joints) == set(mj_view.subtree_parts(theta))
