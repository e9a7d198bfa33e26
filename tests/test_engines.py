"""The engine layer: the registry, every catalogue system loaded in every engine (as exported, joints mapped by
name), one stepping loop for MuJoCo with its spec transforms, Pinocchio's KKT constraints, the adapters built from
a model the engine already loaded (harness.files.importer)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import models
from harness.checks import relative_error, relative_error_rows
from harness.compare import conformance, strategies
from harness.compare.roundtrip import roundtrip
from harness.derivation.compile import compiled
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


STATES = 3          # per system and engine; the conformance suite draws hundreds (harness check)


def lecture_states(system, count: int = STATES, seed: int = 3) -> list[State]:
    """``count`` states of ``system`` at default parameters, drawn like the hypothesis strategy draws them
    (:mod:`harness.compare.strategies`: a coordinate's own range, else angles in [-π, π] and lengths within ±1 m;
    rates within ±5 per second; inputs within ±10), from a fixed seed."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        q = [rng.uniform(*c.range) if c.range else
             rng.uniform(-strategies.ANGLE, strategies.ANGLE) if c.unit == "rad" else
             rng.uniform(-strategies.LENGTH, strategies.LENGTH) for c in system.coordinates]
        qd = rng.uniform(-strategies.RATE, strategies.RATE, len(system.coordinates))
        u = {i.name: rng.uniform(-strategies.INPUT, strategies.INPUT) for i in system.inputs}
        out.append(State.make(system, q, qd, u=u))
    return out


@pytest.mark.parametrize("system", SYSTEMS)
def test_every_system_loads_in_every_engine(system):
    """Each engine of the registry loads the exported file of each catalogue system it applies to (default
    parameters): every joint found by name, the file as loaded is what we meant (round trip), and at a few states
    every quantity (M, C q̇, Christoffel C, g, springs, dampers, q̈ with inputs) agrees with the symbolic model in
    lecture coordinates within the conformance bounds (ROUND_OFF of harness.checks.BOUNDS). One test per system,
    the engines in turn: the symbolic model is compiled once per system."""
    s = models.get(system)
    tree = instantiate(s, s.default_parameters())
    states = lecture_states(s)
    references = []
    for state in states:
        ref = evaluate(SYMBOLIC, state)
        ref.extra["qd"] = state.qd
        references.append(ref)
    loaded = []
    for name in ENGINES:
        if ENGINES[name].applies(s):
            continue
        model = ENGINES[name](tree)
        loaded.append(name)
        assert model.joints == [j.name for j in tree.joints], name
        assert [str(f) for f in roundtrip(tree, model)] == [], name
        for state, ref in zip(states, references):
            ev = model.evaluate(state)
            assert set(ev.calls) >= {"M", "Cqd", "g", "qdd"}, name
            for key in ("M", "Cqd", "g", "qdd", "C"):
                assert np.all(np.isfinite(getattr(ev, key))), (name, key)
            checks = conformance.compare(state, ref, ev)
            assert {c.name for c in checks} >= {"M", "Cqd", "g", "g_spring", "f_damper", "qdd", "C (Christoffel)"}
            assert all(c.basis == conformance.ROUND_OFF.name for c in checks)
            failed = [f"{c.name}: {c.value:.3e} > {c.bound:.1e}" for c in checks if not c.passed]
            assert not failed, f"{system} in {name} at q={state.q.tolist()}, qd={state.qd.tolist()}: {failed}"
    assert loaded == [name for name in ENGINES if not ENGINES[name].applies(s)]


def test_drake_maps_joints_by_name_on_a_branched_tree():
    """The cable pulley's tree is branched: the adapters map joints by name, and Drake and Pinocchio agree in our
    order (tree coordinates, within the round-off bound)."""
    s = models.get("cable_pulley")
    tree = instantiate(s, s.default_parameters())
    pm, dm = ENGINES["pinocchio"](tree), ENGINES["drake"](tree)
    n = len(tree.joints)
    theta, theta_dot = np.linspace(0.1, 0.5, n), np.linspace(-1, 1, n)
    a = pm.quantities(theta, theta_dot, {i.name: 0.0 for i in s.inputs})
    b = dm.quantities(theta, theta_dot, {i.name: 0.0 for i in s.inputs})
    for key in ("M", "Cqd", "g_gravity", "g_spring", "qdd", "C"):
        x, y = getattr(a, key), getattr(b, key)
        assert relative_error(x, y, 1.0) <= conformance.ROUND_OFF.value, key


def test_drake_symbolic_terms_agree_with_its_numbers():
    """The benchmarks' symbolic path (``ToSymbolic``) evaluated at a state is the numeric plant's M, C q̇, g."""
    s = models.get("planar_robot")
    tree = instantiate(s, s.default_parameters())
    dm = ENGINES["drake"](tree)
    theta, theta_dot = np.array([0.3, -0.7, 1.1]), np.array([0.5, -1.0, 2.0])
    M, Cqd, g = dm.symbolic_terms()["at"](theta, theta_dot)
    t = dm.quantities(theta, theta_dot, {i.name: 0.0 for i in s.inputs}, christoffel=False)
    for x, y in ((M, t.M), (Cqd, t.Cqd), (g, t.g_gravity)):
        assert relative_error(x, y, 1.0) <= conformance.ROUND_OFF.value


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
    assert relative_error(M_p, M_m) <= conformance.ROUND_OFF.value
    assert relative_error(b_p, b_m, 1.0) <= conformance.ROUND_OFF.value
    assert set(pin_view.subtree_parts(theta)) == set(joints) == set(mj_view.subtree_parts(theta))


@pytest.mark.parametrize("name", ["tower_crane", "governor", "lightweight_robot"])
def test_a_kept_model_gives_the_numbers_of_a_new_one(name):
    """``models_kept``: one model per engine and numeric tree, handed out again within the block; evaluated at
    one state after another, it gives every number a model built for that state alone gives, bit for bit (an
    evaluation sets the whole state: nothing carries over)."""
    from harness.engines import model, models_kept

    system = models.catalogue().get(name)
    params = system.default_parameters()
    rng = np.random.default_rng(7)
    n = len(system.coordinates)
    first, second = (State.make(system, rng.uniform(0.2, 0.6, n), rng.normal(size=n), params) for _ in range(2))
    assert first.tree is second.tree  # one tree per system and parameter values
    fields = ("M", "Cqd", "g", "g_gravity", "g_spring", "f_damper", "qdd", "C")
    for engine_name in ENGINES:
        if ENGINES[engine_name].applies(system):
            continue
        with models_kept():
            kept = model(engine_name, first.tree)
            kept.evaluate(first)
            assert model(engine_name, second.tree) is kept
            again = kept.evaluate(second)
        alone = ENGINES[engine_name](second.tree).evaluate(second)
        for f in fields:
            a, b = getattr(again, f), getattr(alone, f)
            assert (a is None and b is None) or np.array_equal(a, b), (engine_name, f)
        assert model(engine_name, first.tree) is not kept  # outside the block: built for the call alone


@pytest.mark.parametrize("name", ["tower_crane", "governor", "lightweight_robot"])
def test_mujoco_quantities_leave_its_one_data_at_the_state(name):
    """MuJoCo's adapter evaluates the rest state and the polarization of C on its one ``MjData`` before the state's
    own ``mj_forward``: afterwards the data holds the state (what a rollout or a load reads), and its q̈ is what
    ``forward_dynamics`` gives alone."""
    from harness.engines.mujoco_engine import MujocoModel

    system = models.catalogue().get(name)
    rng = np.random.default_rng(11)
    n = len(system.coordinates)
    state = State.make(system, rng.uniform(0.2, 0.6, n), rng.normal(size=n), system.default_parameters(),
                       {i.name: float(rng.normal()) for i in system.inputs})
    mm = MujocoModel(state.tree)
    quantities = mm.quantities(state.theta, state.theta_dot, state.u, state.loads)
    assert np.array_equal(mm.theta_dot(), state.theta_dot) and np.array_equal(mm.theta(), state.theta)
    alone = MujocoModel(state.tree).forward_dynamics(state.theta, state.theta_dot, state.u, state.loads)
    assert np.array_equal(quantities.qdd, alone)


def test_warnings_of_a_discarded_block_are_left_out():
    """``warnings_log.discarded``: what the main job's export check captures is not reported by the next job of
    its process (the check of a system it exported)."""
    from harness.engines import warnings_log
    from harness.engines.mujoco_engine import MujocoModel

    system = models.get("tower_crane")  # MuJoCo's compiler warns at qpos0, where M is singular
    tree = instantiate(system, system.default_parameters())
    warnings_log.drain(tree.system)
    with warnings_log.discarded():
        MujocoModel(tree)
    assert warnings_log.drain(tree.system) == []
    MujocoModel(tree)
    assert warnings_log.drain(tree.system)


def test_relative_errors_of_rows_are_those_of_each_row():
    """``relative_error_rows`` (the importer's per-joint mass, first moment and inertia errors at once) gives
    ``relative_error(a[k], b[k], scale, symmetric=False)`` for every row, bit for bit: equal rows, a diverged row,
    a non-finite one, rows smaller than the scale."""
    rng = np.random.default_rng(3)
    a, b = rng.normal(size=(6, 3, 3)), rng.normal(size=(6, 3, 3))
    a[1] = b[1]                      # equal: 0
    a[2] *= 1e9                      # diverged: its size shows
    a[3, 0, 0] = np.nan              # not finite: inf
    a[4], b[4] = 1e-9 * a[4], 1e-9 * b[4]   # below the scale
    for scale in (0.0, 0.5):
        assert relative_error_rows(a, b, scale) == [relative_error(x, y, scale, symmetric=False) for x, y in zip(a, b)]
    assert relative_error_rows(np.zeros((0, 3)), np.zeros((0, 3)), 1.0) == []


def test_symmetric_eigen_is_numpys_eigh_bit_for_bit():
    """The right-hand side's eigendecomposition (:func:`harness.derivation.compile.symmetric_eigen`, NumPy's gufunc
    without its Python wrapper) gives what ``numpy.linalg.eigh`` gives, bit for bit, for mass matrices of 1 to 7
    coordinates, and non-finite eigenvalues for a non-finite M (which the regularity test rejects)."""
    from harness.derivation.compile import regular_spectrum, symmetric_eigen

    rng = np.random.default_rng(7)
    for n in range(1, 8):
        for _ in range(50):
            A = rng.normal(size=(n, n)) * 10.0 ** rng.uniform(-3, 3)
            M = A @ A.T + np.eye(n) * 10.0 ** rng.uniform(-6, 0)
            w, V = symmetric_eigen(M)
            w_np, V_np = np.linalg.eigh(M)
            assert np.array_equal(w, w_np) and np.array_equal(V, V_np)
    bad = np.array([[np.nan, 0.0], [0.0, 1.0]])
    assert not regular_spectrum(symmetric_eigen(bad)[0])


def test_two_coordinates_solve_in_closed_form_as_lapack_does():
    """``q̈`` of two coordinates (:meth:`~harness.derivation.compile.CompiledModel._forward_dynamics_2`: the
    eigenvalues in closed form, Cramer's rule) is the eigendecomposition's to rounding, ``45 cond(M) ε ‖q̈‖``:
    every two-coordinate system of the catalogue at 20 states. The closed-form eigenvalues are LAPACK's to
    ``4 ε ‖M‖`` on random symmetric matrices (positive definite of every conditioning up to ``1e19``, indefinite,
    negative) and give its regularity verdict, except within a factor 1.5 of the test's threshold."""
    from harness.derivation.compile import eigenvalues_2, regular_spectrum, symmetric_eigen, SINGULAR_M

    two = [s for s in SYSTEMS if len(models.catalogue().get(s).coordinates) == 2]
    assert len(two) >= 8
    for name in two:
        system = models.catalogue().get(name)
        c = compiled(system)
        for state in lecture_states(system, 20, seed=11):
            q, qd, p, u = state.q, state.qd, state.p, np.array([state.u[i.name] for i in system.inputs])
            M, Cqd, g, f_np = c.terms(q, qd, p, u)
            w, V = symmetric_eigen(M)
            expected = V @ ((V.T @ (f_np - Cqd - g)) / w)
            scale = np.linalg.norm(expected) * w[-1] / w[0] * 1e-14
            assert np.allclose(c.forward_dynamics(q, qd, p, u), expected, rtol=0, atol=scale), (name, q)
    rng = np.random.default_rng(5)
    for _ in range(2000):
        w_true = np.sort(10.0 ** rng.uniform(-16, 3, 2)) * rng.choice([1, 1, 1, -1], 2)
        angle = rng.uniform(0, np.pi)
        R = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
        M = (R * w_true) @ R.T
        M = (M + M.T) / 2
        w = eigenvalues_2(M[0, 0], M[1, 0], M[1, 1])
        lapack = symmetric_eigen(M)[0]
        norm = np.abs(lapack).max()
        assert abs(w[1] - lapack[1]) <= 4e-16 * norm
        if lapack[0] > 0:   # a mass matrix (positive definite): w₀ too
            assert abs(w[0] - lapack[0]) <= 4e-16 * norm
        near = lapack[1] > 0 and 0.5 * SINGULAR_M < lapack[0] / lapack[1] < 1.5 * SINGULAR_M
        if not near:
            assert regular_spectrum(w) == regular_spectrum(lapack), M
    assert not regular_spectrum(eigenvalues_2(np.nan, 0.0, 1.0))
    assert not regular_spectrum(eigenvalues_2(-1.0, 0.0, -2.0))


MAPPED = [s for s in SYSTEMS if not models.get(s).identity_map]  # read from the model: nothing derived to collect


@pytest.mark.parametrize("name", MAPPED)
def test_simulation_through_a_map_gives_the_evaluations_qdd(name):
    """What a simulation calls through a map ``θ = φ(q)`` (:class:`harness.scenes.simulate.Dynamics`): a constant
    square map with ``φ(0)``, ``J``, ``J⁻¹`` evaluated once, a map with more tree joints than coordinates by the
    engine's ``mass_and_forces`` projected (5.58–5.60), gives the ``q̈`` of the engine's full evaluation
    (:func:`~harness.engines.base.to_lecture`) to round-off, and ``mass_and_forces`` the quantities' ``M`` and
    ``τ − C θ̇ − g``."""
    from harness.catalogue import repository
    from harness.scenes.simulate import Dynamics

    catalogue = repository()
    system, scene = catalogue.get(name), catalogue.scenes(name)[0]
    for engine_name in ("pinocchio", "mujoco"):
        if ENGINES[engine_name].applies(system):
            continue
        dynamics = Dynamics(system, scene, engine_name)
        c = dynamics.c
        assert (dynamics.affine is not None) == (c.constant_map and c.derivation.J_phi.is_square)
        params, errors = {**system.default_parameters(), **scene.params}, []
        for state in lecture_states(dynamics.system):
            state = State.make(dynamics.system, state.q, state.qd, params, state.u)
            u = np.array([state.u[i.name] for i in dynamics.system.inputs])
            simulated = dynamics.at(u, state.q, state.qd)
            evaluated = ENGINES[engine_name](state.tree).evaluate(state).qdd
            errors.append(relative_error(simulated, evaluated))
            assert errors[-1] < 1e-9, (engine_name, simulated, evaluated)   # measured ≤ 3.1e-15 over the catalogue
            adapter = ENGINES[engine_name](state.tree)
            M, h = adapter.mass_and_forces(state.theta, state.theta_dot, state.u, state.loads)
            t = adapter.quantities(state.theta, state.theta_dot, state.u, state.loads, christoffel=False)
            assert relative_error(M, t.M) < 1e-12
            assert relative_error(h, t.tau_input + t.f_damper - t.Cqd - t.g_gravity - t.g_spring) < 1e-9
            # at an acceleration a (the map's J̇ q̇): h − M a (Pinocchio: its inverse dynamics pin.rnea at a)
            a = np.linspace(-1.0, 1.0, len(state.theta))
            M_a, h_a = adapter.mass_and_forces(state.theta, state.theta_dot, state.u, state.loads, a)
            assert np.array_equal(M_a, M)
            assert relative_error(h_a, h - M @ a) < 1e-9


@pytest.mark.parametrize("name, label", [("planar_manipulator", "swing"), ("spherical_pendulum", "conical")])
def test_a_tree_without_force_elements_skips_them_bit_for_bit(name, label):
    """Pinocchio's adapter evaluates no force element of a pruned tree that has none (``force_free``: ``τ`` = 0
    handed to ``pin.aba``, nothing summed): the same θ̈ and the same tree quantities, bit for bit, as the general
    path that forms each kind's (zero) forces and sums them."""
    from harness.scenes.effects import infer
    from harness.scenes.simulate import Dynamics

    system = models.get(name)
    scene = next(s for s in models.CATALOGUE.scenes(name) if s.name == label)
    lean, lean_scene = infer(system, scene).pruned(system, scene)
    dyn = Dynamics(lean, lean_scene, "pinocchio")
    assert dyn.model.force_free
    rng = np.random.default_rng(3)
    for _ in range(5):
        theta, theta_dot = rng.uniform(-1, 1, (2, len(lean.coordinates)))
        skipped = dyn.model.forward_dynamics(theta, theta_dot, {})
        quantities = dyn.model.quantities(theta, theta_dot, {}, christoffel=False)
        dyn.model.force_free = False
        try:
            assert np.array_equal(dyn.model.forward_dynamics(theta, theta_dot, {}), skipped)
            general = dyn.model.quantities(theta, theta_dot, {}, christoffel=False)
        finally:
            dyn.model.force_free = True
        for key in ("qdd", "g_spring", "f_damper", "tau_input", "M"):
            assert np.array_equal(getattr(general, key), getattr(quantities, key))


@pytest.mark.parametrize("name", ["rotating_body", "two_mass_oscillator", "quarter_car", "toggle_press"])
def test_a_spring_force_is_judged_on_the_size_of_its_terms(name):
    """``g_spring`` is a difference, ``c (L − l₀) ∂L/∂q`` (a joint spring's ``k (θ − θ₀)``): its round-off is relative
    to the size of the terms ``c L``, ``c l₀`` (``Derivation.g_spring_terms``), not to the force, which vanishes at
    the rest length. The terms bound the force at every drawn state; at the rest length the force is round-off
    while the terms are not, and every engine agrees within the tolerance relative to them."""
    system = models.catalogue().get(name)
    for batch in strategies.system_states(system, 12):
        for state in batch:
            ref = evaluate(SYMBOLIC, state)
            terms = ref.extra["g_spring_terms"]
            assert np.all(terms >= np.abs(ref.g_spring) * (1 - 1e-12)), (terms, ref.g_spring)
    if name != "rotating_body":
        return
    params = system.default_parameters() | {"l_f0": system.default_parameters()["l_f_0"]}  # at rest at phi = 0
    state = State.make(system, np.zeros(1), np.zeros(1), params)
    ref = evaluate(SYMBOLIC, state)
    ref.extra["qd"] = state.qd
    terms = float(ref.extra["g_spring_terms"][0])
    assert abs(ref.g_spring[0]) < 1e-12 * terms and conformance.scales(ref)["g_spring"] >= terms > 0
    for engine_name in ENGINES:
        if not ENGINES[engine_name].applies(system):
            other = evaluate(engine_name, state)
            assert relative_error(other.g_spring, ref.g_spring, conformance.scales(ref)["g_spring"]) \
                <= conformance.ROUND_OFF.value


def test_mujocos_polarized_c_is_judged_with_the_gravity_it_subtracts():
    """MuJoCo's Christoffel ``C`` is polarized from ``qfrc_bias(v ± s e_j)``, which holds gravity: its round-off is
    ``ε |g_θ| / s`` per entry, summed by the map ``Jᵀ C_θ J`` (``base._polarized_gravity``). The ball on the beam with
    its smallest drawn ball (``r_K`` = 0.05 m: ``J`` holds 1/r_K) nearly at rest, where the longer profile had found
    MuJoCo's ``C`` at 0.1 of the bound relative to ``|J|ᵀ|M||J|`` alone: the error is within that round-off, and far
    within the bound relative to the scale that holds it."""
    from harness.checks import relative_error
    from harness.engines.base import _polarized_gravity

    system = models.catalogue().get("ball_on_beam")
    params = {"m_K": 1.4154347477575673, "r_K": 0.05, "m_B": 4.856214513410625, "I_xxB": 0.0028855,
              "I_yyB": 0.9988221153363342, "I_zzB": 1.0000366153363343, "g": 13.95263825445709}
    state = State.make(system, [-1.2247438530852968, 0.8563845923321005], [0.0, -1e-05], params)
    ref, mj = evaluate(SYMBOLIC, state), evaluate("mujoco", state)
    ref.extra["qd"] = state.qd
    gravity_round_off = _polarized_gravity(state.J, mj.extra.get("C_subtracted", np.zeros(3)))
    assert np.abs(mj.C - ref.C).max() <= 4 * np.finfo(float).eps * gravity_round_off
    scale = max(conformance.scales(ref)["C"], mj.extra["map_scale"]["C"])
    assert scale >= gravity_round_off
    assert relative_error(mj.C, ref.C, scale) <= 0.01 * conformance.ROUND_OFF.value


def _slender_pendulum(m: float, length: float):
    """A rod of mass ``m`` and length ``length`` swinging about x at its end, slender: no inertia about its own
    axis z, the lecture's and many papers' idealization (the link's tensor is singular, not zero)."""
    from harness.modeling import Coordinate, Gravity, Inertia, Joint, Link, Parameter, System, standard_gravity

    mass, l = Parameter("m", m, "kg", "mass of the rod"), Parameter("l", length, "m", "length of the rod")
    phi = Coordinate("phi", "rad", "angle of the rod from the downward vertical")
    J = mass * l**2 / 12
    return System(name="slender_rod", title="Slender rod", lecture="a test", coordinates=(phi,),
                  links=(Link("rod", mass=mass, com=(0, 0, -l / 2), inertia=Inertia(J, J, 0)),),
                  joints=(Joint("phi", "revolute", "world", "rod", axis="x"),),
                  gravity=Gravity(standard_gravity(), (0, 0, -1)), forces=())


@pytest.mark.parametrize("build", ["slender", "point mass"])
def test_the_stand_in_inertia_mujoco_needs_is_not_in_what_it_is_compared_with(build):
    """MuJoCo refuses a moving body with a principal inertia below mjMINVAL: our export gives a point mass, and a
    slender rod (0 about its axis: MuJoCo's compiler had failed on it with "inertia must have positive eigenvalues"),
    the stand-in ``ε E`` (ε = 1e-15). On a small body that is no round-off: a pendulum of 1 g on 2 cm has M = 4e-7
    kg m², and MuJoCo's ``mj_fullM`` is off ours by ε, 2500 times the tolerance 1e-12 of M. The adapter takes the
    stand-in's terms out (``MujocoModel.stand_in``: ``ε J_ωᵀ J_ω`` in M, ``ε J_ωᵀ J̇_ω q̇`` in the bias): what it
    reports agrees with our derivation to round-off, and what it took out is exactly the stand-in."""
    import mujoco

    from harness.compare.conformance import FLOAT64_RTOL, compare
    from harness.engines import symbolic
    from harness.engines.mujoco_engine import MujocoModel
    from harness.export.numeric import MUJOCO_POINT_MASS_INERTIA

    system = _slender_pendulum(1e-3, 0.02) if build == "slender" else models.get("pendulum")
    state = State.make(system, [0.4], [3.0], None if build == "slender" else {"m": 1e-3, "l": 0.02})
    mm = MujocoModel(state.tree)
    assert len(mm.stand_ins) == 1
    from harness.compare.roundtrip import items

    assert max(item.error for item in items(state.tree, mm)) < 1e-15   # the stand-in is what was meant
    ref = symbolic.evaluate(state)
    ref.extra["qd"] = state.qd
    checks = compare(state, ref, mm.evaluate(state))
    assert all(c.ratio < 0.05 for c in checks), [(c.name, c.ratio) for c in checks if c.ratio >= 0.05]
    M = np.zeros((mm.model.nv, mm.model.nv))
    mujoco.mj_fullM(mm.model, mm.data, M)           # MuJoCo's own, at the state evaluate() left in its data
    assert abs(M[0, 0] - ref.M[0, 0] - MUJOCO_POINT_MASS_INERTIA) <= 1e-3 * MUJOCO_POINT_MASS_INERTIA
    assert abs(M[0, 0] - ref.M[0, 0]) > 100 * FLOAT64_RTOL * ref.M[0, 0]   # what the check would have failed on


def test_a_tendon_evaluates_the_elements_it_has_zero_or_not():
    """A tendon's spring or damper that is not in the model is None in the numeric tree and is not evaluated; one
    the scene sets to 0 (the idle model's, :func:`~harness.modeling.scenes.with_idle_effects`) is a number and is
    evaluated as any other: leaving it out is the pruned model's business, never the adapter's. Seen at a velocity
    of nan: a damper evaluated at 0 gives nan, one not in the model nothing."""
    import dataclasses

    from harness.engines.base import spring_damper_forces
    from harness.modeling.scenes import with_idle_effects

    toggle = models.get("toggle_press")
    (tendon,) = instantiate(toggle, toggle.default_parameters()).tendons
    assert tendon[3:] == (500.0, 1.2, None)                      # spring_F: a spring alone
    manipulator = models.get("planar_manipulator")
    scene = next(s for s in models.CATALOGUE.scenes("planar_manipulator") if s.name == "detached")
    idle, idle_scene = with_idle_effects(manipulator, scene)
    (tendon,) = instantiate(idle, {**idle.default_parameters(), **idle_scene.params}).tendons
    assert tendon[3] == 0.0 and tendon[5] == 0.0                 # spring_e, damper_e: c_e = d_e = 0, present
    for tree, damper_evaluated in ((instantiate(toggle, toggle.default_parameters()), False),
                                   (instantiate(idle, {**idle.default_parameters(), **idle_scene.params}), True)):
        tree = dataclasses.replace(tree, joint_stiffness={}, joint_damping={})   # the tendon alone
        nv = len(tree.joints)
        a, b = tree.tendons[0][1:3]
        position = {a: np.zeros(3), b: np.array([1.0, 0.5, 0.0])}.get
        jacobian = {a: np.zeros((3, nv)), b: np.ones((3, nv))}.get
        f_spring, f_damper = spring_damper_forces(tree, nv, np.zeros(nv), np.full(nv, np.nan), position, jacobian,
                                                  {}, {})
        assert np.isfinite(f_spring).all() and f_spring.any() == (tree.tendons[0][3] != 0.0)
        assert np.isnan(f_damper).any() == damper_evaluated
