"""Elastically mounted cantilever beam, Exercise A.14 (Figure A.22), solution (A.159)-(A.174).

A carriage S (mass ``m_s``) slides on its guide along ``e_y`` (vertical) with position ``s``; the joint A of the
beam sits on the carriage at ``[0, s, 0]``. Gravity acts in ``-e_y`` (``V_g,B = g m_B (s + l_s sin phi)``,
(A.162), (A.163)). A linear spring ``c_1`` (relaxed at ``s = s_10``, (A.164a)) and viscous friction ``d_1``
(A.172a) act in the carriage guide; a torsion spring ``c_2`` (relaxed at ``phi = 0``, (A.164b)) and viscous
friction ``d_2`` (A.172b) act in the joint A.

The beam B is a plate of constant thickness ``d`` and density ``rho`` made of three rectangles of widths
``b_i`` and lengths ``l_i``: sections 2 (next to A) and 1 (the free end) reach to the left of A, section 3 to
the right; for ``phi = 0`` the beam is horizontal and symmetric about the line through A (A.160). Its centre of
gravity lies at the distance ``l_s`` (A.160) left of A: ``p_0^sB = [-l_s cos phi, s + l_s sin phi, 0]``
(A.161). So ``phi`` turns the beam *clockwise* (about ``-e_z``): the beam frame (x along the beam, pointing
from A to section 3; y up for ``phi = 0``) is the carriage frame rotated by ``phi`` about ``-z``.
``I_zzB`` is the lecture's ``I_B,zz^(S)`` (about the centre of gravity); ``I_xxB``, ``I_yyB`` complete a
physical tensor for the engines (their defaults are those of the three plates; they do not enter the planar
motion). The beam's mass and centre of gravity are computed below from the three sections (3.24), (3.29).

The external force ``f^e`` is a follower force: always perpendicular to the beam, magnitude ``f^e``, acting at
the lower edge of the free end, ``[-(l_1 + l_2), -b_1/2, 0]`` in the beam frame (A.170), in the beam's ``+y``
direction: ``f^e = [f^e sin phi, f^e cos phi, 0]`` in the inertial frame (A.169).

Tree: world -(prismatic y, ``s``)-> carriage -(revolute about -z, ``phi``)-> beam; identity map. The carriage
only translates, so its rotational inertia (a cuboid, for the engines) never enters. No singular points.
"""

from sympy import Matrix, cos, diff, sin

from harness.modeling import (WORLD, Claim, Coordinate, Printed, Gravity, Inertia, Input, Joint, JointDamper, JointSpring, Link,
                              Parameter, Point, PointForce, Scene, Step, System, standard_gravity)

m_s = Parameter("m_s", 5.0, "kg", "mass of the carriage S (m_s, as the exercise gives it)")
rho = Parameter("rho", 2700.0, "kg/m^3", "density of the beam B")
d = Parameter("d", 0.01, "m", "thickness of the beam B")
b_1 = Parameter("b_1", 0.1, "m", "width of beam section 1 (free end)")
b_2 = Parameter("b_2", 0.05, "m", "width of beam section 2 (next to A, same side as section 1)")
b_3 = Parameter("b_3", 0.08, "m", "width of beam section 3 (other side of A)")
l_1 = Parameter("l_1", 0.4, "m", "length of beam section 1")
l_2 = Parameter("l_2", 0.6, "m", "length of beam section 2")
l_3 = Parameter("l_3", 0.2, "m", "length of beam section 3")
I_xxB = Parameter("I_xxB", 0.0013185, "kg m^2", "inertia of the beam about its long axis x_B through S")
I_yyB = Parameter("I_yyB", 0.3212105, "kg m^2", "inertia of the beam about y_B through S")
I_zzB = Parameter("I_zzB", 0.3224903, "kg m^2", "moment of inertia I_B,zz^(S) of the beam about z through S")
c_1 = Parameter("c_1", 2000.0, "N/m", "stiffness of the spring carriage - ground")
s_10 = Parameter("s_10", 0.3, "m", "carriage position with relaxed spring c_1", assumption="real")
c_2 = Parameter("c_2", 50.0, "N m/rad", "stiffness of the torsion spring carriage - beam")
d_1 = Parameter("d_1", 10.0, "N s/m", "viscous friction in the carriage guide")
d_2 = Parameter("d_2", 0.5, "N m s/rad", "viscous friction in the joint A")
g = standard_gravity()

s = Coordinate("s", "m", "position of the carriage along e_y")
phi = Coordinate("phi", "rad", "angle of the beam, clockwise, 0 with relaxed torsion spring")
f_e = Input("f_e", "N", "magnitude f^e of the follower force, perpendicular to the beam")

# the beam from its three sections (3.24), (3.29): masses and centres along the beam's x axis
_sections = [(rho * d * b_1 * l_1, -(l_2 + l_1 / 2)),   # section 1, left of A
             (rho * d * b_2 * l_2, -l_2 / 2),           # section 2, left of A
             (rho * d * b_3 * l_3, l_3 / 2)]            # section 3, right of A
m_B = sum(m for m, _ in _sections)
x_sB = sum(m * x for m, x in _sections) / m_B  # = -l_s

SYSTEM = System(
    name="cantilever_beam",
    title="Elastically mounted cantilever beam",
    lecture="Exercise A.14; (A.159)-(A.174)",
    coordinates=(s, phi),
    links=(
        Link("carriage", m_s, (0, 0, 0), Inertia.cuboid(m_s, 0.2, 0.2, 0.1),
             description="carriage S; it only translates"),
        Link("beam", m_B, (x_sB, 0, 0), Inertia(I_xxB, I_yyB, I_zzB),
             description="beam B of three plates, x along the beam"),
    ),
    joints=(
        Joint("s", "prismatic", WORLD, "carriage", axis="y"),
        Joint("phi", "revolute", "carriage", "beam", axis=(0, 0, -1)),
    ),
    gravity=Gravity(g, (0, -1, 0)),
    forces=(
        JointSpring("spring_1", "s", c_1, s_10),
        JointSpring("spring_2", "phi", c_2, 0),
        JointDamper("friction_1", "s", d_1),
        JointDamper("friction_2", "phi", d_2),
        PointForce("follower_force", Point("beam", (-(l_1 + l_2), -b_1 / 2, 0), "f"), (0, f_e, 0), frame="beam"),
    ),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
q, qd, qdd = [s, phi], [s.rate, phi.rate], [s.accel, phi.accel]
c, s_ = cos(phi), sin(phi)
m_B_printed = rho * d * (b_1 * l_1 + b_2 * l_2 + b_3 * l_3)                          # (A.159)
m_S = Printed("m_S", "kg", "printed in (A.163), (A.166); the exercise names the carriage's mass m_s")
l_s = ((b_1 * l_1 * (l_1 / 2 + l_2) + b_2 * l_2**2 / 2 - b_3 * l_3**2 / 2)
       / (b_1 * l_1 + b_2 * l_2 + b_3 * l_3))                                        # (A.160)
V = (g * m_B_printed * (s + l_s * s_) + g * m_S * s                                  # (A.162), (A.163)
     + c_1 * (s - s_10)**2 / 2 + c_2 * phi**2 / 2)                                   # (A.164)
T = (m_S * s.rate**2 / 2                                                             # (A.166)
     + m_B_printed * (phi.rate**2 * l_s**2 + s.rate**2 + 2 * l_s * phi.rate * s.rate * c) / 2  # (A.167)
     + I_zzB * phi.rate**2 / 2)                                                      # (A.168)
f_q = Matrix([f_e * c - d_1 * s.rate,                                                # (A.171a), (A.172a)
              f_e * (l_1 + l_2) - d_2 * phi.rate])                                   # (A.171b), (A.172b)


def _euler_lagrange(L, f_q):
    """(A.174): d/dt ∂L/∂q̇_j − ∂L/∂q_j − f_q,j, one residual per coordinate."""
    rows = []
    for j in range(len(q)):
        p = diff(L, qd[j])
        dp_dt = sum(diff(p, q[k]) * qd[k] + diff(p, qd[k]) * qdd[k] for k in range(len(q)))
        rows.append(dp_dt - diff(L, q[j]) - f_q[j])
    return Matrix(rows)


CLAIMS = [
    Claim("(A.159)", "parameter", m_B_printed, "mass of the beam m_B = rho d (b_1 l_1 + b_2 l_2 + b_3 l_3)",
          reference=m_B),
    Claim("(A.160)", "parameter", l_s, "distance l_s of the beam's centre of gravity from A", reference=-x_sB),
    Claim("(A.161)", "position:beam", Matrix([-l_s * c, s + l_s * s_, 0]), "centre of gravity of the beam"),
    Claim("(A.170)", "position:f", Matrix([-(l_1 + l_2) * c - b_1 / 2 * s_, s + (l_1 + l_2) * s_ - b_1 / 2 * c, 0]),
          "point of application of the follower force"),
    Claim("(A.162)-(A.165)", "V", V, "potential energy V = V_g,B + V_g,S + V_c1 + V_c2"),
    Claim("(A.166)-(A.168)", "T", T, "kinetic energy T = T_t,S + T_t,B + T_r,B"),
    Claim("(A.169)-(A.173)", "f_np", f_q, "generalized forces of the follower force and the viscous friction"),
    Claim("(A.174)", "eom", _euler_lagrange(T - V, f_q),
          "Euler-Lagrange equations with L = T - V of (A.162)-(A.168) and f_q of (A.173)",
          note="the lecture omits the evaluation of (A.174); the residuals are (A.174) evaluated symbolically "
               "with the printed L and f_q"),
]

SCENES = [
    Scene("drop", "Exercise A.14, (A.174): released from rest with relaxed springs (s = s_10, phi = 0, as drawn "
          "in Figure A.22); the carriage sinks and the beam tips under gravity against springs and viscous "
          "friction; the follower force f^e = 10 N steps on at 1 s", (0.3, 0.0), (0.0, 0.0), 3.0,
          {"gravity", "springs", "dampers", "external"}, inputs={f_e: Step(1.0, 10.0)}),
]
