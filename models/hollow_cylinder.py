"""Rotationally constrained hollow cylinder, Exercise A.12 (Figure A.20), solution (A.124)-(A.141).

A hollow cylinder 1 (mass ``m_1``, length ``l_1``, inner diameter ``d_2``) turns about the pivot ``K`` at
``[0, h, 0]`` by the angle ``phi``, measured from the downward vertical, driven by the external torque ``tau_e``
about ``e_z`` ((A.137): ``f_phi = tau_e``). A cylindrical rod 2 (mass ``m_2``, length ``l_2``, diameter ``d_2``)
slides inside it along the common axis; ``s`` is the distance from ``K`` to the rod's inner end, the point of
application ``p_0^d`` (A.135) of the friction force. A linear spring (stiffness ``c``, unstretched length
``s_0``) acts between the cylinders, ``V_f = c/2 (s - s_0)²`` (A.130). Gravity acts in ``-e_y``. Centres of
mass (A.125), (A.126): ``p_0^{s1} = [0, h, 0] + l_1/2 [sin(phi), -cos(phi), 0]`` (base area neglected),
``p_0^{s2} = [0, h, 0] + (s + l_2/2) [sin(phi), -cos(phi), 0]``.

Friction (A.134)-(A.136): a velocity-proportional force with a coefficient proportional to the contact area
``A(s) = (l_1 - s) d_2 pi``, ``f_d = d_0 (l_1 - s) d_2 pi s_dot``, acting on rod 2 at ``p_0^d`` along the axis,
``f_d [-sin(phi), cos(phi), 0]``; generalized forces ``f_s = -f_d``, ``f_phi = 0``. The harness's joint dampers
have constant coefficients (MuJoCo's joint damping is a polynomial in the velocity only), so the friction is
modeled as the lecture does: an external force at ``p_0^d`` whose components depend on ``s``, ``s_dot``,
``phi``; each engine turns it into generalized forces with its own Jacobians (5.73). Its reaction on
cylinder 1 acts along the axis at a point that does not move along the axis, so it does no virtual work and
is left out, as in the lecture. It appears in ``f_np``, not in the damper check ``f_damper``.

Tree: the revolute joint ``phi`` (axis ``z``) at ``[0, h, 0]`` carries cylinder 1, whose axis points along
``-y`` of its frame; the prismatic joint ``s`` along ``-y`` of cylinder 1 carries rod 2 (identity map). The
spring is a spring on the joint ``s``, the torque a torque on cylinder 1. Inertia tensors about the centres of
mass are diagonal in the body frames: ``I_yy`` about the cylinder's axis, ``I_xx``, ``I_zz`` transverse; only
``I_zz1``, ``I_zz2`` (the lecture's ``I_{1,zz}^{(S)}``, ``I_{2,zz}^{(S)}``) enter. The outer diameter ``d_1``
enters nothing here and is not a parameter.

The drawn states keep ``s`` in ``[0, 0.4]`` m, so that the contact length ``l_1 - s`` stays positive for every
drawn ``l_1`` (at least 0.4 m) and the friction coefficient ``d(s)`` non-negative.

The equilibria (A.140), (A.141) ``phi_R = k pi``, ``s_R = m_2 g cos(phi_R)/c + s_0`` are two claims, the
lower (``k = 0``) and the upper (``k = 1``) one; further ``k`` repeat them.
"""

from sympy import Matrix, cos, pi, sin

from harness.modeling import (WORLD, BodyTorque, Claim, Coordinate, Gravity, Inertia, Input, Joint, JointSpring, Link,
                              Parameter, Point, PointForce, Scene, Step, System, standard_gravity)

m_1 = Parameter("m_1", 1.0, "kg", "mass of the hollow cylinder 1")
l_1 = Parameter("l_1", 0.8, "m", "length of the hollow cylinder 1")
I_xx1 = Parameter("I_xx1", 0.054, "kg m^2", "inertia of cylinder 1 about x_1 through s1 (transverse)")
I_yy1 = Parameter("I_yy1", 0.0005, "kg m^2", "inertia of cylinder 1 about y_1 through s1 (its axis)")
I_zz1 = Parameter("I_zz1", 0.054, "kg m^2", "inertia of cylinder 1 about z_1 through s1 (I_{1,zz}^{(S)})")
m_2 = Parameter("m_2", 0.6, "kg", "mass of the rod 2")
l_2 = Parameter("l_2", 0.6, "m", "length of the rod 2")
d_2 = Parameter("d_2", 0.04, "m", "diameter of the rod 2 (inner diameter of cylinder 1)")
I_xx2 = Parameter("I_xx2", 0.018, "kg m^2", "inertia of rod 2 about x_2 through s2 (transverse)")
I_yy2 = Parameter("I_yy2", 0.00012, "kg m^2", "inertia of rod 2 about y_2 through s2 (its axis)")
I_zz2 = Parameter("I_zz2", 0.018, "kg m^2", "inertia of rod 2 about z_2 through s2 (I_{2,zz}^{(S)})")
h = Parameter("h", 1.0, "m", "height of the pivot K")
c = Parameter("c", 200.0, "N/m", "stiffness of the spring between the cylinders")
s_0 = Parameter("s_0", 0.3, "m", "unstretched length of the spring")
d_0 = Parameter("d_0", 50.0, "N s/m^3", "friction coefficient per contact area, d(s) = d_0 A(s)")
g = standard_gravity()

phi = Coordinate("phi", "rad", "angle of the cylinders from the downward vertical")
s = Coordinate("s", "m", "distance from the pivot K to the inner end of rod 2", range=(0.0, 0.4))
tau_e = Input("tau_e", "N m", "external torque about e_z on cylinder 1")
f_d = d_0 * (l_1 - s) * d_2 * pi * s.rate  # (A.134)

SYSTEM = System(
    name="hollow_cylinder",
    title="Rotationally constrained hollow cylinder",
    lecture="Exercise A.12; (A.125)-(A.141)",
    coordinates=(phi, s),
    links=(
        Link("cylinder_1", m_1, (0, -l_1 / 2, 0), Inertia(I_xx1, I_yy1, I_zz1),
             description="hollow cylinder, axis along -y of its frame"),
        Link("rod_2", m_2, (0, -l_2 / 2, 0), Inertia(I_xx2, I_yy2, I_zz2),
             description="rod sliding in cylinder 1, frame at its inner end p_0^d"),
    ),
    joints=(
        Joint("phi", "revolute", WORLD, "cylinder_1", axis="z", origin=(0, h, 0)),
        Joint("s", "prismatic", "cylinder_1", "rod_2", axis=(0, -1, 0)),
    ),
    gravity=Gravity(g, (0, -1, 0)),
    forces=(
        JointSpring("spring", "s", c, s_0),
        BodyTorque("torque_e", "cylinder_1", (0, 0, tau_e)),
        PointForce("friction_d", Point("rod_2", (0, 0, 0), "d"), (-f_d * sin(phi), f_d * cos(phi), 0)),
    ),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
w_p, w_s = phi.rate, s.rate
e = Matrix([sin(phi), -cos(phi), 0])
K = Matrix([0, h, 0])
_I_note = "I_{1,zz}^{(S)}, I_{2,zz}^{(S)} read as I_zz1, I_zz2"
CLAIMS = [
    Claim("(A.125)", "position:cylinder_1", K + l_1 / 2 * e, "centre of mass of the hollow cylinder"),
    Claim("(A.126)", "position:rod_2", K + (s + l_2 / 2) * e, "centre of mass of the rod"),
    Claim("(A.127a)", "v:cylinder_1", l_1 / 2 * Matrix([cos(phi), sin(phi), 0]) * w_p,
          "velocity of the hollow cylinder's centre of mass"),
    Claim("(A.127b)", "v:rod_2", Matrix([sin(phi), -cos(phi), 0]) * w_s + (s + l_2 / 2) * Matrix([cos(phi), sin(phi), 0]) * w_p,
          "velocity of the rod's centre of mass"),
    Claim("(A.135)", "position:d", Matrix([s * sin(phi), h - s * cos(phi), 0]),
          "point of application of the friction force"),
    Claim("(A.128), (A.129)", "T", (I_zz1 + I_zz2) * w_p**2 / 2 + m_1 * l_1**2 * w_p**2 / 8
          + m_2 * (w_s**2 + w_p**2 * (s + l_2 / 2)**2) / 2, "kinetic energy T = T_r + T_t1 + T_t2", note=_I_note),
    Claim("(A.130), (A.131)", "V", c * (s - s_0)**2 / 2 + m_1 * g * (h - l_1 / 2 * cos(phi))
          + m_2 * g * (h - (s + l_2 / 2) * cos(phi)), "potential energy V = V_f + V_1 + V_2"),
    Claim("(A.133a)", "dL_dqd:phi", m_1 * l_1**2 * w_p / 4 + m_2 * (s + l_2 / 2)**2 * w_p + (I_zz1 + I_zz2) * w_p,
          "∂L/∂phi_dot", note=_I_note),
    Claim("(A.133b)", "ddt_dL_dqd:phi", m_1 * l_1**2 * phi.accel / 4 + m_2 * (s + l_2 / 2)**2 * phi.accel
          + 2 * m_2 * (s + l_2 / 2) * w_p * w_s + (I_zz1 + I_zz2) * phi.accel, "d/dt ∂L/∂phi_dot", note=_I_note),
    Claim("(A.133c)", "dL_dq:phi", -m_1 * g * l_1 / 2 * sin(phi) - m_2 * g * (s + l_2 / 2) * sin(phi), "∂L/∂phi"),
    Claim("(A.133d)", "dL_dqd:s", m_2 * w_s, "∂L/∂s_dot"),
    Claim("(A.133e)", "ddt_dL_dqd:s", m_2 * s.accel, "d/dt ∂L/∂s_dot"),
    Claim("(A.133f)", "dL_dq:s", m_2 * w_p**2 * (s + l_2 / 2) - c * (s - s_0) + m_2 * g * cos(phi), "∂L/∂s"),
    Claim("(A.136a), (A.136b)", "f_np:friction_d", Matrix([0, -f_d]),
          "generalized forces of the friction force: f_{f_d,phi} = 0, f_{f_d,s} = -f_d",
          note="printed as two scalars, f_{f_d,s} (A.136a) and f_{f_d,phi} (A.136b); here in the order (phi, s) of q; "
               "f_d from (A.134)"),
    Claim("(A.137a), (A.137b)", "f_np:torque_e", Matrix([tau_e, 0]),
          "generalized forces of the external torque: f_{tau_e,phi} = tau_e, f_{tau_e,s} = 0",
          note="printed as two scalars, f_{tau_e,s} (A.137a) and f_{tau_e,phi} (A.137b); here in the order (phi, s)"),
    Claim("(A.138)", "f_np", Matrix([tau_e, -f_d]), "generalized forces f_phi = tau_e, f_s = -f_d",
          note="f_d from (A.134): d_0 (l_1 - s) d_2 pi s_dot"),
    Claim("(A.139a)", "eom", (m_1 * l_1**2 / 4 + m_2 * (s + l_2 / 2)**2 + I_zz1 + I_zz2) * phi.accel
          + 2 * m_2 * (s + l_2 / 2) * w_p * w_s + g * (m_1 * l_1 / 2 + m_2 * (s + l_2 / 2)) * sin(phi) - tau_e,
          "equation of motion of phi", index=(0,), note=_I_note),
    Claim("(A.139b)", "eom", m_2 * s.accel + c * (s - s_0) - m_2 * g * cos(phi) - m_2 * w_p**2 * (s + l_2 / 2)
          - (-f_d), "equation of motion of s", index=(1,), note="f_d from (A.134)"),
    Claim("(A.140), (A.141) k = 0", "equilibrium", Matrix([0, m_2 * g * cos(0) / c + s_0]),
          "lower equilibrium phi_R = 0, s_R = m_2 g cos(phi_R)/c + s_0 = s_0 + m_2 g/c (tau_e = 0)"),
    Claim("(A.140), (A.141) k = 1", "equilibrium", Matrix([pi, m_2 * g * cos(pi) / c + s_0]),
          "upper equilibrium phi_R = pi, s_R = m_2 g cos(phi_R)/c + s_0 = s_0 - m_2 g/c (tau_e = 0)"),
]

SCENES = [
    Scene("swing", "Exercise A.12, (A.139): released from rest at phi = 0.6 rad with the rod at s = 0.25 m; the "
          "rod slides against the spring and the contact-area friction (A.134); the torque tau_e = 2 N m steps on "
          "at 1.5 s", (0.6, 0.25), (0.0, 0.0), 3.0, {"gravity", "springs", "external"},
          inputs={tau_e: Step(1.5, 2.0)}),
]
