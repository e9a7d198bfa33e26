"""Cart with pendulum, Exercise 5.2 (Figure 5.7), solution (5.92).

A cart of mass ``m_W`` moves along ``e_x`` (position ``s``), held by a linear spring (``c_W``, relaxed
length ``s_W0``) to the inertial frame: the spring's potential is ``c_W/2 (s - s_W0)²``, modeled as a spring
on the cart's prismatic joint. Viscous friction ``f_R = -d_R ṡ`` and the driving force ``f^e`` act on the
cart. A homogeneous cuboid rod (density ``rho_S``, length ``l_S``, width ``b_S``, height ``h_S``) hangs from a
frictionless pivot on the cart; ``phi`` is measured from the downward vertical, gravity acts in ``-e_y``.
Its mass is ``m_S = rho_S l_S b_S h_S`` and its inertia about the centre of mass ``I_zz^S = m_S (l_S² + b_S²)/12``
(3.128); the centre of mass lies at ``l_S/2`` from the pivot.
"""

from sympy import cos, sin

from harness.derivation.bodies import Box, moment_of_inertia

from harness.modeling import (Printed, WORLD, Claim, Coordinate, Gravity, Inertia, Input, Joint, JointDamper, JointInput,
                              JointSpring, Link, Parameter, Scene, Sine, System, standard_gravity)

m_W = Parameter("m_W", 5.0, "kg", "mass of the cart")
c_W = Parameter("c_W", 100.0, "N/m", "spring constant of the cart's spring")
s_W0 = Parameter("s_W0", 0.2, "m", "relaxed length of the cart's spring", assumption="real")
d_R = Parameter("d_R", 2.0, "N s/m", "viscous friction coefficient of the cart")
rho_S = Parameter("rho_S", 2700.0, "kg/m^3", "density of the pendulum rod")
l_S = Parameter("l_S", 0.6, "m", "length of the pendulum rod")
b_S = Parameter("b_S", 0.04, "m", "width of the pendulum rod (in the plane of motion)")
h_S = Parameter("h_S", 0.02, "m", "height of the pendulum rod (normal to the plane)")
g = standard_gravity()

s = Coordinate("s", "m", "position of the cart")
phi = Coordinate("phi", "rad", "angle of the rod from the downward vertical")
f_e = Input("f_e", "N", "driving force on the cart")

m_S = rho_S * l_S * b_S * h_S

SYSTEM = System(
    name="cart_pendulum",
    title="Cart with pendulum",
    lecture="Exercise 5.2; (5.92)",
    coordinates=(s, phi),
    links=(
        Link("cart", m_W, (0, 0, 0), Inertia.cuboid(m_W, 0.4, 0.2, 0.2),
             description="the cart; its rotational inertia never enters (it only translates)"),
        Link("rod", m_S, (0, -l_S / 2, 0), Inertia.cuboid(m_S, b_S, l_S, h_S),
             description="homogeneous cuboid rod, long axis along -y of its frame"),
    ),
    joints=(
        Joint("s", "prismatic", WORLD, "cart", axis="x"),
        Joint("phi", "revolute", "cart", "rod", axis="z"),
    ),
    gravity=Gravity(g, (0, -1, 0)),
    forces=(
        JointSpring("spring_W", "s", c_W, s_W0),
        JointDamper("friction_R", "s", d_R),
        JointInput("drive", "s", f_e),
    ),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
# the solution names the mass m_S and the inertia I_zz^S and prints their values; (5.92) is written in them
m_S_p = Printed("m_S", "kg", "mass of the pendulum rod, as the solution prints it")
I_zz_S_p = Printed("I_zz^S", "kg m^2", "moment of inertia of the rod about its centre of gravity S")
_rod = Box.around((0, -l_S / 2, 0), (b_S, l_S, h_S))   # the rod as the link declares it: frame in A, S at -l_S/2
I_Szz_S_p = Printed("I_Szz^S", "kg m^2", "moment of inertia of the rod about the e_z axis through S, as (3.132) prints it")
CLAIMS = [
    Claim("(3.128)", "parameter", rho_S * (l_S**3 * b_S * h_S / 3 + b_S**3 * l_S * h_S / 12),
          "I_S,zz^(A): the rod's moment of inertia about the axis of rotation (e_z through A)",
          reference=lambda: moment_of_inertia(_rod, rho_S),
          note="reference: the volume integral of rho_S (x² + y²) over the rod's cuboid, independent of the "
               "Inertia.cuboid formula the link uses"),
    Claim("(3.132)", "parameter", rho_S * (l_S**3 * b_S * h_S / 12 + b_S**3 * l_S * h_S / 12),
          "I_S,zz^(S): the rod's moment of inertia about the parallel axis through its centre of gravity S",
          reference=lambda: moment_of_inertia(_rod, rho_S, about=(0, -l_S / 2, 0)), defines=I_Szz_S_p,
          note="reference: the volume integral about S"),
    Claim("(3.135)", "parameter", I_Szz_S_p + m_S * l_S**2 / 4, "Steiner: I_S,zz^(A) = I_S,zz^(S) + m_S l_S²/4",
          reference=lambda: moment_of_inertia(_rod, rho_S), ingredients=("(3.132)",),
          note="with the printed I_S,zz^(S) of (3.132) and m_S = rho_S l_S b_S h_S as the text defines it beside "
               "(3.132); reference: the volume integral about A"),
    Claim("Solution of Exc. 5.2 (m_S)", "parameter", rho_S * l_S * b_S * g * h_S,
          "mass of the rod m_S = rho_S l_S b_S g h_S", reference=m_S, defines=m_S_p),
    Claim("Solution of Exc. 5.2 (I_zz^S)", "parameter", m_S_p * (l_S**2 + b_S**2) / 12,
          "I_zz^S = m_S (l_S² + b_S²)/12", reference=SYSTEM.links[1].inertia.matrix[2, 2], defines=I_zz_S_p,
          ingredients=("Solution of Exc. 5.2 (m_S)",)),
    Claim("(5.92a)", "eom", (m_W + m_S_p) * s.accel + m_S_p * l_S * cos(phi) * phi.accel / 2
          - m_S_p * l_S * sin(phi) * phi.rate**2 / 2 + c_W * (s - s_W0) - (f_e - d_R * s.rate), "cart equation",
          index=(0,), ingredients=("Solution of Exc. 5.2 (m_S)",)),
    Claim("(5.92b)", "eom", m_S_p * l_S * cos(phi) * phi.accel / 2 + (I_zz_S_p + m_S_p * l_S**2 / 4) * phi.accel
          + m_S_p * g * l_S * sin(phi) / 2, "pendulum equation", index=(1,),
          ingredients=("Solution of Exc. 5.2 (m_S)", "Solution of Exc. 5.2 (I_zz^S)")),
]

SCENES = [
    Scene("shaken", "Exercise 5.2: the cart driven by f^e = 5 sin(2π 0.8 t) N against its spring and friction",
          (0.2, 0.3), (0.0, 0.0), 4.0, {"gravity", "springs", "dampers", "inputs"}, inputs={f_e: Sine(5.0, 0.8)}),
    Scene("released", "Exercise 5.2 without friction (d_R = 0) and without drive (f^e = 0): the cart released "
          "at s = 0.3 m beside its spring's rest length with the rod at 0.5 rad; cart and rod swap energy "
          "(conservative)", (0.3, 0.5), (0.0, 0.0), 4.0, {"gravity", "springs"}, params={d_R: 0.0}),
]
