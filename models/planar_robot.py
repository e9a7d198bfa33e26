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

import math

from sympy import Matrix, Rational, cos, sin

from harness.modeling import (printed_matrix, WORLD, Claim, Coordinate, Gravity, Inertia, Input, Joint, Link, Parameter, Point,
                              PointForce, Scene, Step, System, standard_gravity)

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
g = standard_gravity()

phi_1 = Coordinate("phi_1", "rad", "absolute angle of segment 1 (q_1)")
phi_2 = Coordinate("phi_2", "rad", "absolute angle of segment 2 (q_2)")
phi_3 = Coordinate("phi_3", "rad", "absolute angle of segment 3 (q_3; the segment points along -[cos, sin])")

f_ex = Input("f_ex", "N", "external force f_e = [-f_ex, 0, 0] at the free end of segment 2")

SYSTEM = System(
    name="planar_robot",
    title="Planar robot",
    lecture="Exercise A.11; (A.108)-(A.123)",
    coordinates=(phi_1, phi_2, phi_3),
    links=(
        Link("segment_1", m_1, (l_1 / 6, 0, 0), Inertia(I_xx1, I_yy1, I_1),
             description="segment 1, bearing at a third of its length"),
        Link("segment_2", m_2, (l_2 / 2, 0, 0), Inertia(I_xx2, I_yy2, I_2),
             description="segment 2, mounted at the 2 l_1/3 end of segment 1"),
        Link("segment_3", m_3, (-l_3 / 2, 0, 0), Inertia(I_xx3, I_yy3, I_3),
             description="segment 3, mounted at the -l_1/3 end of segment 1, pointing along -x_3"),
    ),
    joints=(
        Joint("phi_1", "revolute", WORLD, "segment_1", axis="z", origin=(0, h, 0)),
        Joint("phi_2rel", "revolute", "segment_1", "segment_2", axis="z", origin=(2 * l_1 / 3, 0, 0),
              phi=phi_2 - phi_1),
        Joint("phi_3rel", "revolute", "segment_1", "segment_3", axis="z", origin=(-l_1 / 3, 0, 0),
              phi=phi_3 - phi_1),
    ),
    gravity=Gravity(g, (0, -1, 0)),
    forces=(PointForce("f_e", Point("segment_2", (l_2, 0, 0), "e"), (-f_ex, 0, 0)),),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
q_1, q_2, q_3 = phi_1, phi_2, phi_3
qd_1, qd_2, qd_3 = phi_1.rate, phi_2.rate, phi_3.rate
bearing = Matrix([0, h, 0])


def e(angle):
    return Matrix([cos(angle), sin(angle), 0])


M_printed = Matrix([
    [l_1**2 / 36 * (m_1 + 16 * m_2 + 4 * m_3) + I_1, l_1 * l_2 / 3 * m_2 * cos(q_1 - q_2),
     l_1 * l_3 / 6 * m_3 * cos(q_1 - q_3)],
    [l_1 * l_2 / 3 * m_2 * cos(q_1 - q_2), l_2**2 / 4 * m_2 + I_2, 0],
    [l_1 * l_3 / 6 * m_3 * cos(q_1 - q_3), 0, l_3**2 / 4 * m_3 + I_3]])                      # (A.123a)
C_printed = Matrix([
    [0, l_1 * l_2 / 3 * m_2 * sin(q_1 - q_2) * qd_2, l_1 * l_3 / 6 * m_3 * sin(q_1 - q_3) * qd_3],
    [-l_1 * l_2 / 3 * m_2 * sin(q_1 - q_2) * qd_2, 0, 0],
    [l_1 * l_3 / 6 * m_3 * sin(q_1 - q_3) * qd_3, 0, 0]])                                    # (A.123b)
g_printed = Matrix([
    l_1 / 6 * m_1 * g * cos(q_1) + 2 * l_1 / 3 * m_2 * g * cos(q_1) - l_1 / 3 * m_3 * g * cos(q_1),
    l_2 / 2 * m_2 * g * cos(q_2),
    -l_3 / 2 * m_3 * g * cos(q_3)])                                                          # (A.123c)
f_q_printed = Matrix([2 * l_1 / 3 * sin(q_1), l_2 * sin(q_2), 0]) * f_ex                   # (A.120)
qd = Matrix([qd_1, qd_2, qd_3])
M_sym, C_sym = printed_matrix("M", 3, 3, "kg m^2"), printed_matrix("C", 3, 3, "kg m^2/s")  # (A.122) is printed
g_sym, f_sym = printed_matrix("g", 3, 1, "N m"), printed_matrix("f_q", 3, 1, "N m")      # in M, C, g, f_q
qdd = Matrix([phi_1.accel, phi_2.accel, phi_3.accel])

CLAIMS = [
    Claim("(A.113a)", "position:segment_1", bearing + l_1 / 6 * e(q_1), "centre of gravity S_1"),
    Claim("(A.113b)", "position:segment_2", bearing + 2 * l_1 / 3 * e(q_1) + l_2 / 2 * e(q_2), "centre of gravity S_2"),
    Claim("(A.113c)", "position:segment_3",
          bearing + l_1 / 3 * Matrix([-cos(q_1), -sin(q_1), 0]) + l_3 / 2 * Matrix([-cos(q_3), -sin(q_3), 0]),
          "centre of gravity S_3"),
    Claim("(A.114a)", "v:segment_1", l_1 / 6 * Matrix([-sin(q_1), cos(q_1), 0]) * qd_1, "velocity of S_1"),
    Claim("(A.114b)", "v:segment_2", 2 * l_1 / 3 * Matrix([-sin(q_1), cos(q_1), 0]) * qd_1
          + l_2 / 2 * Matrix([-sin(q_2), cos(q_2), 0]) * qd_2, "velocity of S_2"),
    Claim("(A.114c)", "v:segment_3", l_1 / 3 * Matrix([sin(q_1), -cos(q_1), 0]) * qd_1
          + l_3 / 2 * Matrix([sin(q_3), -cos(q_3), 0]) * qd_3, "velocity of S_3"),
    Claim("(A.115a)", "v_squared:segment_1", (l_1 / 6)**2 * qd_1**2, "squared speed of S_1"),
    Claim("(A.115b)", "v_squared:segment_2", (2 * l_1 / 3)**2 * qd_1**2 + (l_2 / 2)**2 * qd_2**2
          + Rational(2, 3) * l_1 * l_2 * cos(q_1 - q_2) * qd_1 * qd_2, "squared speed of S_2"),
    Claim("(A.115c)", "v_squared:segment_3", (l_1 / 3)**2 * qd_1**2 + (l_3 / 2)**2 * qd_3**2
          + Rational(1, 3) * l_1 * l_3 * cos(q_1 - q_3) * qd_1 * qd_3, "squared speed of S_3"),
    Claim("(A.119)", "position:e", bearing + 2 * l_1 / 3 * e(q_1) + l_2 * e(q_2),
          "point of application of f_e (free end of segment 2)"),
    Claim("(A.116)", "T",
          (m_1 * (l_1 / 6)**2 + m_2 * (2 * l_1 / 3)**2 + m_3 * (l_1 / 3)**2 + I_1) * qd_1**2 / 2
          + (m_2 * (l_2 / 2)**2 + I_2) * qd_2**2 / 2 + (m_3 * (l_3 / 2)**2 + I_3) * qd_3**2 / 2
          + m_2 * l_1 * l_2 * cos(q_1 - q_2) * qd_1 * qd_2 / 3 + m_3 * l_1 * l_3 * cos(q_1 - q_3) * qd_1 * qd_3 / 6,
          "kinetic energy"),
    Claim("(A.117)", "V",
          m_1 * g * (h + l_1 / 6 * sin(q_1)) + m_2 * g * (h + 2 * l_1 / 3 * sin(q_1) + l_2 / 2 * sin(q_2))
          + m_3 * g * (h - l_1 / 3 * sin(q_1) - l_3 / 2 * sin(q_3)), "potential energy, reference y = 0"),
    Claim("(A.120)", "f_np", f_q_printed, "generalized forces of f_e (A.118)", defines=f_sym),
    Claim("(A.123a)", "M", M_printed, "mass matrix", defines=M_sym),
    Claim("(A.123b)", "C", C_printed, "Coriolis matrix", defines=C_sym,
          note="its C·q' is also claimed on its own (next claim): C is not unique, C·q' is"),
    Claim("(A.122), (A.123b)", "Cqd", C_sym * qd, "C(q, q')q' with the printed C", ingredients=("(A.123b)",)),
    Claim("(A.123c)", "g", g_printed, "potential forces", defines=g_sym),
    Claim("(A.122)", "eom", M_sym * qdd + C_sym * qd + g_sym - f_sym,
          ingredients=("(A.120)", "(A.123a)", "(A.123b)", "(A.123c)"), description="M q'' + C q' + g = f_q with the printed (A.120), (A.123)"),
]

# every segment hanging down (segment 3 points along -[cos(phi_3), sin(phi_3)])
_hanging = (-math.pi / 2, -math.pi / 2, math.pi / 2)

SCENES = [
    Scene("pushed", "Exercise A.11, (A.122): released from rest near the hanging position (segments turned by "
          "0.3, -0.2, 0.25 rad); the force f_e = [-f_ex, 0, 0] at the free end of segment 2 steps to f_ex = 5 N at "
          "1 s", (_hanging[0] + 0.3, _hanging[1] - 0.2, _hanging[2] + 0.25), (0.0, 0.0, 0.0), 3.0,
          {"gravity", "external"}, inputs={f_ex: Step(1.0, 5.0)}),
]
