"""Mathematical pendulum, Example 3.12 (Figure 3.31).

A point mass ``m`` on a massless rigid rod of length ``l`` swings about the ``e_x`` axis; gravity acts in
``-e_z``. The angle ``phi`` is measured from the downward vertical, so that the mass is at
``y = l sin(phi)``, ``z = -l cos(phi)`` (3.109). Equation of motion (3.111): ``m l² phi'' = -m g l sin(phi)``.
"""

from sympy import Matrix, cos, sin

from harness.derivation.bodies import joint_force
from harness.modeling import Claim, Coordinate, Gravity, Joint, Link, Parameter, Printed, Scene, System, standard_gravity

m = Parameter("m", 1.0, "kg", "point mass")
l = Parameter("l", 1.0, "m", "length of the massless rod")
g = standard_gravity()
phi = Coordinate("phi", "rad", "angle from the downward vertical")

SYSTEM = System(
    name="pendulum",
    title="Mathematical pendulum",
    lecture="Example 3.12; (3.109), (3.111), (3.112)",
    coordinates=(phi,),
    links=(Link("bob", mass=m, com=(0, 0, -l), description="point mass m at the rod's end"),),
    joints=(Joint("phi", "revolute", "world", "bob", axis="x"),),
    gravity=Gravity(g, (0, 0, -1)),
    doc=__doc__,
)

y_ddot_p = Printed("y_ddot", "m/s^2", "acceleration of the mass in e_y, as (3.109a) prints it")
z_ddot_p = Printed("z_ddot", "m/s^2", "acceleration of the mass in e_z, as (3.109b) prints it")
f_S_p = Printed("f_S", "N", "cutting force in the rod, as (3.112) prints it")

CLAIMS = [
    Claim("(3.109)", "position:bob", Matrix([0, l * sin(phi), -l * cos(phi)]),
          "position of the mass: y = l sin(phi), z = -l cos(phi)"),
    Claim("(3.109a) y_dot", "v:bob", l * cos(phi) * phi.rate, "y_dot = l cos(phi) phi_dot", index=(1,)),
    Claim("(3.109a) y_ddot", "a:bob", -l * sin(phi) * phi.rate**2 + l * cos(phi) * phi.accel,
          "y_ddot = -l sin(phi) phi_dot² + l cos(phi) phi_ddot", index=(1,), defines=y_ddot_p),
    Claim("(3.109b) z_dot", "v:bob", l * sin(phi) * phi.rate, "z_dot = l sin(phi) phi_dot", index=(2,)),
    Claim("(3.109b) z_ddot", "a:bob", l * cos(phi) * phi.rate**2 + l * sin(phi) * phi.accel,
          "z_ddot = l cos(phi) phi_dot² + l sin(phi) phi_ddot", index=(2,), defines=z_ddot_p),
    Claim("(3.112)", "parameter", m * g * cos(phi) + m * l * phi.rate**2, "the cutting force f_S in the rod",
          reference=lambda: (joint_force(SYSTEM, "phi").T * Matrix([0, -sin(phi), cos(phi)]))[0], defines=f_S_p,
          note="reference: the force the joint exerts on the mass (its momentum balance cut free, "
               "harness.derivation.bodies.joint_force), along the rod towards the pivot, the direction in which "
               "(3.108) lets f_S act on the mass (-f_S sin(phi), f_S cos(phi))"),
    Claim("(3.108a)", "eom", m * y_ddot_p - (-f_S_p * sin(phi)), "momentum balance in e_y of the cut-free mass",
          ingredients=("(3.109a) y_ddot", "(3.112)")),
    Claim("(3.108b)", "eom", m * z_ddot_p - (-m * g + f_S_p * cos(phi)), "momentum balance in e_z of the cut-free mass",
          ingredients=("(3.109b) z_ddot", "(3.112)")),
    Claim("(3.110a)", "eom", m * (-l * sin(phi) * phi.rate**2 + l * cos(phi) * phi.accel) - (-f_S_p * sin(phi)),
          "(3.108a) with (3.109a)", ingredients=("(3.112)",)),
    Claim("(3.110b)", "eom", m * (l * cos(phi) * phi.rate**2 + l * sin(phi) * phi.accel) - (-m * g + f_S_p * cos(phi)),
          "(3.108b) with (3.109b)", ingredients=("(3.112)",)),
    Claim("(3.111)", "eom", m * l**2 * phi.accel + m * g * l * sin(phi), "m l² phi'' = -m g l sin(phi)"),
    Claim("(3.114)", "eom", m * l**2 * phi.accel - (-m * g * l * sin(phi)),
          "d/dt l_x^(0) = m l² phi'' = tau_x^(0) = -m g l sin(phi), angular momentum about 0"),
    Claim("(3.115)", "M", m * l**2, "I_xx^(0) = m l², the mass matrix of the pendulum"),
]

SCENES = [
    Scene("swing", "Example 3.12: released at 60° from rest, gravity only (conservative)", (1.0472,), (0.0,), 4.0,
          {"gravity"}),
]
