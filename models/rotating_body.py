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

import sympy as sp

from harness.modeling.system import Coordinate, Gravity, Inertia, Link, Joint, Parameter, Point, Spring, System, WORLD

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
g = Parameter("g", 9.81, "m/s^2", "acceleration due to gravity")

phi = Coordinate("phi", "rad", "angle of the body about z through A, counter-clockwise")

_rho, _d, _b, _l1, _l2, _lm, _mm = (x.symbol for x in (rho, d, b, l_1, l_2, l_m, m_m))

# sub-bodies at phi = 0: mass, centre of gravity, inertia tensor about it (homogeneous cuboids (3.128))
m_1 = _l2 * _d * _b * _rho
r_1 = sp.Matrix([-_l2 / 2, _l1 + 3 * _d / 2, 0])
I_1 = Inertia.cuboid(m_1, _l2, _d, _b).matrix
m_2 = _d * (_l1 + 2 * _d) * _b * _rho
r_2 = sp.Matrix([_d / 2, _d + _l1 / 2, 0])
I_2 = Inertia.cuboid(m_2, _d, _l1 + 2 * _d, _b).matrix
m_3 = _l2 * _d * _b * _rho
r_3 = sp.Matrix([_d + _l2 / 2, _d / 2, 0])
I_3 = Inertia.cuboid(m_3, _l2, _d, _b).matrix
r_m = sp.Matrix([_d + _lm, _d, 0])                                   # the point mass, no own inertia


def steiner(mass, r):
    """Inertia tensor of a mass ``mass`` at offset ``r`` from the reference point (3.126)."""
    return mass * ((r.T * r)[0] * sp.eye(3) - r * r.T)


# the rigid body: mass, centre of gravity, inertia about A (A.21) and about the centre of gravity
m_g = m_1 + m_2 + m_3 + _mm
p_S = (m_1 * r_1 + m_2 * r_2 + m_3 * r_3 + _mm * r_m) / m_g
I_A = I_1 + steiner(m_1, r_1) + I_2 + steiner(m_2, r_2) + I_3 + steiner(m_3, r_3) + steiner(_mm, r_m)
I_S = I_A - steiner(m_g, p_S)

spring_body = Point("body", (-_l2, _d + _l1, 0), "fc")                      # r_fc^0 (A.14)
spring_ground = Point(WORLD, (-_l2, _d + _l1 - l_f_0.symbol, 0), "fcfp")    # r_fcfp (A.25)

SYSTEM = System(
    name="rotating_body",
    title="Rotating rigid body",
    lecture="Exercise A.2; (A.10)-(A.28)",
    parameters=(rho, d, b, l_1, l_2, l_m, m_m, c, l_f_0, l_f0, g),
    coordinates=(phi,),
    links=(Link("body", m_g, tuple(p_S),
                Inertia(I_S[0, 0], I_S[1, 1], I_S[2, 2], I_S[0, 1], I_S[0, 2], I_S[1, 2]),
                description="frame (three homogeneous bars) and point mass m_m, one rigid body"),),
    joints=(Joint("phi", "revolute", WORLD, "body", axis="z"),),
    gravity=Gravity(g.symbol, (0, -1, 0)),
    forces=(Spring("spring", spring_ground, spring_body, c.symbol, l_f0.symbol),),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
from harness.modeling.claims import Claim  # noqa: E402

_p, _pdd = phi.symbol, phi.accel
_g, _c, _lf_0, _lf0 = g.symbol, c.symbol, l_f_0.symbol, l_f0.symbol
_x, _y, _z = sp.symbols("x y z", real=True)
_bounds_1 = ((_x, -_l2, 0), (_y, _l1 + _d, _l1 + 2 * _d), (_z, -_b / 2, _b / 2))   # sub-body 1, (A.11)


def _rot(r):
    """``r`` turned by phi about z, as printed in (A.22), (A.24)."""
    return sp.Matrix([r[0] * sp.cos(_p) - r[1] * sp.sin(_p), r[0] * sp.sin(_p) + r[1] * sp.cos(_p), 0])


# printed quantities of the solution
_m1_p, _m2_p, _m3_p = _l2 * _d * _b * _rho, _d * (_l1 + 2 * _d) * _b * _rho, _l2 * _d * _b * _rho
_r1_p = sp.Matrix([-_l2 / 2, _l1 + 3 * _d / 2, 0])                                   # (A.12)
_r2_p = sp.Matrix([_d / 2, _d + _l1 / 2, 0])                                         # (A.13)
_r3_p = sp.Matrix([_d + _l2 / 2, _d / 2, 0])
_rm_p = sp.Matrix([_d + _lm, _d, 0])
_rfc0_p = sp.Matrix([-_l2, _d + _l1, 0])                                             # (A.14)
_f_c_p = (_m1_p * _g * _l2 / 2 - _m2_p * _g * _d / 2 - _m3_p * _g * (_d + _l2 / 2)
          - _mm * _g * (_d + _lm)) / _l2                                             # (A.18)
_I1S_p = _m1_p / 12 * (_l2**2 + _d**2)                                               # (A.20)
_I_A_p = (_I1S_p + _m1_p * (_r1_p[0]**2 + _r1_p[1]**2)                               # (A.21), (A.28)
          + _m2_p / 12 * (_d**2 + (_l1 + 2 * _d)**2) + _m2_p * (_r2_p[0]**2 + _r2_p[1]**2)
          + _m3_p / 12 * (_l2**2 + _d**2) + _m3_p * (_r3_p[0]**2 + _r3_p[1]**2)
          + _mm * (_rm_p[0]**2 + _rm_p[1]**2))
_tau_gravity_p = sum(-(r[0] * sp.cos(_p) - r[1] * sp.sin(_p)) * mass * _g                # (A.23)
                     for mass, r in ((_m1_p, _r1_p), (_m2_p, _r2_p), (_m3_p, _r3_p), (_mm, _rm_p)))
_rfc_p = _rot(_rfc0_p)                                                               # (A.24)
_rfcfp_p = sp.Matrix([-_l2, _d + _l1 - _lf_0, 0])                                    # (A.25)
_lf_p = sp.sqrt(((_rfc_p - _rfcfp_p).T * (_rfc_p - _rfcfp_p))[0])                    # (A.26)
_fc_vec_p = _c * (_lf_p - _lf0) * (_rfc_p - _rfcfp_p) / _lf_p                        # (A.27)
_tau_fc_p = _rfc_p[0] * _fc_vec_p[1] - _rfc_p[1] * _fc_vec_p[0]                     # (r_fc x f_c)_z

CLAIMS = [
    Claim("(A.10)", "parameter", _m1_p, "mass of sub-body 1", reference=sp.integrate(_rho, *_bounds_1)),
    Claim("(A.11)", "parameter", -_l2 / 2, "r_Sm1,x by (3.29)",
          reference=sp.integrate(_x * _rho, *_bounds_1) / _m1_p),
    Claim("(A.12)", "parameter", _r1_p, "centre of gravity of sub-body 1 at phi = 0",
          reference=sp.Matrix([sp.integrate(v * _rho, *_bounds_1) / _m1_p for v in (_x, _y, _z)])),
    Claim("(after A.12)", "parameter", sp.Matrix([_m2_p, _m3_p]), "masses m_2, m_3 of sub-bodies 2, 3",
          reference=sp.Matrix([m_2, m_3])),
    Claim("(A.13)", "parameter", sp.Matrix.hstack(_r2_p, _r3_p, _rm_p),
          "centres of gravity of sub-bodies 2, 3 and of the point mass at phi = 0",
          reference=sp.Matrix.hstack(r_2, r_3, r_m)),
    Claim("(A.14), (A.24)", "position:fc", _rfc_p, "point of application of the spring force"),
    Claim("(A.25)", "position:fcfp", _rfcfp_p, "base point of the spring"),
    Claim("(A.17) ff.", "parameter",
          sp.Matrix([_m1_p * _g * _l2 / 2, -_m2_p * _g * _d / 2, -_m3_p * _g * (_d + _l2 / 2), -_mm * _g * (_d + _lm)]),
          "gravity torques about A at phi = 0: tau_m1,z, tau_m2,z, tau_m3,z, tau_mm,z",
          reference=sp.Matrix([r.cross(sp.Matrix([0, -mass * _g, 0]))[2]
                               for mass, r in ((m_1, r_1), (m_2, r_2), (m_3, r_3), (_mm, r_m))])),
    Claim("(A.18)", "parameter", _f_c_p, "spring force f_c (along +y) that holds the body at phi = 0",
          reference=-m_g * _g * p_S[0] / _l2,
          note="reference: the torque balance about A at phi = 0, -m_g g x_S + (-l_2) f_c = 0"),
    Claim("(A.20)", "parameter", _I1S_p, "I_zz,m1^(S) of sub-body 1",
          reference=_rho * sp.integrate(_x**2 + _y**2, (_x, -_l2 / 2, _l2 / 2), (_y, -_d / 2, _d / 2),
                                        (_z, -_b / 2, _b / 2))),
    Claim("(A.21)", "parameter", _I1S_p + _m1_p * (_r1_p[0]**2 + _r1_p[1]**2), "I_zz,m1^(A) of sub-body 1",
          reference=(I_1 + steiner(m_1, r_1))[2, 2]),
    Claim("(A.28)", "eom", _I_A_p * _pdd - (_tau_gravity_p + _tau_fc_p),
          "I_zz^(A) phi'' = tau_z^(A), all torques about A",
          note="I_zz^(A) and tau_z^(A) assembled as the text says: the sub-bodies 2, 3 and the point mass "
               "'in an analogous manner' to (A.20), (A.21), (A.23); the spring torque r_fc x f_c with f_c from "
               "(A.24)-(A.27). (A.27) at phi = 0 is c (l_f^0 - l_f0) e_y, the negative of the force (A.19) "
               "f_c e_y = -c (l_f^0 - l_f0) e_y on the body"),
]

from harness.modeling.scenes import Scene  # noqa: E402

SCENES = [
    Scene("swing", "Exercise A.2, (A.28): turned by 0.2 rad out of the equilibrium phi = 0 set by the spring's "
          "preload (A.18), (A.19) and released from rest; gravity and spring (conservative)", (0.2,), (0.0,), 2.0,
          frozenset({"gravity", "springs"})),
]
