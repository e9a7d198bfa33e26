"""Rotatory two-mass oscillator, Exercise 5.3 (Figure 5.8), solution (5.103)-(5.108).

Two rigid bodies rotate about the common ``x_0`` axis, which is a principal axis of inertia of both, with
their centres of mass on it (no products of inertia, no unbalance). Lecture coordinates are the *absolute*
angles ``phi_1``, ``phi_2`` of the bodies about ``x_0``. The kinematic tree is a chain: body 1 turns about
``x_0`` by ``theta_phi_1 = phi_1``; body 2 is mounted on body 1 (0.5 m further along ``x``, a value that
never enters) and turns by the *relative* angle ``theta_phi_2rel = phi_2 - phi_1`` (the linear map
``theta = phi(q)``). So the torsion spring ``c_12`` and the rotary damper ``d_12`` between the bodies act on
the relative joint, ``c_1`` and ``d_1`` between body 1 and the inertial system on joint 1:
``V = c_1/2 phi_1² + c_12/2 (phi_2 - phi_1)²`` (5.104), relaxed at ``phi_1 = 0`` and ``phi_1 - phi_2 = 0``.

External torques ``tau_1``, ``tau_2`` act on bodies 1 and 2 about ``x_0``, counted in the positive sense of
``phi_1``, ``phi_2`` as every other torque of the lecture (the text says only that "an external torque acts";
Figure 5.8 is not in the text). The solution (5.105) counts them *against* it (``tau_e1 = -tau_1 - …``,
``tau_e2 = -tau_2 + …``), and (5.107) agrees: those claims carry that reading as a declared convention, so the
harness reports them as convention-dependent instead of the model being built to match them.
No gravity is mentioned (and with the centres of mass on the axis it would not act). Only ``I_xx,1``,
``I_xx,2`` enter the motion; the masses and the inertias about ``y``, ``z`` (discs) are there because an
engine needs a physical body.
"""

from sympy import Matrix, zeros

from harness.modeling import (WORLD, BodyTorque, Claim, Coordinate, Inertia, Input, Joint, JointDamper, JointSpring,
                              Link, Parameter, Scene, Step, System)

I_xx1 = Parameter("I_xx1", 0.02, "kg m^2", "inertia of body 1 about its axis of rotation x (I_xx,1^s1)")
I_yy1 = Parameter("I_yy1", 0.011, "kg m^2", "inertia of body 1 about y through s1 (does not enter)")
I_zz1 = Parameter("I_zz1", 0.011, "kg m^2", "inertia of body 1 about z through s1 (does not enter)")
I_xx2 = Parameter("I_xx2", 0.05, "kg m^2", "inertia of body 2 about its axis of rotation x (I_xx,2^s2)")
I_yy2 = Parameter("I_yy2", 0.027, "kg m^2", "inertia of body 2 about y through s2 (does not enter)")
I_zz2 = Parameter("I_zz2", 0.027, "kg m^2", "inertia of body 2 about z through s2 (does not enter)")
m_1 = Parameter("m_1", 4.0, "kg", "mass of body 1 (does not enter)")
m_2 = Parameter("m_2", 6.0, "kg", "mass of body 2 (does not enter)")
c_1 = Parameter("c_1", 40.0, "N m/rad", "torsion spring between the inertial system and body 1")
c_12 = Parameter("c_12", 25.0, "N m/rad", "torsion spring between body 1 and body 2")
d_1 = Parameter("d_1", 0.2, "N m s/rad", "rotary damper between the inertial system and body 1")
d_12 = Parameter("d_12", 0.1, "N m s/rad", "rotary damper between body 1 and body 2")

phi_1 = Coordinate("phi_1", "rad", "absolute angle of body 1 about x_0")
phi_2 = Coordinate("phi_2", "rad", "absolute angle of body 2 about x_0")

tau_1 = Input("tau_1", "N m", "external torque on body 1 about x_0, in the sense of phi_1")
tau_2 = Input("tau_2", "N m", "external torque on body 2 about x_0, in the sense of phi_2")

SYSTEM = System(
    name="two_mass_oscillator",
    title="Rotatory two-mass oscillator",
    lecture="Exercise 5.3; (5.103)-(5.108)",
    coordinates=(phi_1, phi_2),
    links=(
        Link("body_1", m_1, (0, 0, 0), Inertia(I_xx1, I_yy1, I_zz1),
             description="rigid body 1, centre of mass on the axis x_0"),
        Link("body_2", m_2, (0, 0, 0), Inertia(I_xx2, I_yy2, I_zz2),
             description="rigid body 2, centre of mass on the axis x_0"),
    ),
    joints=(
        Joint("phi_1", "revolute", WORLD, "body_1", axis="x"),
        Joint("phi_2rel", "revolute", "body_1", "body_2", axis="x", origin=(0.5, 0, 0), phi=phi_2 - phi_1),
    ),
    forces=(
        JointSpring("spring_1", "phi_1", c_1),
        JointSpring("spring_12", "phi_2rel", c_12),
        JointDamper("damper_1", "phi_1", d_1),
        JointDamper("damper_12", "phi_2rel", d_12),
        BodyTorque("torque_1", "body_1", (tau_1, 0, 0)),
        BodyTorque("torque_2", "body_2", (tau_2, 0, 0)),
    ),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
w_1, w_2 = phi_1.rate, phi_2.rate                     # omega_1, omega_2 of (5.103)
_SUPERSCRIPT = "I_xx,1 (I_xx,1^s1 in (5.108)) read as I_xx1, I_xx,2 as I_xx2"
_AGAINST = {"tau_1, tau_2 counted against phi_1, phi_2 (the sense Figure 5.8 may draw; not in the text)":
            {tau_1: -tau_1, tau_2: -tau_2}}
CLAIMS = [
    Claim("(5.103)", "T", I_xx1 * w_1**2 / 2 + I_xx2 * w_2**2 / 2, "T_1 + T_2, omega_i = phi_i'", note=_SUPERSCRIPT),
    Claim("(5.104)", "V", c_1 * phi_1**2 / 2 + c_12 * (phi_2 - phi_1)**2 / 2, "V_c1 + V_c12"),
    Claim("(5.105), (5.106)", "f_np", Matrix([-tau_1 - d_1 * w_1 - d_12 * (w_1 - w_2), -tau_2 + d_12 * (w_1 - w_2)]),
          "f_q^np = [tau_e1, tau_e2]", conventions=_AGAINST),
    Claim("(5.107b)", "eom", I_xx1 * phi_1.accel
          - (-c_1 * phi_1 - d_1 * w_1 + c_12 * (phi_2 - phi_1) + d_12 * (w_2 - w_1) - tau_1),
          "d/dt omega_1 = (…)/I_xx,1", index=(0,), conventions=_AGAINST,
          note="transcribed multiplied by I_xx,1 (residual in N m); " + _SUPERSCRIPT),
    Claim("(5.107d)", "eom", I_xx2 * phi_2.accel - (-c_12 * (phi_2 - phi_1) - d_12 * (w_2 - w_1) - tau_2),
          "d/dt omega_2 = (…)/I_xx,2", index=(1,), conventions=_AGAINST,
          note="transcribed multiplied by I_xx,2 (residual in N m); " + _SUPERSCRIPT),
    Claim("(5.108)", "M", Matrix([[I_xx1, 0], [0, I_xx2]]), "mass matrix", note=_SUPERSCRIPT),
    Claim("(5.108)", "C", zeros(2, 2), "Coriolis matrix C = 0"),
    Claim("(5.108)", "g", Matrix([c_1 * phi_1 + c_12 * (phi_1 - phi_2), -c_12 * (phi_1 - phi_2)]), "potential forces"),
]

SCENES = [
    Scene("twisted", "Exercise 5.3, (5.107): body 1 released from rest at phi_1 = 0.3 rad (body 2 at 0), springs "
          "and dampers; the torque tau_2 = -1 N m (1 N m against phi_2) steps on at 1 s", (0.3, 0.0), (0.0, 0.0), 2.0,
          {"springs", "dampers", "external"}, inputs={tau_2: Step(1.0, -1.0)}),
]
