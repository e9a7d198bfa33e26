"""Elastically mounted cantilever beam, Exercise A.14 (Figure A.22), solution (A.159)-(A.174).

A carriage S (mass ``m_S``) slides on its guide along ``e_y`` (vertical) with position ``s``; the joint A of the
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

import sympy as sp

from harness.modeling.system import (Coordinate, Gravity, Inertia, Input, Joint, JointDamper, JointSpring, Link, Parameter,
                           Point, PointForce, System, WORLD)

m_S = Parameter("m_S", 5.0, "kg", "mass of the carriage S")
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
g = Parameter("g", 9.81, "m/s^2", "acceleration due to gravity")

# the beam from its three sections (3.24), (3.29): masses and centres along the beam's x axis
_rd = rho.symbol * d.symbol
_sections = [(_rd * b_1.symbol * l_1.symbol, -(l_2.symbol + l_1.symbol / 2)),   # section 1, left of A
             (_rd * b_2.symbol * l_2.symbol, -l_2.symbol / 2),                   # section 2, left of A
             (_rd * b_3.symbol * l_3.symbol, l_3.symbol / 2)]                    # section 3, right of A
m_B = sum(m for m, _ in _sections)
x_sB = sum(m * x for m, x in _sections) / m_B  # = -l_s

force_point = Point("beam", (-(l_1.symbol + l_2.symbol), -b_1.symbol / 2, 0), "f")

SYSTEM = System(
    name="cantilever_beam",
    title="Elastically mounted cantilever beam",
    lecture="Exercise A.14; (A.159)-(A.174)",
    parameters=(m_S, rho, d, b_1, b_2, b_3, l_1, l_2, l_3, I_xxB, I_yyB, I_zzB, c_1, s_10, c_2, d_1, d_2, g),
    coordinates=(Coordinate("s", "m", "position of the carriage along e_y"),
                 Coordinate("phi", "rad", "angle of the beam, clockwise, 0 with relaxed torsion spring")),
    links=(
        Link("carriage", m_S.symbol, (0, 0, 0), Inertia.cuboid(m_S.symbol, 0.2, 0.2, 0.1),
             description="carriage S; it only translates"),
        Link("beam", m_B, (x_sB, 0, 0), Inertia(I_xxB.symbol, I_yyB.symbol, I_zzB.symbol),
             description="beam B of three plates, x along the beam"),
    ),
    joints=(
        Joint("s", "prismatic", WORLD, "carriage", axis="y"),
        Joint("phi", "revolute", "carriage", "beam", axis=(0, 0, -1)),
    ),
    gravity=Gravity(g.symbol, (0, -1, 0)),
    inputs=(Input("f_e", "N", "magnitude f^e of the follower force, perpendicular to the beam"),),
    forces=(
        JointSpring("spring_1", "s", c_1.symbol, s_10.symbol),
        JointSpring("spring_2", "phi", c_2.symbol, 0),
        JointDamper("friction_1", "s", d_1.symbol),
        JointDamper("friction_2", "phi", d_2.symbol),
        PointForce("follower_force", force_point, (0, sp.Symbol("f_e", real=True), 0), frame="beam"),
    ),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
from harness.modeling.claims import Claim  # noqa: E402

_s, _phi = SYSTEM.coordinates
_q, _qd, _qdd = [_s.symbol, _phi.symbol], [_s.rate, _phi.rate], [_s.accel, _phi.accel]
_b1, _b2, _b3, _l1, _l2, _l3 = (x.symbol for x in (b_1, b_2, b_3, l_1, l_2, l_3))
_mS, _g, _fe = m_S.symbol, g.symbol, sp.Symbol("f_e", real=True)
_c, _sp_ = sp.cos(_phi.symbol), sp.sin(_phi.symbol)
_mB = rho.symbol * d.symbol * (_b1 * _l1 + _b2 * _l2 + _b3 * _l3)                     # (A.159)
_ls = ((_b1 * _l1 * (_l1 / 2 + _l2) + _b2 * _l2**2 / 2 - _b3 * _l3**2 / 2)
       / (_b1 * _l1 + _b2 * _l2 + _b3 * _l3))                                          # (A.160)
_V = (_g * _mB * (_s.symbol + _ls * _sp_) + _g * _mS * _s.symbol                      # (A.162), (A.163)
      + c_1.symbol * (_s.symbol - s_10.symbol)**2 / 2 + c_2.symbol * _phi.symbol**2 / 2)  # (A.164)
_T = (_mS * _s.rate**2 / 2                                                             # (A.166)
      + _mB * (_phi.rate**2 * _ls**2 + _s.rate**2 + 2 * _ls * _phi.rate * _s.rate * _c) / 2  # (A.167)
      + I_zzB.symbol * _phi.rate**2 / 2)                                                # (A.168)
_f_q = sp.Matrix([_fe * _c - d_1.symbol * _s.rate,                                     # (A.171a), (A.172a)
                  _fe * (_l1 + _l2) - d_2.symbol * _phi.rate])                          # (A.171b), (A.172b)


def _euler_lagrange(L, f_q):
    """(A.174): d/dt ∂L/∂q̇_j − ∂L/∂q_j − f_q,j, one residual per coordinate."""
    rows = []
    for j in range(len(_q)):
        p = sp.diff(L, _qd[j])
        dp_dt = sum(sp.diff(p, _q[k]) * _qd[k] + sp.diff(p, _qd[k]) * _qdd[k] for k in range(len(_q)))
        rows.append(dp_dt - sp.diff(L, _q[j]) - f_q[j])
    return sp.Matrix(rows)


CLAIMS = [
    Claim("(A.159)", "parameter", _mB, "mass of the beam m_B = rho d (b_1 l_1 + b_2 l_2 + b_3 l_3)", reference=m_B),
    Claim("(A.160)", "parameter", _ls, "distance l_s of the beam's centre of gravity from A", reference=-x_sB),
    Claim("(A.161)", "position:beam", sp.Matrix([-_ls * _c, _s.symbol + _ls * _sp_, 0]),
          "centre of gravity of the beam"),
    Claim("(A.170)", "position:f", sp.Matrix([-(_l1 + _l2) * _c - _b1 / 2 * _sp_,
                                              _s.symbol + (_l1 + _l2) * _sp_ - _b1 / 2 * _c, 0]),
          "point of application of the follower force"),
    Claim("(A.162)-(A.165)", "V", _V, "potential energy V = V_g,B + V_g,S + V_c1 + V_c2"),
    Claim("(A.166)-(A.168)", "T", _T, "kinetic energy T = T_t,S + T_t,B + T_r,B"),
    Claim("(A.169)-(A.173)", "f_np", _f_q, "generalized forces of the follower force and the viscous friction"),
    Claim("(A.174)", "eom", _euler_lagrange(_T - _V, _f_q),
          "Euler-Lagrange equations with L = T - V of (A.162)-(A.168) and f_q of (A.173)",
          note="the lecture omits the evaluation of (A.174); the residuals are (A.174) evaluated symbolically "
               "with the printed L and f_q"),
]

from harness.modeling.scenes import Scene, Step  # noqa: E402

SCENES = [
    Scene("drop", "Exercise A.14, (A.174): released from rest with relaxed springs (s = s_10, phi = 0, as drawn "
          "in Figure A.22); the carriage sinks and the beam tips under gravity against springs and viscous "
          "friction; the follower force f^e = 10 N steps on at 1 s", (0.3, 0.0), (0.0, 0.0), 3.0,
          frozenset({"gravity", "springs", "dampers", "external"}), inputs={"f_e": Step(1.0, 10.0)}),
]
