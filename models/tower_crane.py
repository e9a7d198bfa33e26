"""Tower crane with 5 degrees of freedom, Exercises 4.2, 4.4, Example 5.2 and Exercise 5.4 (Figure 4.10);
(4.41), (4.71)-(4.74), (5.31)-(5.42).

Frames and joints (Exercise 4.2, extending Example 4.2 (4.36)-(4.39)): the tower with its jib turns by ``phi_1``
about ``z_0`` (frame 1, ``R_0^1 = R_z(phi_1)``, ``d_0^1 = 0``); the trolley moves along ``x_1`` by ``s_2`` at the
height ``h_1`` (frame 2, ``d_1^2 = [s_2, 0, h_1]``, ``R_1^2 = E``); the rope turns by ``phi_3`` about ``y_2``
(frame 3, ``R_2^3 = R_y(phi_3)``) and by ``phi_4`` about ``x_3`` (frame 4, ``R_3^4 = R_x(phi_4)``); the load hangs
at the rope length ``s_5`` along ``-z_4`` (frame 5). This gives (4.41),
``p_0^L = [s_2 c_1 + s_5(-s_1 s_4 - c_1 s_3 c_4), s_2 s_1 + s_5(c_1 s_4 - s_1 s_3 c_4), h_1 - s_5 c_3 c_4]``.
The tree joints are exactly these five elementary joints (``s_5`` prismatic along ``[0, 0, -1]``): the map
``theta = phi(q)`` is the identity, ``q = [phi_1, s_2, phi_3, phi_4, s_5]``. Frames 3 and 4 are massless.

Bodies (Example 5.2): the tower is a solid cylinder (radius ``r_1``, height ``h_1``, density ``rho_1``,
``m_Z = r_1^2 pi h_1 rho_1``, centre of mass ``p_1^{sZ} = [0, 0, h_1/2]``) with a firmly attached cuboid jib
(``l_1x, l_1y, l_1z``, ``rho_1``, ``m_Q = l_1x l_1y l_1z rho_1``, ``p_1^{sQ} = [l_1x/2, 0, l_1z]`` as printed in
(5.31)); inertia tensors (5.32) from the formula collection. As the model has one rigid body per link, the
tower is their union: mass ``m_Z + m_Q``, the common centre of mass ``p_1^{sT}`` and the inertia tensor about
it by Steiner's theorem (the lecture's first approach). Only its ``z`` moment about the axis enters, which is
``l_1x^2/4 m_Q + I_zz,1^{sZ} + I_zz,1^{sQ}`` as in (5.37); the height of the jib does not enter at all. (5.31)
puts the jib's centre at the height ``l_1z``, at the foot of the tower, while the trolley runs at ``h_1`` (Figure
4.10 shows the jib at the top); the picture shows the two solids (``Link.solids``) where (5.31) puts them. The
trolley (mass ``m_K``) has its centre of mass at the origin of frame 2 and a diagonal inertia tensor
``diag(I_xx2, I_yy2, I_zz2)`` (printed as ``diag(I_xx,2, I_xx,2, I_xx,2)``, used with ``I_zz,2`` in (5.39)). The
load is a point mass ``m_L`` at the origin of frame 5 (``p_5^L = 0``). Gravity acts in ``e_g = [0, 0, -1]``
(5.42).

Drives and friction (Exercise 5.4): motor torque ``tau_1`` on the tower, force ``f_LK`` on the trolley, force
``f_S`` on the rope (in the direction of increasing ``s_5``); viscous friction ``d_T`` (tower), ``d_LK``
(trolley), ``d_St`` (rope length ``s_5``), ``d_Sr`` (rope angles ``phi_3`` and ``phi_4``), each a joint damper
``-d q_dot_j``. Exercise 5.4 prints no equations.

Coordinate singularities: at ``s_5 = 0`` the rope angles do not move the load, and at ``cos(phi_4) = 0`` (rope
along ``y_2``) ``phi_3`` does not; there ``M`` is singular (``M_33 = m_L s_5^2 cos^2(phi_4)``). The conformance
checks draw ``s_5`` in ``[0.3, 3] m`` (at least 0.3 m of rope) and ``phi_4`` in ``[-1.2, 1.2]`` rad, a margin of
0.37 rad (21 degrees) from ``|phi_4| = pi/2``.
"""

from sympy import Matrix, cos, diag, pi, sin, zeros

from harness.derivation.bodies import moment_of_inertia
from harness.derivation.kinematics import link_poses
from harness.modeling import (Printed, WORLD, Box, Claim, Constant, Coordinate, Cylinder, Gravity, Inertia, Input,
                              Joint, JointDamper, JointInput, Link, Parameter, Scene, Step, System, standard_gravity,
                              steiner)

h_1 = Parameter("h_1", 3.0, "m", "height of the tower (cylinder); height of the trolley's rail")
r_1 = Parameter("r_1", 0.1, "m", "radius of the tower (solid cylinder)")
rho_1 = Parameter("rho_1", 2700.0, "kg/m^3", "density of tower and jib")
l_1x = Parameter("l_1x", 3.0, "m", "length of the jib (cuboid) along x_1")
l_1y = Parameter("l_1y", 0.1, "m", "width of the jib along y_1")
l_1z = Parameter("l_1z", 0.15, "m", "height of the jib along z_1")
m_K = Parameter("m_K", 10.0, "kg", "mass of the trolley")
I_xx2 = Parameter("I_xx2", 0.05, "kg m^2", "inertia of the trolley about x_2 through its centre of mass")
I_yy2 = Parameter("I_yy2", 0.08, "kg m^2", "inertia of the trolley about y_2 through its centre of mass")
I_zz2 = Parameter("I_zz2", 0.1, "kg m^2", "inertia of the trolley about z_2 through its centre of mass")
m_L = Parameter("m_L", 20.0, "kg", "mass of the (point-shaped) load")
d_T = Parameter("d_T", 50.0, "N m s/rad", "viscous friction of the tower (phi_1)")
d_LK = Parameter("d_LK", 20.0, "N s/m", "viscous friction of the trolley (s_2)")
d_St = Parameter("d_St", 10.0, "N s/m", "viscous friction of the translational motion of the rope (s_5)")
d_Sr = Parameter("d_Sr", 2.0, "N m s/rad", "viscous friction of the rotational motion of the rope (phi_3, phi_4)")
g = standard_gravity()

phi_1 = Coordinate("phi_1", "rad", "rotation of the tower about z_0")
s_2 = Coordinate("s_2", "m", "position of the trolley along x_1")
phi_3 = Coordinate("phi_3", "rad", "rotation of the rope about y_2")
phi_4 = Coordinate("phi_4", "rad", "rotation of the rope about x_3", range=(-1.2, 1.2))
s_5 = Coordinate("s_5", "m", "length of the rope", range=(0.3, 3.0))

tau_1 = Input("tau_1", "N m", "motor torque on the tower")
f_LK = Input("f_LK", "N", "motor force on the trolley")
f_S = Input("f_S", "N", "motor force on the rope, in the direction of increasing s_5")

# ---- the tower: cylinder Z and jib Q (5.31), (5.32), joined into one rigid body by Steiner's theorem
m_Z = r_1**2 * pi * h_1 * rho_1
m_Q = l_1x * l_1y * l_1z * rho_1
p_sZ = Matrix([0, 0, h_1 / 2])
p_sQ = Matrix([l_1x / 2, 0, l_1z])
I_sZ = Inertia.cylinder(m_Z, r_1, h_1).matrix
I_sQ = Inertia.cuboid(m_Q, l_1x, l_1y, l_1z).matrix
m_T = m_Z + m_Q
p_sT = (m_Z * p_sZ + m_Q * p_sQ) / m_T


I_sT = I_sZ + steiner(m_Z, p_sZ - p_sT) + I_sQ + steiner(m_Q, p_sQ - p_sT)  # (3.133)

SYSTEM = System(
    name="tower_crane",
    title="Tower crane (5 degrees of freedom)",
    lecture="Exercises 4.2, 4.4, Example 5.2, Exercise 5.4; (4.41), (4.71)-(4.74), (5.31)-(5.42)",
    coordinates=(phi_1, s_2, phi_3, phi_4, s_5),
    links=(
        Link("tower", m_T, tuple(p_sT), Inertia(I_sT[0, 0], I_sT[1, 1], I_sT[2, 2], I_sT[0, 1], I_sT[0, 2], I_sT[1, 2]),
             description="tower (solid cylinder) with jib (cuboid), one rigid body",
             solids=((Cylinder(r_1, h_1), rho_1), (Box.around(p_sQ, (l_1x, l_1y, l_1z)), rho_1))),
        Link("trolley", m_K, (0, 0, 0), Inertia(I_xx2, I_yy2, I_zz2)),
        Link("rope_3", description="massless frame 3, turned by phi_3 about y_2"),
        Link("rope_4", description="massless frame 4, turned by phi_4 about x_3"),
        Link("load", m_L, (0, 0, 0), description="point mass m_L at the end of the rope"),
    ),
    joints=(
        Joint("phi_1", "revolute", WORLD, "tower", axis="z"),
        Joint("s_2", "prismatic", "tower", "trolley", axis="x", origin=(0, 0, h_1)),
        Joint("phi_3", "revolute", "trolley", "rope_3", axis="y"),
        Joint("phi_4", "revolute", "rope_3", "rope_4", axis="x"),
        Joint("s_5", "prismatic", "rope_4", "load", axis=(0, 0, -1)),
    ),
    gravity=Gravity(g, (0, 0, -1)),
    forces=(
        JointInput("motor_T", "phi_1", tau_1),
        JointInput("motor_LK", "s_2", f_LK),
        JointInput("motor_S", "s_5", f_S),
        JointDamper("friction_T", "phi_1", d_T),
        JointDamper("friction_LK", "s_2", d_LK),
        JointDamper("friction_Sr3", "phi_3", d_Sr),
        JointDamper("friction_Sr4", "phi_4", d_Sr),
        JointDamper("friction_St", "s_5", d_St),
    ),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
q = [phi_1, s_2, phi_3, phi_4, s_5]
w = Matrix(SYSTEM.qd)
c1, s1, c3, s3, c4, s4 = cos(phi_1), sin(phi_1), cos(phi_3), sin(phi_3), cos(phi_4), sin(phi_4)

# Manipulator Jacobians of the model's kinematics (4.68): J_v = d p_0 / dq, J_omega = [R_0^{j-1} a_j ...] dphi/dq
_poses = link_poses(SYSTEM)
_to_q = dict(zip(SYSTEM.theta, SYSTEM.phi))


def _J_v(link, point):
    pose = _poses[link]
    return (pose.R * Matrix(point) + pose.d).xreplace(_to_q).jacobian(SYSTEM.q)


def _J_omega(link):
    return _poses[link].J_omega_theta.xreplace(_to_q) * SYSTEM.phi.jacobian(SYSTEM.q)


l_xsT = p_sT[0]  # x_1 coordinate of the tower's centre of mass, [l_xsT, 0, l_zsT] of Exercise 4.4
Jv_sL = Matrix([  # (4.73), as printed
    [(s3 * c4 * s_5 - s_2) * s1 - c1 * s4 * s_5, c1, -c1 * c3 * c4 * s_5, (c1 * s3 * s4 - s1 * c4) * s_5,
     -s1 * s4 - c1 * s3 * c4],
    [(-s3 * c4 * s_5 + s_2) * c1 - s1 * s4 * s_5, s1, -s1 * c3 * c4 * s_5, (s1 * s3 * s4 + c1 * c4) * s_5,
     c1 * s4 - s1 * s3 * c4],
    [0, 0, s3 * c4 * s_5, c3 * s4 * s_5, -c3 * c4]])
I_zzZ = r_1**2 * m_Z / 2                                  # (5.32)
I_zzQ = (l_1x**2 + l_1y**2) * m_Q / 12                    # (5.32)
M_sT = zeros(5, 5)
M_sT[0, 0] = l_1x**2 / 4 * m_Q + I_zzZ + I_zzQ            # (5.37)
M_sK = diag(s_2**2 * m_K + I_zz2, m_K, 0, 0, 0)           # (5.39)
M_sL = Jv_sL.T * Jv_sL * m_L                              # (5.41) with (4.73)
T_sT = I_zzZ * w[0]**2 / 2 + m_Q * (l_1x / 2)**2 * w[0]**2 / 2 + I_zzQ * w[0]**2 / 2  # (5.34), (5.35a), (5.35b)
T_sK = m_K * w[1]**2 / 2 + (m_K * s_2**2 + I_zz2) * w[0]**2 / 2                    # (5.40)
T_sL = (w.T * M_sL * w)[0] / 2                                                     # after (5.41)
V_sL = m_L * g * (h_1 - s_5 * cos(phi_3) * cos(phi_4))                             # (5.42)
_tower_com_note = ("l_xsT is the x_1 coordinate of the tower's common centre of mass p_1^{sT} (Example 5.2: "
                   "cylinder and jib); ")
phi_2p = Printed("phi_2", "rad", "printed in c_phi2 = cos(phi_2), row 2, column 1 of (4.71), (4.72)")
c2p = cos(phi_2p)
_c_phi2_note = "c_phi2 in row 2, column 1 as printed"
CLAIMS = [
    Claim("(3.122)", "parameter", rho_1 * r_1**4 * pi * h_1 / 2,
          "I_zz of a homogeneous cylinder about its axis: the tower (Example 3.13's cylinder)",
          reference=lambda: moment_of_inertia(Cylinder(r_1, h_1), rho_1),
          note="Example 3.13's R, l, rho are the tower's r_1, h_1, rho_1; (3.122) prints rho R^4 pi l/2 = m R^2/2, the "
               "first form is claimed; reference: the volume integral over the tower's cylinder, independent of the "
               "formula the model builds I^sZ from"),
    Claim("(4.41)", "position:load", Matrix([
        s_2 * c1 + s_5 * (-s1 * s4 - c1 * s3 * c4),
        s_2 * s1 + s_5 * (c1 * s4 - s1 * s3 * c4),
        h_1 - s_5 * c3 * c4]), "position of the load p_0^L"),
    Claim("(4.71) J_v", "parameter", Matrix([[-s1 * l_xsT, 0, 0, 0, 0], [c2p * l_xsT, 0, 0, 0, 0], [0] * 5]),
          "translational manipulator Jacobian (J_v)_0^{sT} of the tower's centre of mass",
          reference=_J_v("tower", p_sT), note=_tower_com_note + _c_phi2_note),
    Claim("(4.71) J_omega", "parameter", Matrix([[0] * 5, [0] * 5, [1, 0, 0, 0, 0]]),
          "rotational manipulator Jacobian (J_omega)_0^{sT} of the tower", reference=_J_omega("tower")),
    Claim("(4.72) J_v", "parameter", Matrix([[-s1 * s_2, c1, 0, 0, 0], [c2p * s_2, s1, 0, 0, 0], [0] * 5]),
          "translational manipulator Jacobian (J_v)_0^{sK} of the trolley",
          reference=_J_v("trolley", (0, 0, 0)), note=_c_phi2_note),
    Claim("(4.72) J_omega", "parameter", Matrix([[0] * 5, [0] * 5, [1, 0, 0, 0, 0]]),
          "rotational manipulator Jacobian (J_omega)_0^{sK} of the trolley", reference=_J_omega("trolley")),
    Claim("(4.73)", "parameter", Jv_sL, "translational manipulator Jacobian (J_v)_0^{sL} of the load",
          reference=_J_v("load", (0, 0, 0))),
    Claim("(4.74)", "parameter", Matrix([[0, 0, -s1, c1 * c3, 0], [0, 0, c1, s1 * c3, 0], [1, 0, 0, -s3, 0]]),
          "rotational manipulator Jacobian (J_omega)_0^{sL} of the load (frame 5)", reference=_J_omega("load")),
    Claim("(5.32) I^sQ", "parameter", diag((l_1y**2 + l_1z**2) * m_Q / 12, (l_1x**2 + l_1z**2) * m_Q / 12, I_zzQ),
          "inertia tensor of the jib (cuboid) about its centre of mass", reference=I_sQ,
          note="reference: Inertia.cuboid (3.128)"),
    Claim("(5.37)+(5.39)+(5.41)", "M", M_sT + M_sK + M_sL,
          "mass matrix M = M^sT + M^sK + M^sL, with (J_v)_0^{sL} of (4.73) in (5.41)",
          note="(5.41) prints M^sL = (J_v^sL)^T J_v^sL m_L without expanding it; evaluated with the printed (4.73)"),
    Claim("(5.34)+(5.35)+(5.40)+T^sL", "T", T_sT + T_sK + T_sL,
          "kinetic energy T^sZ + T^sQ + T^sK + T^sL", note="T^sL = 1/2 q_dot^T M^sL q_dot after (5.41), with (4.73)"),
    Claim("(5.42)", "g", Matrix([V_sL]).jacobian(q).T,
          "potential forces g = dV/dq (5.96) of V = V^sL = m_L g (h_1 - s_5 cos(phi_3) cos(phi_4))",
          note="the lecture sets the constant V^sT = V^sK = 0 (the model's V differs by the constant potential of "
               "tower and trolley); the printed V is compared through its gradient g = dV/dq"),
]

SCENES = [
    Scene("slew", "Exercise 5.4, Example 5.2: the tower slews by 60 degrees under tau_1 = 150 N m (reversed to "
          "-150 N m at 2 s), the trolley is driven out along the 3 m jib from 1 m to 2.4 m by f_LK = 15 N (reversed "
          "at 2 s), the rope is paid out from 1 m to 2 m (f_S = -193 N holds back most of the load's weight "
          "196 N); the load swings; viscous friction in every joint",
          (0.0, 1.0, 0.0, 0.0, 1.0), (0.0, 0.0, 0.0, 0.0, 0.0), 4.0, {"gravity", "dampers", "inputs"},
          inputs={tau_1: Step(2.0, -150.0, before=150.0), f_LK: Step(2.0, -15.0, before=15.0), f_S: Constant(-193.0)}),
    Scene("swing", "Example 5.2, (5.42): the load released from rest with the rope at phi_3 = 0.3, phi_4 = 0.2 "
          "rad, held by the constant rope force f_S = -m_L g (the rope first shortens, then pays out to 2.7 m "
          "as the swinging load pulls harder); tower and trolley free (they recoil), no friction",
          (0.0, 1.5, 0.3, 0.2, 1.5), (0.0, 0.0, 0.0, 0.0, 0.0), 3.0, {"gravity", "inputs"},
          inputs={f_S: Constant(-20.0 * 9.81)}),
]
