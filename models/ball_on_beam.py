"""Ball on beam, Example 5.4 (Figure 5.6) and Exercise 5.1; (5.82)-(5.91).

A beam turns about the ``z_0`` axis of the inertial frame by the angle ``phi_1`` (frame ``(0_1 x_1 y_1 z_1)``,
its origin on the axis of rotation, ``x_1`` along the beam). A homogeneous ball (mass ``m_K``, radius ``r_K``)
rolls without slipping on the beam; its centre lies at ``[r, r_K, 0]`` in the beam frame, so that by (5.82)
``p^{sK} = [r cos(phi_1) - r_K sin(phi_1), r sin(phi_1) + r_K cos(phi_1), 0]``. The generalized coordinates are
``q = [phi_1, r]``. Gravity acts in ``e_g = [0, -1, 0]``: (5.88) is ``m_K g p^{sK}_y`` minus the constant
``m_K g r_K`` (zero level at ``phi_1 = 0``). The input is the external torque ``tau^e`` (``tau_e``) about the
axis of rotation, acting on the beam (a motor torque in the beam's joint).

Rolling (5.85): the ball turns relative to the beam by ``phi_2`` about ``z_1`` with ``r_dot = -r_K phi_2_dot``,
i.e. ``phi_2 = -r / r_K`` (zero at ``r = 0``); its absolute angular velocity is ``phi_1_dot + phi_2_dot``
(5.86). Tree: ``phi_1`` revolute about ``z_0`` (beam), ``r`` prismatic along ``x_1`` from ``[0, r_K, 0]``
(massless frame ``contact``), ``phi_2`` revolute about ``z`` (ball, centre of mass at the frame origin,
isotropic inertia ``I_zz^{sK} = 2/5 m_K r_K^2`` (5.84), (3.123)). The map ``theta = phi(q)`` has three tree
joints for two lecture coordinates: ``theta = [phi_1, r, -r / r_K]`` - the rolling constraint.

The lecture gives only the beam's moment of inertia ``I_zz^B`` about the axis of rotation (written
``I_zz^{sB}`` in (5.87), (5.91b)). The model adds what a rigid body needs and does not enter the equations: the
beam's mass ``m_B`` with its centre of mass on the axis of rotation, and its moments ``I_xx^B``, ``I_yy^B``.
Defaults: a wooden ball of radius 0.1 m on a 2 m beam (5 kg, cross-section 0.1 m x 0.05 m). A ball much smaller
than that (r_K of a few cm) makes the Christoffel C from Pinocchio's RNEA derivatives exceed 1e-12: its tree
round-off (world-frame spatial algebra of a ball spinning at r_dot/r_K) is amplified by the rolling map
J = dphi/dq, whose entry -1/r_K enters C_q = J^T C_theta J twice (error ~ 1/r_K^3, not a modeling error).
"""

from sympy import Matrix, cos, diff, sin

from harness.derivation.bodies import Ball, moment_of_inertia, solid_volume
from harness.modeling import (Printed, WORLD, Claim, Coordinate, Gravity, Inertia, Input, Joint, JointInput, Link, Parameter,
                              Scene, Step, System, standard_gravity)

m_K = Parameter("m_K", 2.0, "kg", "mass of the ball")
r_K = Parameter("r_K", 0.1, "m", "radius of the ball")
m_B = Parameter("m_B", 5.0, "kg", "mass of the beam (centre of mass on the axis of rotation; does not enter)")
I_xxB = Parameter("I_xxB", 0.0052, "kg m^2", "moment of inertia of the beam about x_1 (does not enter)")
I_yyB = Parameter("I_yyB", 1.668, "kg m^2", "moment of inertia of the beam about y_1 (does not enter)")
I_zzB = Parameter("I_zzB", 1.671, "kg m^2", "moment of inertia I_zz^B of the beam about the axis of rotation z")
g = standard_gravity()

tau_e = Input("tau_e", "N m", "external torque tau^e about the axis of rotation, on the beam")

phi_1 = Coordinate("phi_1", "rad", "angle of the beam against x_0")
r = Coordinate("r", "m", "position of the ball's centre along the beam, from the y_1 axis")

I_zz_sK = 2 * m_K * r_K**2 / 5  # (5.84), homogeneous ball (3.123)

SYSTEM = System(
    name="ball_on_beam",
    title="Ball on beam",
    lecture="Example 5.4, Exercise 5.1; (5.82)-(5.91)",
    coordinates=(phi_1, r),
    links=(
        Link("beam", m_B, (0, 0, 0), Inertia(I_xxB, I_yyB, I_zzB)),
        Link("contact", description="massless frame at the ball's centre, sliding along x_1 by r"),
        Link("ball", m_K, (0, 0, 0), Inertia(I_zz_sK, I_zz_sK, I_zz_sK),
             description="homogeneous ball, turned by phi_2 = -r/r_K relative to the beam (rolling)"),
    ),
    joints=(
        Joint("phi_1", "revolute", WORLD, "beam", axis="z"),
        Joint("r", "prismatic", "beam", "contact", axis="x", origin=(0, r_K, 0)),
        Joint("phi_2", "revolute", "contact", "ball", axis="z", phi=-r / r_K),  # rolling (5.85): r_dot = -r_K phi_2_dot
    ),
    gravity=Gravity(g, (0, -1, 0)),
    forces=(JointInput("torque_e", "phi_1", tau_e),),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
w_1, v = phi_1.rate, r.rate
I_zz_sB = Printed("I_zz^sB", "kg m^2", "printed I_zz^{sB} in (5.87), (5.91b); the text introduces I_zz^B")
I_K = I_zz_sK
T_printed = (m_K * (r**2 * w_1**2 + (v - r_K * w_1)**2) / 2      # (5.83)
             + I_K * (w_1 - v / r_K)**2 / 2                      # (5.86)
             + I_zz_sB * w_1**2 / 2)                             # (5.87)
V_printed = m_K * g * (r * sin(phi_1) + r_K * cos(phi_1)) - m_K * g * r_K  # (5.88)
_I_K_note = "I_zz^{sK} = 2/5 m_K r_K^2 (5.84)"
_ball = Ball(r_K)
CLAIMS = [
    Claim("(5.84)", "parameter", 2 * m_K * r_K**2 / 5, "I_zz^sK: the ball's moment of inertia about its centre",
          reference=lambda: moment_of_inertia(_ball, m_K / solid_volume(_ball)),
          note="reference: the volume integral over a homogeneous ball of radius r_K and mass m_K, independent of "
               "the formula the model builds the ball's inertia from"),
    Claim("(5.82)", "position:ball", Matrix([r * cos(phi_1) - r_K * sin(phi_1), r * sin(phi_1) + r_K * cos(phi_1), 0]),
          "centre of the ball"),
    Claim("(5.85)", "parameter", -r_K, "rolling: r_dot = -r_K phi_2_dot, the printed factor between the rates",
          reference=1 / diff(SYSTEM.joint("phi_2").phi, r.symbol),
          note="φ_2 is the ball's tree joint phi_2 (its angle relative to the beam); the printed factor "
               "-r_K = r_dot/phi_2_dot is compared with the model's joint map phi_2 = -r/r_K "
               "(reference 1/(∂phi_2/∂r))"),
    Claim("(5.83)+(5.86)+(5.87)", "T", T_printed, "kinetic energy T_t,K + T_r,K + T_r,B of the Lagrangian (5.89)",
          note=_I_K_note),
    Claim("(5.88)", "g", Matrix([V_printed]).jacobian([phi_1, r]).T,
          "potential forces g = dV/dq (5.96) of V = m_K g (r sin(phi_1) + r_K cos(phi_1)) - m_K g r_K",
          note="V is fixed only up to a constant ((5.88) sets V = 0 at phi_1 = 0, the model's V = m_K g p_y differs "
               "by m_K g r_K); the printed V is compared through its gradient g = dV/dq"),
    Claim("(5.91a)", "eom", (m_K + I_K / r_K**2) * r.accel - (I_K / r_K + m_K * r_K) * phi_1.accel
          - m_K * r * w_1**2 + m_K * g * sin(phi_1), "equation of r", index=(1,), note=_I_K_note),
    Claim("(5.91b)", "eom", -(m_K * r_K + I_K / r_K) * r.accel + (I_K + I_zz_sB + m_K * (r**2 + r_K**2)) * phi_1.accel
          + 2 * m_K * r * v * w_1 + m_K * g * (r * cos(phi_1) - r_K * sin(phi_1)) - tau_e,
          "equation of phi_1", index=(0,), note="I_zz^{sB} as printed"),
]

SCENES = [
    Scene("tilt", "Example 5.4: the beam tilted by a torque step, the ball rolls (rolling map in the engines)",
          (0.0, 0.3), (0.0, 0.0), 2.0, {"gravity", "inputs"}, inputs={tau_e: Step(0.5, 2.0)}),
]
