"""Rigid body with torsional spring, Exercise A.13 (Figure A.21), solution (A.142)-(A.158).

A beam of two rigidly connected slender rods turns about the origin by ``phi``; gravity acts in ``-e_y``.
At ``phi = 0`` rod 1 (length ``L_s``, mass ``m``) stands on the pivot along ``+y`` (centre of gravity
``[0, L_s/2, 0]``, (A.142)) and rod 2 (length ``L_s/2``, mass ``m/2``) sits on its top end along ``+x``
(centre of gravity ``[L_s/4, L_s, 0]``, (A.143)). The rotation (A.148) is ``p_0^s(phi) = R_z(-phi) p_0^s(0)``:
``phi`` turns the beam *clockwise*, so the joint axis is ``-z`` (``theta_phi = phi``, identity map).

The beam is one rigid body; the core has no fixed joints, so the model composes it here, as the lecture
does: total mass ``3m/2``, centre of gravity (3.31), (A.144), and the inertia tensor about it by Steiner's
theorem (3.126), (A.146), in three dimensions. Each rod is a homogeneous cuboid whose width in the plane of
motion is neglected, as the exercise does (``I_zz,s^(S) = m_s L_s²/12``), but which keeps a thickness ``b`` along
``z``: ``b`` enters only ``I_xx``, ``I_yy`` (never the planar motion), and keeps the beam from being an exactly
planar body, whose tensor ``I_zz = I_xx + I_yy`` MuJoCo rejects once rounded ("A + B >= C"). The beam's tensor
has a product of inertia ``I_xy``.

The torsional spring ``c_F`` at the pivot is relaxed at ``phi = 0`` (A.152). The force ``f`` (magnitude ``f``,
an input) acts at the top end of rod 1, ``p_0^f = [L_s sin(phi), L_s cos(phi), 0]`` (A.153), along rod 2's
axis: a follower force with body components ``[f, 0, 0]`` (A.154).
"""

from sympy import Matrix, Rational, cos, factor, sin

from harness.modeling import (WORLD, Claim, Coordinate, Gravity, Inertia, Input, Joint, JointSpring, Link, Parameter,
                              Point, PointForce, Scene, Step, System, standard_gravity, steiner)

m = Parameter("m", 2.0, "kg", "mass of rod 1 (rod 2 has m/2)")
L_s = Parameter("L_s", 1.0, "m", "length of rod 1 (rod 2 has L_s/2)")
b = Parameter("b", 0.03, "m", "thickness of the rods along z (does not enter the planar motion)")
c_F = Parameter("c_F", 30.0, "N m/rad", "stiffness of the torsional spring, relaxed at phi = 0")
g = standard_gravity()

phi = Coordinate("phi", "rad", "angle of the beam, clockwise from its drawn position")
f = Input("f", "N", "magnitude of the force along rod 2's axis")

# the two rods, positions at phi = 0 (A.142), (A.143) and inertia tensors about their own centres of gravity
m_s1, p_s1, I_s1 = m, Matrix([0, L_s / 2, 0]), Inertia.cuboid(m, 0, L_s, b).matrix              # along y
m_s2, p_s2, I_s2 = m / 2, Matrix([L_s / 4, L_s, 0]), Inertia.cuboid(m / 2, L_s / 2, 0, b).matrix  # along x

# the beam: mass, centre of gravity (3.31), inertia about it by Steiner's theorem (3.126)
m_beam = m_s1 + m_s2
p_s = (m_s1 * p_s1 + m_s2 * p_s2) / m_beam
I_s = (I_s1 + steiner(m_s1, p_s1 - p_s) + I_s2 + steiner(m_s2, p_s2 - p_s)).applyfunc(factor)

SYSTEM = System(
    name="torsion_spring_body",
    title="Rigid body with torsional spring",
    lecture="Exercise A.13; (A.142)-(A.158)",
    coordinates=(phi,),
    links=(Link("beam", m_beam, tuple(p_s), Inertia(I_s[0, 0], I_s[1, 1], I_s[2, 2], I_s[0, 1], I_s[0, 2], I_s[1, 2]),
                description="rod 1 (along y_1) and rod 2 (along x_1 at the top of rod 1), rigidly connected"),),
    joints=(Joint("phi", "revolute", WORLD, "beam", axis=(0, 0, -1)),),
    gravity=Gravity(g, (0, -1, 0)),
    forces=(
        JointSpring("spring_F", "phi", c_F),
        PointForce("force_f", Point("beam", (0, L_s, 0), "f"), (f, 0, 0), frame="beam"),
    ),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
w, a = phi.rate, phi.accel
p_f_printed = Matrix([L_s * sin(phi), L_s * cos(phi), 0])                     # (A.153)
f_printed = Matrix([f * cos(phi), -f * sin(phi), 0])                          # (A.154)
CLAIMS = [
    Claim("(A.144)", "parameter", Matrix([L_s / 12, 2 * L_s / 3, 0]), "centre of gravity of the beam at phi = 0",
          reference=p_s),
    Claim("(A.145a)", "parameter", m * L_s**2 / 12, "I_zz^(s1) of rod 1", reference=I_s1[2, 2]),
    Claim("(A.145b)", "parameter", m * L_s**2 / 96, "I_zz^(s2) of rod 2", reference=I_s2[2, 2]),
    Claim("(A.147a)", "parameter", Matrix([L_s / 12, L_s / 6, 0]), "p_s,s1 = p_0^s - p_0^s1", reference=p_s - p_s1),
    Claim("(A.147b)", "parameter", Matrix([-L_s / 6, -L_s / 3, 0]), "p_s,s2 = p_0^s - p_0^s2", reference=p_s - p_s2),
    Claim("(A.146)", "parameter", 19 * m * L_s**2 / 96, "I_zz^(s) of the beam about its centre of gravity",
          reference=I_s[2, 2]),
    Claim("(A.148)", "position:beam", Matrix([L_s / 12 * cos(phi) + 2 * L_s / 3 * sin(phi),
                                              -L_s / 12 * sin(phi) + 2 * L_s / 3 * cos(phi), 0]),
          "centre of gravity of the beam"),
    Claim("(A.149)", "v:beam", Matrix([-L_s / 12 * sin(phi) * w + 2 * L_s / 3 * cos(phi) * w,
                                       -L_s / 12 * cos(phi) * w - 2 * L_s / 3 * sin(phi) * w, 0]),
          "velocity of the centre of gravity of the beam"),
    Claim("(A.153)", "position:f", p_f_printed, "point of application of f"),
    Claim("(A.150), (A.151)", "T", Rational(65, 192) * m * w**2 * L_s**2 + Rational(19, 192) * m * w**2 * L_s**2,
          "T_t + T_r"),
    Claim("(A.156)", "T", Rational(7, 16) * m * w**2 * L_s**2, "kinetic part of the Lagrangian"),
    Claim("(A.152)", "V", -L_s / 8 * m * g * sin(phi) + m * g * L_s * cos(phi) + c_F * phi**2 / 2, "V_g + V_F"),
    Claim("(A.156)", "V", -(L_s / 8 * m * g * sin(phi) - m * g * L_s * cos(phi) - c_F * phi**2 / 2),
          "potential part of the Lagrangian L = T - V"),
    Claim("(A.154), (A.155)", "f_np", (f_printed.T * p_f_printed.diff(phi))[0],
          "f_q,f = f^T dp_0^f/dphi with the printed force (A.154) and point (A.153)"),
    Claim("(A.155)", "f_np", f * L_s, "generalized force of f"),
    Claim("(A.158)", "eom", Rational(7, 8) * m * L_s**2 * a - m * g * L_s * cos(phi) / 8
          - m * g * L_s * sin(phi) + c_F * phi - f * L_s, "equation of motion"),
]

SCENES = [
    Scene("tip_over", "Exercise A.13, (A.158): released from rest at phi = 0 (spring relaxed); gravity tips the "
          "beam over and it swings about its tilted equilibrium (0.24 rad) against the torsional "
          "spring; the follower force f = 5 N along rod 2 steps on at 1 s",
          (0.0,), (0.0,), 3.0, {"gravity", "springs", "external"}, inputs={f: Step(1.0, 5.0)}),
]
