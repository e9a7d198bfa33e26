"""Pendulum rod, Example 3.15 (Figure 3.36).

A frictionlessly mounted, homogeneous cuboid rod (density rho_S, length l_S, width b_S, height h_S) rotates about
the e_z axis through its end A. The angle phi is measured from the downward vertical; the centre of mass is at
r_S = [l_S/2 sin(phi), -l_S/2 cos(phi), 0] (3.130), so gravity acts along -e_y. Mass m_S = rho_S l_S b_S h_S;
the inertia about the centre of mass is I_zz^(S) = rho_S (l_S^3 b_S h_S + b_S^3 l_S h_S)/12 (3.132); Steiner's
theorem gives I_zz^(A) = I_zz^(S) + m_S l_S^2/4 (3.135), and T = I_zz^(A) phi_dot^2 / 2 (3.129), (3.134).
"""

from sympy import Matrix, cos, sin

from harness.derivation.bodies import Box, centre_of_mass, moment_of_inertia
from harness.modeling import (Claim, Coordinate, Gravity, Inertia, Joint, Link, Parameter, Scene, System,
                              standard_gravity)

rho_S = Parameter("rho_S", 7850.0, "kg/m^3", "density of the rod (steel)")
l_S = Parameter("l_S", 0.5, "m", "length of the rod")
b_S = Parameter("b_S", 0.04, "m", "width of the rod")
h_S = Parameter("h_S", 0.01, "m", "height of the rod")
g = standard_gravity()

phi = Coordinate("phi", "rad", "angle of the rod from the downward vertical")
m_S = rho_S * l_S * b_S * h_S

SYSTEM = System(
    name="pendulum_rod",
    title="Pendulum rod",
    lecture="Example 3.15; (3.128)-(3.135)",
    coordinates=(phi,),
    links=(Link("rod", mass=m_S, com=(0, -l_S / 2, 0), inertia=Inertia.cuboid(m_S, b_S, l_S, h_S),
                description="homogeneous cuboid, length l_S along -y of its frame in A"),),
    joints=(Joint("phi", "revolute", "world", "rod", axis="z"),),
    gravity=Gravity(g, (0, -1, 0)),
    doc=__doc__,
)

I_A = rho_S * (l_S**3 * b_S * h_S / 3 + b_S**3 * l_S * h_S / 12)      # (3.128)
I_S = rho_S * (l_S**3 * b_S * h_S / 12 + b_S**3 * l_S * h_S / 12)     # (3.132)
# the velocity of the model's centre of mass; the derivation's expressions hold the system's own symbols, SYSTEM.q
_v_S = centre_of_mass(SYSTEM, "rod").diff(SYSTEM.q[0]) * SYSTEM.qd[0]
CLAIMS = [
    Claim("(3.128)", "parameter", I_A, "moment of inertia I_S,zz^(A) of the rod about the axis of rotation",
          reference=lambda: moment_of_inertia(Box((-b_S / 2, b_S / 2), (-l_S, 0), (-h_S / 2, h_S / 2)), rho_S),
          note="reference: the volume integral over the rod in the frame at A, as (3.128) writes it, independent of "
               "the formula the model builds the rod's inertia from"),
    Claim("(3.129)", "T", I_A * phi.rate**2 / 2, "kinetic energy, first variant: T = I_S,zz^(A) phi_dot^2 / 2",
          note="I_S,zz^(A) as printed in (3.128)"),
    Claim("(3.130)", "position:rod", Matrix([l_S / 2 * sin(phi), -l_S / 2 * cos(phi), 0]),
          "centre of mass r_S of the rod"),
    Claim("(3.131)", "parameter", m_S * l_S**2 / 4 * phi.rate**2 / 2,
          "translational kinetic energy T_t = m_S/2 r_S_dot^T r_S_dot", reference=(m_S * (_v_S.T * _v_S)[0] / 2),
          note="its last form; reference: m_S/2 |v_S|² with the velocity of the model's centre of mass"),
    Claim("(3.132)", "parameter", I_S, "moment of inertia I_S,zz^(S) of the rod about the parallel axis through S",
          reference=lambda: moment_of_inertia(Box.around((0, 0, 0), (b_S, l_S, h_S)), rho_S),
          note="reference: the volume integral over the rod about its centre of mass, as (3.132) writes it"),
    Claim("(3.131), (3.133)", "T", m_S * l_S**2 / 4 * phi.rate**2 / 2 + I_S * phi.rate**2 / 2,
          "second variant: T = T_t + T_r, T_r = I_S,zz^(S) phi_dot^2 / 2",
          note="T_t as printed in (3.131), I_S,zz^(S) as printed in (3.132)"),
    Claim("(3.134) middle", "T", rho_S * b_S * h_S * l_S**3 * phi.rate**2 / 8
          + rho_S * (l_S**3 * b_S * h_S / 12 + b_S**3 * l_S * h_S / 12) * phi.rate**2 / 2, "T = T_t + T_r written out"),
    Claim("(3.134)", "T", (rho_S * b_S * h_S * l_S**3 / 3 + rho_S * b_S**3 * l_S * h_S / 12) * phi.rate**2 / 2,
          "kinetic energy T = I_zz^(A) phi_dot^2 / 2"),
    Claim("(3.135)", "parameter", I_S + m_S * l_S**2 / 4, "Steiner: I_zz^(A) = I_zz^(S) + m_S l_S^2 / 4",
          reference=I_A),
]

SCENES = [
    Scene("swing", "Example 3.15: released at 45 deg from rest, gravity only (conservative)", (0.7854,), (0.0,),
          2.0, {"gravity"}),
]
