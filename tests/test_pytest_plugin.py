"""Users run our conformance checks from their own pytest suite: the plugin (entry point ``pytest11``) gives
them the ``harness_conformance`` and ``harness_system`` fixtures. Shown by a user's test file outside this
repository, with its own model, run by a separate pytest."""

USER_TESTS = '''
from harness.modeling.system import Coordinate, Gravity, Inertia, Joint, Link, Parameter, System

m = Parameter("m", 2.0, "kg", "mass of the disc")
r = Parameter("r", 0.3, "m", "distance of the centre of mass from the axis")
g = Parameter("g", 9.81, "m/s^2", "gravity")
MY_PENDULUM = System(
    name="my_physical_pendulum", title="a user's own model", lecture="-", parameters=(m, r, g),
    coordinates=(Coordinate("phi", "rad", "angle"),),
    links=(Link("disc", m.symbol, (0, 0, -r.symbol), Inertia(0.01, 0.02, 0.025)),),
    joints=(Joint("phi", "revolute", "world", "disc", axis="x"),),
    gravity=Gravity(g.symbol, (0, 0, -1)))


def test_my_model_agrees_with_both_engines(harness_conformance):
    summary = harness_conformance(MY_PENDULUM)
    assert summary.examples == 4 and ("M", "mujoco") in summary.worst


def test_a_catalogued_system(harness_conformance, harness_system):
    harness_conformance(harness_system("pendulum"), engines=("pinocchio",))
'''


def test_plugin_fixtures_in_a_users_suite(tmp_path):
    import pytest

    (tmp_path / "test_user_models.py").write_text(USER_TESTS)
    # a separate pytest session (in this process, to spare the interpreter start): it loads the plugin from the
    # installed entry point, not from this repository's conftest
    code = pytest.main(["-q", "-p", "no:cacheprovider", "-p", "no:xdist", "--rootdir", str(tmp_path),
                        "--harness-examples", "4", str(tmp_path / "test_user_models.py")])
    assert code == 0
