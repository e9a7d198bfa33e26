"""Rotating rigid body, Exercise A.2 (Figures A.4, A.5), solution (A.10)-(A.28).

A frame of homogeneous density ``rho`` (thickness ``d`` in the plane, width ``b`` along ``z``, centred on
``z = 0``) carries a point mass ``m_m`` and turns about the ``z`` axis through the bearing ``A`` at the origin
by ``phi`` (counter-clockwise, the rotation (A.22)); gravity acts in ``-e_y``. The sketch is not in the text;
the geometry at ``phi = 0`` is read from the integration bounds (A.11) and the centres of gravity
(A.12), (A.13), in the split of Figure A.5 into four sub-bodies:

* sub-body 1 (top bar): ``-l_2 <= x <= 0``, ``l_1 + d <= y <= l_1 + 2d``, mass ``m_1 = l_2 d b rho`` (A.10);
* sub-body 2 (vertical bar): ``0 <= x <= d``, ``0 <= y <= l_1 + 2d``, mass ``m_2 = d (l_1 + 2d) b rho``;
* sub-body 3 (bottom bar): ``d <= x <= d + l_2``, ``0 <= y <= d``, mass ``m_3 = l_2 d b rho``;
* the point mass ``m_m`` at ``[d + l_m, d, 0]`` (A.13).

The frame and the point mass are one rigid body; the core has no fixed joints, so the model composes it
here, as the lecture does: the inertia tensor about ``A`` is the sum of each sub-body's tensor about its own
centre of gravity (cuboids, (3.128), (A.20)) and Steiner's term (3.126), (A.21); the body's inertia about
its centre of gravity ``p_S = Σ m_i r_i / m_g`` follows by Steiner's theorem once more.

A linear spring (stiffness ``c``, relaxed length ``l_f0``) connects the left end of the top bar,
``r_fc^0 = [-l_2, d + l_1, 0]`` (A.14), with the ground point ``r_fcfp = [-l_2, d + l_1 - l_f^0, 0]`` (A.25)
straight below it; ``l_f^0`` (parameter ``l_f_0``) is the spring's length at ``phi = 0``, and its potential is
``c/2 (l_f(phi) - l_f0)²`` with ``l_f(phi) = |r_fc(phi) - r_fcfp|`` (A.26). The lecture chooses the preload so
that ``phi = 0`` is an equilibrium (A.18), (A.19); here ``l_f0`` is a parameter whose default is that preload
for the other defaults, so the drawn states also cover systems out of that equilibrium. The spring never
reaches zero length: that would need ``l_f^0 = 2 (d + l_1)``, far outside the drawn parameters
(``l_f_0 <= 0.3 m < 0.55 m <= 2 (d + l_1)``).
"""

from sympy import Matrix, cos, integrate, sin, sqrt, symbols

from harness.derivation.bodies import element_force, element_vector, point_in_q
from harness.modeling import (printed_matrix, WORLD, Claim, Coordinate, Gravity, Inertia, Joint, Link, Parameter, Point, Scene, Spring,
                              System, standard_gravity, steiner)

rho = Parameter("rho", 2700.0, "kg/m^3", "density of the frame")
d = Parameter("d", 0.05, "m", "thickness of the frame's bars (in the plane)")
b = Parameter("b", 0.05, "m", "width of the frame (along z)")
l_1 = Parameter("l_1", 0.5, "m", "inner height of the vertical bar")
l_2 = Parameter("l_2", 0.4, "m", "length of the top and bottom bars")
l_m = Parameter("l_m", 0.3, "m", "position of the point mass along the bottom bar")
m_m = Parameter("m_m", 1.0, "kg", "point mass")
c = Parameter("c", 1000.0, "N/m", "stiffness of the spring")
l_f_0 = Parameter("l_f_0", 0.15, "m", "length of the spring at phi = 0 (lecture l_f^0)")
# default: the preload (A.18), (A.19) for the other defaults, f_c = -14.3778 N, l_f0 = l_f^0 + f_c/c
l_f0 = Parameter("l_f0", 0.13562, "m", "relaxed length of the spring (lecture l_f0)")
g = standard_gravity()

phi = Coordinate("phi", "rad", "angle of the body about z through A, counter-clockwise")

# sub-bodies at phi = 0: mass, centre of gravity, inertia tensor about it (homogeneous cuboids (3.128))
m_1 = l_2 * d * b * rho
r_1 = Matrix([-l_2 / 2, l_1 + 3 * d / 2, 0])
I_1 = Inertia.cuboid(m_1, l_2, d, b).matrix
m_2 = d * (l_1 + 2 * d) * b * rho
r_2 = Matrix([d / 2, d + l_1 / 2, 0])
I_2 = Inertia.cuboid(m_2, d, l_1 + 2 * d, b).matrix
m_3 = l_2 * d * b * rho
r_3 = Matrix([d + l_2 / 2, d / 2, 0])
I_3 = Inertia.cuboid(m_3, l_2, d, b).matrix
r_m = Matrix([d + l_m, d, 0])                                   # the point mass, no own inertia

# the rigid body: mass, centre of gravity, inertia about A (A.21) and about the centre of gravity
m_g = m_1 + m_2 + m_3 + m_m
p_S = (m_1 * r_1 + m_2 * r_2 + m_3 * r_3 + m_m * r_m) / m_g
I_A = I_1 + steiner(m_1, r_1) + I_2 + steiner(m_2, r_2) + I_3 + steiner(m_3, r_3) + steiner(m_m, r_m)
I_S = I_A - steiner(m_g, p_S)

SYSTEM = System(
    name="rotating_body",
    title="Rotating rigid body",
    lecture="Exercise A.2; (A.10)-(A.28)",
    coordinates=(phi,),
    links=(Link("body", m_g, tuple(p_S), Inertia(I_S[0, 0], I_S[1, 1], I_S[2, 2], I_S[0, 1], I_S[0, 2], I_S[1, 2]),
                description="frame (three homogeneous bars) and point mass m_m, one rigid body"),),
    joints=(Joint("phi", "revolute", WORLD, "body", axis="z"),),
    gravity=Gravity(g, (0, -1, 0)),
    forces=(Spring("spring", Point(WORLD, (-l_2, d + l_1 - l_f_0, 0), "fcfp"),      # r_fcfp (A.25)
                   Point("body", (-l_2, d + l_1, 0), "fc"), c, l_f0),),              # r_fc^0 (A.14)
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
x, y, z = symbols("x y z", real=True)
bounds_1 = ((x, -l_2, 0), (y, l_1 + d, l_1 + 2 * d), (z, -b / 2, b / 2))   # sub-body 1, (A.11)


def _rot(r):
    """``r`` turned by phi about z, as printed in (A.22), (A.24)."""
    return Matrix([r[0] * cos(phi) - r[1] * sin(phi), r[0] * sin(phi) + r[1] * cos(phi), 0])


# printed quantities of the solution
m1_p, m2_p, m3_p = l_2 * d * b * rho, d * (l_1 + 2 * d) * b * rho, l_2 * d * b * rho
r1_p = Matrix([-l_2 / 2, l_1 + 3 * d / 2, 0])                                   # (A.12)
r2_p = Matrix([d / 2, d + l_1 / 2, 0])                                          # (A.13)
r3_p = Matrix([d + l_2 / 2, d / 2, 0])
rm_p = Matrix([d + l_m, d, 0])
rfc0_p = Matrix([-l_2, d + l_1, 0])                                             # (A.14)
f_c_p = (m1_p * g * l_2 / 2 - m2_p * g * d / 2 - m3_p * g * (d + l_2 / 2) - m_m * g * (d + l_m)) / l_2  # (A.18)
I1S_p = m1_p / 12 * (l_2**2 + d**2)                                             # (A.20)
I_A_p = (I1S_p + m1_p * (r1_p[0]**2 + r1_p[1]**2)                               # (A.21), (A.28)
         + m2_p / 12 * (d**2 + (l_1 + 2 * d)**2) + m2_p * (r2_p[0]**2 + r2_p[1]**2)
         + m3_p / 12 * (l_2**2 + d**2) + m3_p * (r3_p[0]**2 + r3_p[1]**2)
         + m_m * (rm_p[0]**2 + rm_p[1]**2))
tau_gravity_p = sum(-(r[0] * cos(phi) - r[1] * sin(phi)) * mass * g             # (A.23)
                    for mass, r in ((m1_p, r1_p), (m2_p, r2_p), (m3_p, r3_p), (m_m, rm_p)))
rfc_p = _rot(rfc0_p)                                                            # (A.24)
rfcfp_p = Matrix([-l_2, d + l_1 - l_f_0, 0])                                    # (A.25)
lf_p = sqrt(((rfc_p - rfcfp_p).T * (rfc_p - rfcfp_p))[0])                       # (A.26)
fc_vec_p = c * (lf_p - l_f0) * (rfc_p - rfcfp_p) / lf_p                         # (A.27)
f_c_sym = printed_matrix("f_c", 3, 1, "N", "spring force vector of (A.27)")
tau_fc_p = rfc_p[0] * f_c_sym[1] - rfc_p[1] * f_c_sym[0]                        # (r_fc x f_c)_z with (A.27)

_r_1_phi = point_in_q(SYSTEM, Point("body", tuple(r_1)))     # sub-body 1's centre of gravity, body-fixed

CLAIMS = [
    Claim("(A.10)", "parameter", m1_p, "mass of sub-body 1", reference=lambda: integrate(rho, *bounds_1)),
    Claim("(A.11)", "parameter", -l_2 / 2, "r_Sm1,x by (3.29)", reference=lambda: integrate(x * rho, *bounds_1) / m1_p),
    Claim("(A.12)", "parameter", r1_p, "centre of gravity of sub-body 1 at phi = 0",
          reference=lambda: Matrix([integrate(v * rho, *bounds_1) / m1_p for v in (x, y, z)])),
    Claim("(after A.12)", "parameter", Matrix([m2_p, m3_p]), "masses m_2, m_3 of sub-bodies 2, 3",
          reference=Matrix([m_2, m_3])),
    Claim("(A.13)", "parameter", Matrix.hstack(r2_p, r3_p, rm_p),
          "centres of gravity of sub-bodies 2, 3 and of the point mass at phi = 0",
          reference=Matrix.hstack(r_2, r_3, r_m)),
    Claim("(A.14), (A.24)", "position:fc", rfc_p, "point of application of the spring force"),
    Claim("(A.25)", "position:fcfp", rfcfp_p, "base point of the spring"),
    Claim("(A.17) ff.", "parameter",
          Matrix([m1_p * g * l_2 / 2, -m2_p * g * d / 2, -m3_p * g * (d + l_2 / 2), -m_m * g * (d + l_m)]),
          "gravity torques about A at phi = 0: tau_m1,z, tau_m2,z, tau_m3,z, tau_mm,z",
          reference=Matrix([r.cross(Matrix([0, -mass * g, 0]))[2]
                            for mass, r in ((m_1, r_1), (m_2, r_2), (m_3, r_3), (m_m, r_m))])),
    Claim("(A.18)", "parameter", f_c_p, "spring force f_c (along +y) that holds the body at phi = 0",
          reference=-m_g * g * p_S[0] / l_2,
          note="reference: the torque balance about A at phi = 0, -m_g g x_S + (-l_2) f_c = 0"),
    Claim("(A.19)", "parameter", -c * (l_f_0 - l_f0), "spring force f_c = -c (l_f^0 - l_f0) at phi = 0",
          reference=element_force(SYSTEM, "spring")[1].subs(phi.symbol, 0),
          note="l_f^0 → l_f_0 (length of the spring at phi = 0), l_f0 → l_f0 (relaxed length); f_c is the "
               "y-component of the spring force on the body, as in (A.16), (A.18): compared with the model's "
               "spring at phi = 0"),
    Claim("(A.20)", "parameter", I1S_p, "I_zz,m1^(S) of sub-body 1",
          reference=lambda: rho * integrate(x**2 + y**2, (x, -l_2 / 2, l_2 / 2), (y, -d / 2, d / 2), (z, -b / 2, b / 2))),
    Claim("(A.21)", "parameter", I1S_p + m1_p * (r1_p[0]**2 + r1_p[1]**2), "I_zz,m1^(A) of sub-body 1",
          reference=(I_1 + steiner(m_1, r_1))[2, 2]),
    Claim("(A.22)", "parameter", _rot(r1_p), "centre of gravity of sub-body 1 turned by phi",
          reference=_r_1_phi, note="reference: the body-fixed point r_1 (A.12) in the model's kinematics"),
    Claim("(A.23)", "parameter", Matrix([0, 0, -(r1_p[0] * cos(phi) - r1_p[1] * sin(phi)) * m1_p * g]),
          "torque of sub-body 1's weight about A", reference=_r_1_phi.cross(Matrix([0, -m_1 * g, 0])),
          note="reference: r_Sm1(phi) × f_Sm1 (3.10) with the model's kinematics and gravity"),
    Claim("(A.26)", "parameter", lf_p, "length of the spring l_f(phi)",
          reference=element_vector(SYSTEM, SYSTEM.forces[0])[1], note="reference: |p_b - p_a| of the model's spring"),
    Claim("(A.27)", "force:spring", fc_vec_p, "spring force f_c on the body at r_fc, with l_f of (A.26)",
          defines=f_c_sym),
    Claim("(A.28)", "eom", I_A_p * phi.accel - (tau_gravity_p + tau_fc_p), ingredients=("(A.27)",),
          description="I_zz^(A) phi'' = tau_z^(A), all torques about A",
          note="I_zz^(A) and tau_z^(A) assembled as the text says: the sub-bodies 2, 3 and the point mass "
               "'in an analogous manner' to (A.20), (A.21), (A.23); the spring torque r_fc x f_c with f_c from "
               "(A.24)-(A.27). (A.27) at phi = 0 is c (l_f^0 - l_f0) e_y, the negative of the force (A.19) "
               "f_c e_y = -c (l_f^0 - l_f0) e_y on the body"),
]

SCENES = [
    Scene("swing", "Exercise A.2, (A.28): turned by 0.2 rad out of the equilibrium phi = 0 set by the spring's "
          "preload (A.18), (A.19) and released from rest; gravity and spring (conservative)", (0.2,), (0.0,), 2.0,
          {"gravity", "springs"}),
]
