"""The hypothesis strategies build valid physical objects (never filtered): positive parameters, inertia
tensors positive definite and satisfying the triangle inequality, states accepted by State.make."""

import numpy as np
from hypothesis import HealthCheck, given, settings, strategies as st

import models
from harness.export.numeric import check_inertia, instantiate
from harness.compare.strategies import STATES_PER_DRAW, draws, parameters


# each example draws for every system of the catalogue (20 x 32 draws per test); the conformance checks draw their
# 200 states per system from the same strategies and would fail on an unphysical one
PER_SYSTEM = settings(max_examples=20)


@PER_SYSTEM
@given(st.data())
def test_random_parameters_are_physical(data):
    for system in models.catalogue().values():
        params = data.draw(parameters(system))
        for p in system.parameters:
            p.check(params[p.name])
        for link in instantiate(system, params).links:
            check_inertia(link.name, link.mass, link.inertia)
            moments = np.sort(np.linalg.eigvalsh(link.inertia))
            assert moments[0] + moments[1] >= moments[2] * (1 - 1e-12)


@settings(max_examples=20, suppress_health_check=[HealthCheck.large_base_example])  # a batch of every system at once
@given(st.data())
def test_random_states_share_their_parameter_draw(data):
    """The states the checks draw (a parameter draw's batch): the right shapes, STATES_PER_DRAW of them with one
    parameter draw (one engine model each)."""
    for system in models.catalogue().values():
        batch = data.draw(draws(system))
        assert len(batch) == STATES_PER_DRAW
        for state in batch:
            assert state.q.shape == state.qd.shape == (len(system.coordinates),)
            assert np.all(np.isfinite(state.q)) and set(state.u) == {i.name for i in system.inputs}
        assert all(state.params == batch[0].params for state in batch)
        assert all(state.tree is batch[0].tree for state in batch)  # one tree: each engine builds one model


def test_a_systems_kept_states_are_the_drawn_ones_bit_for_bit(tmp_path, monkeypatch):
    """:func:`system_states` keeps what it drew (``states/`` beside the derivation cache); read back (a new process:
    the in-process copy dropped) they are the drawn states, every number's bits, in order; a damaged entry is drawn
    again; where the settings do not fix the examples (a random seed) nothing is kept."""
    from harness.compare import strategies
    from harness.settings import draws_from_seed_only, load_hypothesis_profile

    monkeypatch.setenv("HARNESS_CACHE_DIR", str(tmp_path / "derivations"))
    system = models.get("planar_manipulator")   # parameter groups, inputs, two coordinates

    def bits(batches):
        return [[(s.q.tobytes(), s.qd.tobytes(), list(s.params.items()), list(s.u.items())) for s in batch]
                for batch in batches]

    load_hypothesis_profile()
    with draws_from_seed_only():
        drawn = strategies.system_states(system, examples=40)
        path = strategies._kept_path(system, 40, True)
        assert path.is_file() and path.parent == tmp_path / "states"
        strategies._STATES.clear()
        read = strategies.system_states(system, examples=40)
    assert read is not drawn and len(read) == 20
    assert bits(read) == bits(drawn)
    assert strategies._kept_path(system, 42, True) != path

    path.write_text(path.read_text().replace('"q": [', '"q": [1.5, ', 1))
    assert strategies._read_kept(path, system) is None   # the checksum no longer matches: drawn again

    import hypothesis.core

    monkeypatch.setattr(hypothesis.core, "global_force_seed", None)  # as pytest --hypothesis-seed would fix them
    settings.register_profile("random draws", settings.get_profile("ci"), derandomize=False, database=None)
    settings.load_profile("random draws")
    try:
        with draws_from_seed_only():
            assert strategies._kept_path(system, 40, True) is None
    finally:
        load_hypothesis_profile()


def test_a_seeded_job_leaves_the_next_jobs_seed_alone(monkeypatch):
    """:func:`harness.settings.apply_seed` in a process that runs several jobs (a kept or Dask worker, the test
    suite): after a job with ``--seed`` one without draws from the system's own seed, as a fresh process does (it
    drew from the earlier job's seed: found when a ``--seed`` test left it to the next test of its worker)."""
    import hypothesis.core

    from harness import settings as harness_settings
    from harness.compare.strategies import states_seed

    system = models.get("pendulum")
    monkeypatch.setattr(hypothesis.core, "global_force_seed", None)
    monkeypatch.setattr(harness_settings, "_OWN_FORCED_SEED", [])
    harness_settings.apply_seed(None)
    fresh = states_seed(system)
    harness_settings.apply_seed(7)
    assert states_seed(system) == 7
    harness_settings.apply_seed(None)
    assert states_seed(system) == fresh and hypothesis.core.global_force_seed is None


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_a_parameter_with_a_range_is_drawn_in_it(data):
    """A four-bar's lengths drawn in [default/2, 2 default] mostly do not close (ground 0.74 m against links of
    0.375 m together: "M is not finite at q = 0", the parameters named since): ``Parameter(range=...)`` is the span
    the checks draw it from. A range without the default, or outside the assumption, is refused at declaration; a
    parameter without one keeps the model's fingerprint."""
    import dataclasses

    import pytest

    from harness.errors import ModelError
    from harness.modeling import Parameter

    system = models.get("pendulum")
    l_ranged = Parameter("l", 1.0, "m", "length of the massless rod", range=(0.9, 1.1))
    ranged = dataclasses.replace(system, parameters=tuple(l_ranged if p.name == "l" else p for p in system.parameters))
    values = data.draw(parameters(ranged))
    assert 0.9 <= values["l"] <= 1.1
    assert Parameter("m", 1.0, "kg", "mass").canonical() == \
        "Parameter(name='m',default=1.0,unit='kg',description='mass',assumption='positive')"   # as before ranges
    for span, says in (((1.1, 1.2), "hold the default"), ((-1.0, 2.0), "must be positive"), ((1.0,), "pair")):
        with pytest.raises(ModelError, match=says):
            Parameter("l", 1.0, "m", "length", range=span)


def test_a_non_negative_parameter_at_zero_is_given_a_span_or_refused():
    """A damping that defaults to 0 (a swinging spring's, Lynch 2002) was drawn in [0, 2 default] = {0}: its
    f_damper checks compared zeros and passed without testing the damper's export. Such a parameter is refused with
    the fix; with ``range`` it is drawn in it."""
    import pytest

    from harness.errors import ModelError
    from harness.modeling import Parameter

    with pytest.raises(ModelError, match=r"parameter d: non-negative with default 0, it would be drawn at 0 only .* "
                                         r"range=\(0, 1.0\)"):
        Parameter("d", 0.0, "N s/m", "damping", assumption="nonnegative")
    assert Parameter("d", 0.0, "N s/m", "damping", assumption="nonnegative", range=(0, 2.0)).range == (0.0, 2.0)
    assert Parameter("mu", 0.3, "1", "friction", assumption="nonnegative").range is None


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_an_inertia_with_products_as_parameters_is_drawn_as_one_valid_tensor(data):
    """A body not aligned with its frame (a CAD part) has products of inertia; with its six entries parameters, each
    drawn by itself made a tensor with a negative principal moment (a user's arm: −0.48 kg m², "inertia tensor is
    not positive (semi-)definite"). The six are drawn as one tensor, a positive diagonal obeying the triangle
    inequality turned by a uniform rotation; a tensor only partly of parameters that a draw makes invalid is an
    error naming the drawn parameters and the fix."""
    import pytest

    from harness.errors import ModelError
    from harness.export.numeric import instantiate
    from harness.modeling import Coordinate, Inertia, Joint, Link, Parameter, System

    entries = [Parameter(f"I_{k}", v, "kg m^2", f"inertia {k}", assumption="positive" if len(set(k)) == 1 else "real")
               for k, v in (("xx", 0.02), ("yy", 0.03), ("zz", 0.04), ("xy", 0.004), ("xz", -0.003), ("yz", 0.002))]
    m = Parameter("m", 1.0, "kg", "mass")
    phi = Coordinate("phi", "rad", "angle")

    def body(inertia):
        return System(name="tilted", title="a tilted body", lecture="(none)", coordinates=(phi,),
                      links=(Link("body", mass=m, com=(0.1, 0, 0), inertia=inertia),),
                      joints=(Joint("phi", "revolute", "world", "body", axis="z"),), forces=())

    system = body(Inertia(*entries))
    values = data.draw(parameters(system))
    I = np.array([[values["I_xx"], values["I_xy"], values["I_xz"]], [values["I_xy"], values["I_yy"], values["I_yz"]],
                  [values["I_xz"], values["I_yz"], values["I_zz"]]])
    a, b, c = np.linalg.eigvalsh(I)
    assert a > 0 and a + b >= c * (1 - 1e-12)
    instantiate(system, values)            # a valid tensor: the export's check passes
    partly = body(Inertia(0.02, 0.03, 0.04, *entries[3:]))
    bad = {**partly.default_parameters(), "I_xy": 0.5}
    with pytest.raises(ModelError, match=r"not positive .* with the parameters I_xy = 0\.5 \(drawn by the checks\)"):
        instantiate(partly, bad)


def test_a_map_undefined_at_drawn_parameters_names_them():
    """The toggle press's map φ₂ = arcsin(L₁/L₂ sin q) (A.100) is undefined where L₁ sin q > L₂: at q = 0.3 with L₁
    five times L₂ the error had named q alone, which is fine at the default parameters; it names the parameters."""
    import pytest

    from harness.derivation.compile import compiled
    from harness.errors import ModelError

    system = models.get("toggle_press")
    params = {**system.default_parameters(), "L_1": 5 * system.default_parameters()["L_2"]}
    p = np.array([params[x.name] for x in system.parameters])
    with pytest.raises(ModelError, match=r"not finite at q = 0\.3 in toggle_press with the parameters L_1 = .* a "
                                         r"map that closes a chain must be defined over that range"):
        compiled(system).forward_dynamics(np.array([0.3]), np.array([0.0]), p, np.zeros(len(system.inputs)))


def _within(span: str, value: float) -> bool:
    """``value`` inside ``[lo, hi]`` as the system page prints it (4 significant digits)."""
    lo, hi = (float(v) for v in span.split("]")[0].strip("[").split(","))
    return lo - 1e-3 * abs(lo) <= value <= hi + 1e-3 * abs(hi)


@settings(max_examples=20, suppress_health_check=[HealthCheck.large_base_example])  # every system at once
@given(st.data())
def test_the_system_page_states_the_spans_drawn(data):
    """The page's "range drawn" said "default" for every coordinate and for a parameter without ``range=``; it now
    gives the span each is drawn from (:func:`drawn_spans`), and every draw lies in it."""
    from harness.compare.strategies import drawn_spans

    for system in models.catalogue().values():
        q_spans, p_spans, _ = drawn_spans(system)
        params = data.draw(parameters(system))
        for name, value in params.items():
            assert p_spans[name].startswith("a valid inertia") or _within(p_spans[name], value), (system.name, name)
        for state in data.draw(draws(system)):
            assert all(_within(q_spans[c.name], x) for c, x in zip(system.coordinates, state.q)), system.name
