"""The parts of the core the lecture systems of the skeleton do not exercise: a linear map (absolute angles), rotor inertia as engine armature,
a nonlinear map theta = phi(q), a massless link between two non-commuting hinges (fused into one MuJoCo
body), external follower forces at points and torques on bodies (5.73) — checked
against both engines exactly like a catalogue system."""

import sympy as sp
import pytest

from harness.compare import conformance
from harness.modeling.system import (BodyTorque, Coordinate, Damper, Gravity, Inertia, Input, Joint, Link, Parameter, Point,
                           PointForce, System, WORLD)

m = Parameter("m", 1.0, "kg", "mass of each link")
l = Parameter("l", 0.7, "m", "length of each link")
I_xx = Parameter("I_xx", 0.001, "kg m^2", "inertia about x")
I_yy = Parameter("I_yy", 0.04, "kg m^2", "inertia about y")
I_zz = Parameter("I_zz", 0.04, "kg m^2", "inertia about z")
d = Parameter("d", 0.5, "N s/m", "damper tip - world")
g = Parameter("g", 9.81, "m/s^2", "gravity")
I_a = Parameter("I_a", 0.02, "kg m^2", "rotor inertia reflected onto joint 2 (armature)")
phi_1, phi_2 = sp.Symbol("phi_1", real=True), sp.Symbol("phi_2", real=True)
rod = dict(mass=m.symbol, com=(l.symbol / 2, 0, 0), inertia=Inertia(I_xx.symbol, I_yy.symbol, I_zz.symbol))
tip = Point("link_2", (l.symbol, 0, 0), "tip")

ABSOLUTE_ANGLES = System(
    name="double_pendulum_absolute", title="double pendulum in absolute angles", lecture="(test)",
    parameters=(m, l, I_xx, I_yy, I_zz, d, g, I_a),
    coordinates=(Coordinate("phi_1", "rad", "absolute angle of link 1"),
                 Coordinate("phi_2", "rad", "absolute angle of link 2")),
    links=(Link("link_1", **rod), Link("link_2", **rod)),
    joints=(Joint("joint_1", "revolute", WORLD, "link_1", axis="z", phi=phi_1),
            Joint("joint_2", "revolute", "link_1", "link_2", axis="z", origin=(l.symbol, 0, 0), phi=phi_2 - phi_1,
                  armature=I_a.symbol)),
    gravity=Gravity(g.symbol, (0, -1, 0)),
    inputs=(Input("f", "N", "follower force at the tip"), Input("tau", "N m", "torque on link 1")),
    forces=(PointForce("follower", tip, (0, sp.Symbol("f", real=True), 0), frame="link_2"),
            BodyTorque("torque", "link_1", (0, 0, sp.Symbol("tau", real=True))),
            PointForce("wind", Point("link_1", (l.symbol / 2, 0, 0), "mid_1"), (0.5, 0.2, 0)),
            Damper("tip_damper", Point(WORLD, (0.3, 0.2, 0), "anchor"), tip, d.symbol)),
)

q = sp.Symbol("q", real=True)
NONLINEAR_MAP = System(
    name="pendulum_nonlinear_map", title="pendulum with theta = q + 0.3 sin q", lecture="(test)",
    parameters=(m, l, I_xx, I_yy, I_zz, g),
    coordinates=(Coordinate("q", "rad", "a coordinate related nonlinearly to the joint angle"),),
    links=(Link("link_1", **rod),),
    joints=(Joint("joint_1", "revolute", WORLD, "link_1", axis="z", phi=q + sp.Rational(3, 10) * sp.sin(q)),),
    gravity=Gravity(g.symbol, (0, -1, 0)),
)


a, b = sp.Symbol("a", real=True), sp.Symbol("b", real=True)
MASSLESS_GIMBAL = System(
    name="gimbal_pendulum", title="two hinges at one point through a massless link", lecture="(test)",
    parameters=(m, l, I_xx, I_yy, I_zz, g),
    coordinates=(Coordinate("a", "rad", "about z"), Coordinate("b", "rad", "about the turned y")),
    links=(Link("gimbal", 0), Link("rod", m.symbol, (0, 0.1, -l.symbol), Inertia(I_xx.symbol, I_yy.symbol, I_zz.symbol))),
    joints=(Joint("a", "revolute", WORLD, "gimbal", axis="z", origin=(0.2, 0, 0), rpy=(0.3, 0, 0)),
            Joint("b", "revolute", "gimbal", "rod", axis="y")),
    gravity=Gravity(g.symbol, (0, 0, -1)),
)


@pytest.mark.parametrize("system", [ABSOLUTE_ANGLES, NONLINEAR_MAP, MASSLESS_GIMBAL], ids=lambda s: s.name)
def test_mapped_system_agrees_with_both_engines(system):
    summary = conformance.run(system)
    assert summary.failure is None, summary.failure
    assert summary.passed
