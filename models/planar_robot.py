"""Planar robot, Exercise A.11 (Figure A.19), solution (A.108)-(A.123).

Three segments move in the ``x_0 y_0`` plane; gravity acts in ``-e_y`` (``V = Σ m_i g e_yᵀ p_0^{S_i}``,
reference ``y = 0``, (A.117)). Segment 1 (length ``l_1``) turns about the bearing at ``[0, h, 0]``, which
divides it in the ratio 1 : 2: its ends lie at ``2 l_1/3`` and ``-l_1/3`` along its axis, its centre of
gravity at ``l_1/6`` (A.113a). Segment 2 is mounted at the ``2 l_1/3`` end and points along
``[cos q_2, sin q_2]``, centre of gravity at ``l_2/2``, free end at ``l_2`` (A.113b), (A.119); segment 3 is
mounted at the ``-l_1/3`` end and points along ``-[cos q_3, sin q_3]``, centre of gravity at ``l_3/2``
(A.113c). All bearings are frictionless.

Lecture coordinates are the *absolute* angles ``q = [phi_1, phi_2, phi_3]`` (A.108) of the segments' axes
against ``x_0`` (segment 3's axis drawn from its bearing to its free end is ``phi_3 + pi``). The kinematic tree
mounts segments 2 and 3 on segment 1, so its joints turn by the *relative* angles
``theta_phi_2rel = phi_2 - phi_1`` and ``theta_phi_3rel = phi_3 - phi_1`` (the alternative coordinates
(A.109)): a linear map ``theta = phi(q)``. In the frame of segment 3 its centre of gravity lies at
``[-l_3/2, 0, 0]``.

``I_1``, ``I_2``, ``I_3`` are the segments' inertias about ``z`` through ``S_i`` (A.112); the segments' inertias
about their own axis (``I_xx``) and the second in-plane axis (``I_yy``) never enter a planar motion and are
there for a physical body in the engines. The external force ``f_e = [-f_ex, 0, 0]`` (components in the
inertial frame) acts at the free end of segment 2 (A.118)-(A.120); ``f_ex`` is an input.
"""

from harness.modeling.system import (Coordinate, Gravity, Inertia, Input, Joint, Link, Parameter, Point, PointForce,
                           System, WORLD)

m_1 = Parameter("m_1", 3.0, "kg", "mass of segment 1")
m_2 = Parameter("m_2", 1.5, "kg", "mass of segment 2")
m_3 = Parameter("m_3", 1.0, "kg", "mass of segment 3")
l_1 = Parameter("l_1", 0.9, "m", "length of segment 1")
l_2 = Parameter("l_2", 0.7, "m", "length of segment 2")
l_3 = Parameter("l_3", 0.5, "m", "length of segment 3")
I_1 = Parameter("I_1", 0.2, "kg m^2", "inertia of segment 1 about z through S_1")
I_2 = Parameter("I_2", 0.06, "kg m^2", "inertia of segment 2 about z through S_2")
I_3 = Parameter("I_3", 0.02, "kg m^2", "inertia of segment 3 about z through S_3")
I_xx1 = Parameter("I_xx1", 0.002, "kg m^2", "inertia of segment 1 about its own axis (does not enter)")
I_yy1 = Parameter("I_yy1", 0.2, "kg m^2", "inertia of segment 1 about y through S_1 (does not enter)")
I_xx2 = Parameter("I_xx2", 0.001, "kg m^2", "inertia of segment 2 about its own axis (does not enter)")
I_yy2 = Parameter("I_yy2", 0.06, "kg m^2", "inertia of segment 2 about y through S_2 (does not enter)")
I_xx3 = Parameter("I_xx3", 0.0005, "kg m^2", "inertia of segment 3 about its own axis (does not enter)")
I_yy3 = Parameter("I_yy3", 0.02, "kg m^2", "inertia of segment 3 about y through S_3 (does not enter)")
h = Parameter("h", 1.2, "m", "height of the bearing of segment 1")
g = Parameter("g", 9.81, "m/s^2", "acceleration due to gravity")

phi_1 = Coordinate("phi_1", "rad", "absolute angle of segment 1 (q_1)")
phi_2 = Coordinate("phi_2", "rad", "absolute angle of segment 2 (q_2)")
phi_3 = Coordinate("phi_3", "rad", "absolute angle of segment 3 (q_3; the segment points along -[cos, sin])")

f_ex = Input("f_ex", "N", "external force f_e = [-f_ex, 0, 0] at the free end of segment 2")

free_end_2 = Point("segment_2", (l_2.symbol, 0, 0), "e")

SYSTEM = System(
    name="planar_robot",
    title="Planar robot",
    lecture="Exercise A.11; (A.108)-(A.123)",
    parameters=(m_1, m_2, m_3, l_1, l_2, l_3, I_1, I_2, I_3, I_xx1, I_yy1, I_xx2, I_yy2, I_xx3, I_yy3, h, g),
    coordinates=(phi_1, phi_2, phi_3),
    links=(
        Link("segment_1", m_1.symbol, (l_1.symbol / 6, 0, 0), Inertia(I_xx1.symbol, I_yy1.symbol, I_1.symbol),
             description="segment 1, bearing at a third of its length"),
        Link("segment_2", m_2.symbol, (l_2.symbol / 2, 0, 0), Inertia(I_xx2.symbol, I_yy2.symbol, I_2.symbol),
             description="segment 2, mounted at the 2 l_1/3 end of segment 1"),
        Link("segment_3", m_3.symbol, (-l_3.symbol / 2, 0, 0), Inertia(I_xx3.symbol, I_yy3.symbol, I_3.symbol),
             description="segment 3, mounted at the -l_1/3 end of segment 1, pointing along -x_3"),
    ),
    joints=(
        Joint("phi_1", "revolute", WORLD, "segment_1", axis="z", origin=(0, h.symbol, 0)),
        Joint("phi_2rel", "revolute", "segment_1", "segment_2", axis="z", origin=(2 * l_1.symbol / 3, 0, 0),
              phi=phi_2.symbol - phi_1.symbol),
        Joint("phi_3rel", "revolute", "segment_1", "segment_3", axis="z", origin=(-l_1.symbol / 3, 0, 0),
              phi=phi_3.symbol - phi_1.symbol),
    ),
    gravity=Gravity(g.symbol, (0, -1, 0)),
    inputs=(f_ex,),
    forces=(PointForce("f_e", free_end_2, (-f_ex.symbol, 0, 0)),),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
import sympy as _sp  # noqa: E402

from harness.modeling.claims import Claim  # noqa: E402

_q1, _q2, _q3 = phi_1.symbol, phi_2.symbol, phi_3.symbol
_qd1, _qd2, _qd3 = phi_1.rate, phi_2.rate, phi_3.rate
_m1, _m2, _m3, _l1, _l2, _l3 = (x.symbol for x in (m_1, m_2, m_3, l_1, l_2, l_3))
_I1, _I2, _I3, _h, _g, _f = I_1.symbol, I_2.symbol, I_3.symbol, h.symbol, g.symbol, f_ex.symbol
_c, _s = _sp.cos, _sp.sin
_bearing = _sp.Matrix([0, _h, 0])


def _e(angle):
    return _sp.Matrix([_c(angle), _s(angle), 0])


_M_printed = _sp.Matrix([
    [_l1**2 / 36 * (_m1 + 16 * _m2 + 4 * _m3) + _I1, _l1 * _l2 / 3 * _m2 * _c(_q1 - _q2),
     _l1 * _l3 / 6 * _m3 * _c(_q1 - _q3)],
    [_l1 * _l2 / 3 * _m2 * _c(_q1 - _q2), _l2**2 / 4 * _m2 + _I2, 0],
    [_l1 * _l3 / 6 * _m3 * _c(_q1 - _q3), 0, _l3**2 / 4 * _m3 + _I3]])                      # (A.123a)
_C_printed = _sp.Matrix([
    [0, _l1 * _l2 / 3 * _m2 * _s(_q1 - _q2) * _qd2, _l1 * _l3 / 6 * _m3 * _s(_q1 - _q3) * _qd3],
    [-_l1 * _l2 / 3 * _m2 * _s(_q1 - _q2) * _qd2, 0, 0],
    [_l1 * _l3 / 6 * _m3 * _s(_q1 - _q3) * _qd3, 0, 0]])                                      # (A.123b)
_g_printed = _sp.Matrix([
    _l1 / 6 * _m1 * _g * _c(_q1) + 2 * _l1 / 3 * _m2 * _g * _c(_q1) - _l1 / 3 * _m3 * _g * _c(_q1),
    _l2 / 2 * _m2 * _g * _c(_q2),
    -_l3 / 2 * _m3 * _g * _c(_q3)])                                                           # (A.123c)
_f_q_printed = _sp.Matrix([2 * _l1 / 3 * _s(_q1), _l2 * _s(_q2), 0]) * _f                   # (A.120)
_qd = _sp.Matrix([_qd1, _qd2, _qd3])
_qdd = _sp.Matrix([phi_1.accel, phi_2.accel, phi_3.accel])

CLAIMS = [
    Claim("(A.113a)", "position:segment_1", _bearing + _l1 / 6 * _e(_q1), "centre of gravity S_1"),
    Claim("(A.113b)", "position:segment_2", _bearing + 2 * _l1 / 3 * _e(_q1) + _l2 / 2 * _e(_q2),
          "centre of gravity S_2"),
    Claim("(A.113c)", "position:segment_3",
          _bearing + _l1 / 3 * _sp.Matrix([-_c(_q1), -_s(_q1), 0]) + _l3 / 2 * _sp.Matrix([-_c(_q3), -_s(_q3), 0]),
          "centre of gravity S_3"),
    Claim("(A.119)", "position:e", _bearing + 2 * _l1 / 3 * _e(_q1) + _l2 * _e(_q2),
          "point of application of f_e (free end of segment 2)"),
    Claim("(A.116)", "T",
          (_m1 * (_l1 / 6)**2 + _m2 * (2 * _l1 / 3)**2 + _m3 * (_l1 / 3)**2 + _I1) * _qd1**2 / 2
          + (_m2 * (_l2 / 2)**2 + _I2) * _qd2**2 / 2 + (_m3 * (_l3 / 2)**2 + _I3) * _qd3**2 / 2
          + _m2 * _l1 * _l2 * _c(_q1 - _q2) * _qd1 * _qd2 / 3 + _m3 * _l1 * _l3 * _c(_q1 - _q3) * _qd1 * _qd3 / 6,
          "kinetic energy"),
    Claim("(A.117)", "V",
          _m1 * _g * (_h + _l1 / 6 * _s(_q1)) + _m2 * _g * (_h + 2 * _l1 / 3 * _s(_q1) + _l2 / 2 * _s(_q2))
          + _m3 * _g * (_h - _l1 / 3 * _s(_q1) - _l3 / 2 * _s(_q3)), "potential energy, reference y = 0"),
    Claim("(A.120)", "f_np", _f_q_printed, "generalized forces of f_e (A.118)"),
    Claim("(A.123a)", "M", _M_printed, "mass matrix"),
    Claim("(A.123b)", "C", _C_printed, "Coriolis matrix",
          note="its C·q' is also claimed on its own (next claim): C is not unique, C·q' is"),
    Claim("(A.122), (A.123b)", "Cqd", _C_printed * _qd, "C(q, q')q' with the printed C"),
    Claim("(A.123c)", "g", _g_printed, "potential forces"),
    Claim("(A.122)", "eom", _M_printed * _qdd + _C_printed * _qd + _g_printed - _f_q_printed,
          "M q'' + C q' + g = f_q with the printed (A.120), (A.123)"),
]

import math as _math  # noqa: E402

from harness.modeling.scenes import Scene, Step  # noqa: E402

# every segment hanging down (segment 3 points along -[cos(phi_3), sin(phi_3)])
_hanging = (-_math.pi / 2, -_math.pi / 2, _math.pi / 2)

SCENES = [
    Scene("pushed", "Exercise A.11, (A.122): released from rest near the hanging position (segments turned by "
          "0.3, -0.2, 0.25 rad); the force f_e = [-f_ex, 0, 0] at the free end of segment 2 steps to f_ex = 5 N at "
          "1 s", (_hanging[0] + 0.3, _hanging[1] - 0.2, _hanging[2] + 0.25), (0.0, 0.0, 0.0), 3.0,
          frozenset({"gravity", "external"}), inputs={"f_ex": Step(1.0, 5.0)}),
]
