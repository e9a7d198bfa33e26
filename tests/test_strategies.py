"""The hypothesis strategies build valid physical objects (never filtered): positive parameters, inertia
tensors positive definite and satisfying the triangle inequality, states accepted by State.make."""

import numpy as np
from hypothesis import given, settings, strategies as st

import models
from harness.export.numeric import check_inertia, instantiate
from harness.compare.strategies import parameters, states


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


@PER_SYSTEM
@given(st.data())
def test_random_states_have_the_right_shape(data):
    for system in models.catalogue().values():
        state = data.draw(states(system))
        assert state.q.shape == state.qd.shape == (len(system.coordinates),)
        assert np.all(np.isfinite(state.q)) and set(state.u) == {i.name for i in system.inputs}
