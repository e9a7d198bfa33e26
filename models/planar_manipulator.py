"""Planar manipulator, Examples 4.1, 4.3, 5.1 and 5.5 (Figures 4.7, 5.2, 5.9).

Two links rotate about ``z``: link 1 by ``phi_1`` about the origin, link 2 by the *relative* angle
``phi_2`` about the end of link 1 (``d_1^2 = [l_1, 0, 0]``, (4.33)). Centres of mass at ``p_1^{s1} =
[l_s1, 0, 0]``, ``p_2^{s2} = [l_s2, 0, 0]``, end effector at ``p_2^{e2} = [l_2, 0, 0]`` (4.34). The links'
inertia tensors about their centres of mass are diagonal in the body frames (5.24). Gravity acts in
``e_g = [0, -1, 0]`` (5.28).

A linear spring (``c_e``, ``s_0e``) and a linear damper (``d_e``) connect the end effector with the fixed
bearing ``A`` at ``p_0^A = [l_0A, h_0A, 0]`` (5.29). Both act along the line between the two points, as a
spring/damper element does (the spring's potential uses the length ``|r_e|``, (5.30)). (5.109) prints the
damper force as ``d_e ṙ_e`` (the full relative velocity, not only its component along ``r_e``); the claims of
(5.109) and (5.110) are transcribed as printed and checked against the element. Viscous friction ``d_2`` acts in joint 2,
motor torques ``tau_1``, ``tau_2`` in joints 1 and 2 (5.111).
"""

from sympy import Matrix, cos, sin, sqrt

from harness.modeling import (WORLD, Claim, Printed, printed_matrix, Constant, Coordinate, Damper, Gravity, Inertia, Input, Joint, JointDamper,
                              JointInput, Link, Parameter, Point, Scene, Spring, Step, System, standard_gravity)

m_1 = Parameter("m_1", 2.0, "kg", "mass of link 1")
m_2 = Parameter("m_2", 1.5, "kg", "mass of link 2")
l_1 = Parameter("l_1", 1.0, "m", "length of link 1")
l_2 = Parameter("l_2", 0.8, "m", "length of link 2")
l_s1 = Parameter("l_s1", 0.5, "m", "joint 1 to centre of mass of link 1")
l_s2 = Parameter("l_s2", 0.4, "m", "joint 2 to centre of mass of link 2")
I_xx1 = Parameter("I_xx1", 0.002, "kg m^2", "inertia of link 1 about x_1 through s1")
I_yy1 = Parameter("I_yy1", 0.17, "kg m^2", "inertia of link 1 about y_1 through s1")
I_zz1 = Parameter("I_zz1", 0.168, "kg m^2", "inertia of link 1 about z_1 through s1")
I_xx2 = Parameter("I_xx2", 0.001, "kg m^2", "inertia of link 2 about x_2 through s2")
I_yy2 = Parameter("I_yy2", 0.081, "kg m^2", "inertia of link 2 about y_2 through s2")
I_zz2 = Parameter("I_zz2", 0.08, "kg m^2", "inertia of link 2 about z_2 through s2")
c_e = Parameter("c_e", 50.0, "N/m", "stiffness of the spring end effector - A")
s_0e = Parameter("s_0e", 0.5, "m", "relaxed length of the spring")
d_e = Parameter("d_e", 5.0, "N s/m", "damping coefficient of the damper end effector - A")
d_2 = Parameter("d_2", 0.3, "N m s/rad", "viscous friction in joint 2")
l_0A = Parameter("l_0A", 1.2, "m", "x position of bearing A")
h_0A = Parameter("h_0A", -0.6, "m", "y position of bearing A", assumption="real")
g = standard_gravity()

phi_1 = Coordinate("phi_1", "rad", "angle of link 1 against x_0")
phi_2 = Coordinate("phi_2", "rad", "angle of link 2 relative to link 1")
tau_1 = Input("tau_1", "N m", "motor torque in joint 1")
tau_2 = Input("tau_2", "N m", "motor torque in joint 2")

end_effector = Point("link_2", (l_2, 0, 0), "e2")
bearing_A = Point(WORLD, (l_0A, h_0A, 0), "A")

SYSTEM = System(
    name="planar_manipulator",
    title="Planar manipulator",
    lecture="Examples 4.1, 4.3, 5.1, 5.5; (4.35), (5.22)-(5.30), (5.109)-(5.112)",
    coordinates=(phi_1, phi_2),
    links=(
        Link("link_1", m_1, (l_s1, 0, 0), Inertia(I_xx1, I_yy1, I_zz1)),
        Link("link_2", m_2, (l_s2, 0, 0), Inertia(I_xx2, I_yy2, I_zz2)),
    ),
    joints=(
        Joint("phi_1", "revolute", WORLD, "link_1", axis="z"),
        Joint("phi_2", "revolute", "link_1", "link_2", axis="z", origin=(l_1, 0, 0)),
    ),
    gravity=Gravity(g, (0, -1, 0)),
    forces=(
        Spring("spring_e", bearing_A, end_effector, c_e, s_0e),
        Damper("damper_e", bearing_A, end_effector, d_e),
        JointDamper("friction_2", "phi_2", d_2),
        JointInput("motor_1", "phi_1", tau_1),
        JointInput("motor_2", "phi_2", tau_2),
    ),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
w_1, w_2 = phi_1.rate, phi_2.rate
c_2, s_2 = cos(phi_2), sin(phi_2)
l_e2 = Printed("l_e2", "m", "printed in (4.35c)")
c_2p = Printed("c_2", "N/m", "printed spring stiffness in (5.30)")
r_e = Matrix([l_0A - l_1 * cos(phi_1) - l_2 * cos(phi_1 + phi_2), h_0A - l_1 * sin(phi_1) - l_2 * sin(phi_1 + phi_2), 0])
s_e = sqrt((r_e.T * r_e)[0])                                                        # (5.29), s_e = sqrt(r_e^T r_e)
CLAIMS = [
    Claim("(4.35a)", "position:link_1", Matrix([l_s1 * cos(phi_1), l_s1 * sin(phi_1), 0]), "centre of mass of link 1"),
    Claim("(4.35b)", "position:link_2", Matrix([l_1 * cos(phi_1) + l_s2 * cos(phi_1 + phi_2),
                                                l_1 * sin(phi_1) + l_s2 * sin(phi_1 + phi_2), 0]),
          "centre of mass of link 2"),
    Claim("(4.35c)", "position:e2", Matrix([l_1 * cos(phi_1) + l_e2 * cos(phi_1 + phi_2),
                                            l_1 * sin(phi_1) + l_e2 * sin(phi_1 + phi_2), 0]),
          "end effector", note="l_e2 as printed; the example defines no l_e2"),
    Claim("(4.68)", "J_omega:link_1", Matrix([[0, 0], [0, 0], [1, 0]]), "(J_omega)_0^1"),
    Claim("(4.68)", "J_omega:link_2", Matrix([[0, 0], [0, 0], [1, 1]]), "(J_omega)_0^2"),
    Claim("(4.69)", "J_v:link_1", Matrix([[-sin(phi_1) * l_s1, 0], [cos(phi_1) * l_s1, 0], [0, 0]]), "(J_v)_0^s1"),
    Claim("(4.69)", "J_v:link_2", Matrix([
        [-sin(phi_1) * l_1 - sin(phi_1 + phi_2) * l_s2, -sin(phi_1 + phi_2) * l_s2],
        [cos(phi_1) * l_s1 + cos(phi_1 + phi_2) * l_s2, cos(phi_1 + phi_2) * l_s2],
        [0, 0]]), "(J_v)_0^s2"),
    Claim("(4.70)", "J_v:e2", Matrix([
        [-sin(phi_1) * l_1 - sin(phi_1 + phi_2) * l_2, -sin(phi_1 + phi_2) * l_2],
        [cos(phi_1) * l_s1 + cos(phi_1 + phi_2) * l_2, cos(phi_1 + phi_2) * l_2],
        [0, 0]]), "(J_v)_0^e2, the end effector"),
    Claim("(5.28a)+(5.28b)+(5.30)", "V", m_1 * g * l_s1 * sin(phi_1)
          + m_2 * g * (l_1 * sin(phi_1) + l_s2 * sin(phi_1 + phi_2)) + c_2p * (s_e - s_0e)**2 / 2,
          "potential energy V^s1 + V^s2 + V_e, s_e = |r_e| with r_e of (5.29)",
          note="c_2 as printed in (5.30); the example names the spring stiffness c_e"),
    Claim("(4.32)", "R:link_1", Matrix([[cos(phi_1), -sin(phi_1), 0], [sin(phi_1), cos(phi_1), 0], [0, 0, 1]]),
          "R_0^1"),
    Claim("(4.32)", "R:link_1/link_2", Matrix([[c_2, -s_2, 0], [s_2, c_2, 0], [0, 0, 1]]), "R_1^2"),
    Claim("(4.66)", "S:link_1", Matrix([[0, -w_1, 0], [w_1, 0, 0], [0, 0, 0]]), "S_0^1 = R_0^1' (R_0^1)^T",
          note="printed with omega_1 = phi_1_dot (as the text defines it)"),
    Claim("(4.66)", "S:link_1/link_2", Matrix([[0, -w_2, 0], [w_2, 0, 0], [0, 0, 0]]), "S_1^2 = R_1^2' (R_1^2)^T",
          note="printed with omega_2 = phi_2_dot (as the text defines it)"),
    Claim("(4.67)", "omega:link_2", Matrix([0, 0, w_1]) + Matrix([[cos(phi_1), -sin(phi_1), 0],
                                                              [sin(phi_1), cos(phi_1), 0], [0, 0, 1]]) * Matrix([0, 0, w_2]),
          "omega_0^2 = omega_0^1 + R_0^1 omega_1^2",
          note="omega_0^1 = [0 0 omega_1], omega_1^2 = [0 0 omega_2] and R_0^1 as the text gives them beside it"),
    Claim("(5.22)", "T_t:link_1", m_1 * l_s1**2 * w_1**2 / 2, "translational kinetic energy of link 1",
          note="printed with omega_1 = phi_1_dot"),
    Claim("(5.23)", "T_t:link_2", m_2 * (l_1**2 * w_1**2 + 2 * l_1 * l_s2 * w_1 * (w_1 + w_2) * c_2
                                         + l_s2**2 * (w_1 + w_2)**2) / 2, "translational kinetic energy of link 2",
          note="printed with omega_1, omega_2 = phi_1_dot, phi_2_dot"),
    Claim("(5.25)", "I_0:link_1", Matrix([
        [I_xx1 * cos(phi_1)**2 + I_yy1 * sin(phi_1)**2, (I_xx1 - I_yy1) * sin(phi_1) * cos(phi_1), 0],
        [(I_xx1 - I_yy1) * sin(phi_1) * cos(phi_1), I_xx1 * sin(phi_1)**2 + I_yy1 * cos(phi_1)**2, 0],
        [0, 0, I_zz1]]), "inertia tensor of link 1 in the inertial frame, R_0^1 I_1^s1 (R_0^1)^T",
          note="I_{xx,1}^{s1}, I_{yy,1}^{s1}, I_{zz,1}^{s1} → I_xx1, I_yy1, I_zz1"),
    Claim("(5.26a)", "T_r:link_1", I_zz1 * w_1**2 / 2, "rotational kinetic energy of link 1",
          note="I_{zz,1}^{s1} → I_zz1; omega_1 = phi_1_dot"),
    Claim("(5.26b)", "T_r:link_2", I_zz2 * (w_1 + w_2)**2 / 2, "rotational kinetic energy of link 2",
          note="I_{zz,2}^{s2} → I_zz2; omega_1, omega_2 = phi_1_dot, phi_2_dot"),
    Claim("(5.28a)", "V:link_1", m_1 * g * l_s1 * sin(phi_1), "potential energy of link 1, -m_1 g e_g^T p_0^s1"),
    Claim("(5.28b)", "V:link_2", m_2 * g * (l_1 * sin(phi_1) + l_s2 * sin(phi_1 + phi_2)),
          "potential energy of link 2, -m_2 g e_g^T p_0^s2"),
    Claim("(5.27)", "M", Matrix([
        [m_1 * l_s1**2 + m_2 * (l_1**2 + 2 * l_1 * l_s2 * c_2 + l_s2**2) + I_zz1 + I_zz2,
         m_2 * l_s2 * (l_s2 + l_1 * c_2) + I_zz2],
        [m_2 * l_s2 * (l_s2 + l_1 * c_2) + I_zz2, m_2 * l_s2**2 + I_zz2]]), "mass matrix"),
    Claim("(5.111)", "f_np:motor_1", Matrix([tau_1, 0]), "generalized force of the motor torque tau_1"),
    Claim("(5.111)", "f_np:motor_2", Matrix([0, tau_2]),
          "generalized force of the motor torque tau_2 (on rod 1 and rod 2 by the cutting principle)"),
    Claim("f_q,d2 after (5.111)", "f_np:friction_2", Matrix([0, -d_2 * w_2]),
          "generalized force of the viscous friction in joint 2", note="omega_2 = phi_2_dot"),
    Claim("(5.112)", "C", Matrix([
        [-m_2 * l_1 * l_s2 * s_2 * w_2, -m_2 * l_1 * l_s2 * s_2 * (w_1 + w_2)],
        [-m_2 * l_1 * l_s2 * s_2 * w_1, 0]]), "Coriolis matrix 'for checking'"),
    Claim("(5.109)", "force:damper_e", d_e * Matrix([
        l_2 * sin(phi_1 + phi_2) * (w_1 + w_2) + l_1 * sin(phi_1) * w_1,
        -l_2 * cos(phi_1 + phi_2) * (w_1 + w_2) - l_1 * cos(phi_1) * w_1, 0]),
          "force of the damper on the end effector, printed as d_e r_e' with r_e of (5.29)",
          defines=printed_matrix("f_de", 3, 1, "N", "the damper force (5.109), used by (5.110)")),
    Claim("(5.110)", "f_np:damper_e", d_e * Matrix([
        -l_1**2 * w_1 - l_1 * l_2 * (2 * w_1 + w_2) * c_2 - l_2**2 * (w_1 + w_2),
        -l_1 * l_2 * w_1 * c_2 - l_2**2 * (w_1 + w_2)]),
          "generalized force of the damper, ((J_v)_0^e2)^T f_de", ingredients=("(5.109)",)),
]

SCENES = [
    Scene("driven", "Example 5.5: tau_1 steps to 5 N m at 0.6 s, tau_2 = -1 N m, against the spring c_e, the "
          "damper d_e and the joint friction d_2", (0.3, -0.7), (0.0, 0.0), 3.0,
          {"gravity", "springs", "dampers", "inputs"}, inputs={tau_1: Step(0.6, 5.0), tau_2: Constant(-1.0)}),
    Scene("swing", "Examples 4.1/5.1: free swing under gravity alone (conservative)", (0.3, -0.7), (0.0, 0.0), 3.0,
          {"gravity"}),
    Scene("detached", "Example 5.5 with the end effector's spring and damper detached (c_e = d_e = 0) and a "
          "frictionless joint 2 (d_2 = 0): tau_1 steps to 5 N m at 0.6 s, tau_2 = -1 N m, under gravity",
          (0.3, -0.7), (0.0, 0.0), 3.0, {"gravity", "inputs"}, inputs={tau_1: Step(0.6, 5.0), tau_2: Constant(-1.0)},
          params={c_e: 0.0, d_e: 0.0, d_2: 0.0}),
]
