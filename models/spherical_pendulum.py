"""Spherical pendulum with an external force, Example 5.3 (Figure 5.5); (5.75)-(5.81).

A point mass ``m`` on a massless rigid rod of length ``l`` swings freely about the origin ``0`` of the
inertial frame ``(0_0 x_0 y_0 z_0)``. The generalized coordinates are the angles ``q = [theta, phi]``: by (5.75)
the mass is at ``p = [l sin(theta) cos(phi), -l cos(theta), l sin(theta) sin(phi)]``, so ``theta`` is the
angle of the rod from the downward vertical ``-e_y`` and ``phi`` the azimuth about the ``y`` axis, measured
from ``x_0`` towards ``z_0``. Gravity acts in ``e_g = [0, -1, 0]``: (5.77) ``V = m g l (1 - cos(theta))`` is
``m g p_y`` up to the constant ``m g l`` (zero level at ``theta = 0``). The external force
``f^e = [-f_x^e, 0, 0]`` (input ``f_xe``) acts at the mass, always in the direction of ``-e_x`` (world
components), (5.78).

Tree: ``p = R_y(-phi) R_z(theta) [0, -l, 0]``; joint ``phi`` is a revolute joint about ``-y_0`` (axis
``[0, -1, 0]``, so that the tree coordinate is ``phi`` itself), joint ``theta`` a revolute joint about the
``z`` axis of the massless intermediate frame ``gimbal``; the point mass sits at ``[0, -l, 0]`` of frame
``bob``. The map ``theta = phi(q)`` is the identity.

Coordinate singularity: at ``theta = 0`` (hanging straight down) and ``theta = pi`` (straight up) the azimuth
``phi`` does not move the mass, ``M = m l^2 diag(1, sin^2(theta))`` is singular and (5.81d) divides by
``sin^2(theta)``. The conformance checks draw ``theta`` in ``[0.2, pi - 0.2]``, a margin of 0.2 rad
(11.5 degrees) from both poles (``sin^2(theta) >= 0.039``).
"""

import math

from sympy import Matrix, cos, sin

from harness.modeling import (WORLD, Claim, Coordinate, Gravity, Input, Joint, Link, Parameter, Point, PointForce,
                              Scene, Step, System, standard_gravity)

m = Parameter("m", 1.0, "kg", "point mass")
l = Parameter("l", 1.0, "m", "length of the massless rigid rod")
g = standard_gravity()

f_xe = Input("f_xe", "N", "magnitude f_x^e of the external force f^e = [-f_x^e, 0, 0]")

POLE_MARGIN = 0.2  # rad, distance of the drawn theta from the poles theta = 0 and theta = pi

theta = Coordinate("theta", "rad", "angle of the rod from the downward vertical -y_0",
                   range=(POLE_MARGIN, math.pi - POLE_MARGIN))
phi = Coordinate("phi", "rad", "azimuth of the rod about y_0, from x_0 towards z_0")

SYSTEM = System(
    name="spherical_pendulum",
    title="Spherical pendulum with external force",
    lecture="Example 5.3; (5.75)-(5.81)",
    coordinates=(theta, phi),
    links=(
        Link("gimbal", description="massless frame turned by phi about -y_0"),
        Link("bob", mass=m, com=(0, -l, 0), description="point mass m at the rod's end"),
    ),
    joints=(
        Joint("phi", "revolute", WORLD, "gimbal", axis=(0, -1, 0)),
        Joint("theta", "revolute", "gimbal", "bob", axis="z"),
    ),
    gravity=Gravity(g, (0, -1, 0)),
    forces=(PointForce("f_e", Point("bob", (0, -l, 0), "P"), (-f_xe, 0, 0)),),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
V_printed = m * g * l * (1 - cos(theta))
CLAIMS = [
    Claim("(5.75)", "position:bob", Matrix([l * sin(theta) * cos(phi), -l * cos(theta), l * sin(theta) * sin(phi)]),
          "position of the point mass"),
    Claim("(5.76)", "T", m * l**2 * (theta.rate**2 + phi.rate**2 * sin(theta)**2) / 2, "kinetic energy"),
    Claim("(5.77)", "g", Matrix([V_printed]).jacobian([theta, phi]).T,
          "potential forces g = dV/dq (5.96) of V = m g l (1 - cos(theta))",
          note="V is fixed only up to a constant ((5.77) sets V = 0 at theta = 0, the model's V = m g p_y differs "
               "by m g l); the printed V is compared through its gradient g = dV/dq"),
    Claim("(5.78)", "f_np", Matrix([-f_xe * l * cos(theta) * cos(phi), f_xe * l * sin(theta) * sin(phi)]),
          "generalized forces f_theta, f_phi of f^e = [-f_x^e, 0, 0]"),
    Claim("(5.80a)", "eom", m * l**2 * theta.accel - m * l**2 * phi.rate**2 * cos(theta) * sin(theta)
          + m * g * l * sin(theta) - (-f_xe * l * cos(theta) * cos(phi)), "theta equation", index=(0,)),
    Claim("(5.80b)", "eom", m * l**2 * (phi.accel * sin(theta)**2 + 2 * phi.rate * theta.rate * cos(theta) * sin(theta))
          - f_xe * l * sin(theta) * sin(phi), "phi equation", index=(1,)),
    Claim("(5.81b)", "eom", theta.accel - (-f_xe * l * cos(theta) * cos(phi)
                                           + m * l**2 * phi.rate**2 * cos(theta) * sin(theta)
                                           - m * g * l * sin(theta)) / (m * l**2),
          "state space: x2' with x = [theta, omega_theta, phi, omega_phi], u = f_x^e", index=(0,),
          note="x_1 = theta, x_2 = theta_dot, x_3 = phi, x_4 = phi_dot, u = f_xe; (5.81a), (5.81c) are x_1' = x_2, "
               "x_3' = x_4"),
    Claim("(5.81d)", "eom", phi.accel - (f_xe * l * sin(theta) * sin(phi)
                                         - 2 * m * l**2 * phi.rate * theta.rate * cos(theta) * sin(theta))
          / (m * l**2 * sin(theta)**2),
          "state space: x4'", index=(1,), note="x_2 = theta_dot, x_4 = phi_dot, u = f_xe"),
]

SCENES = [
    Scene("conical", "Example 5.3, (5.81): released at theta = 0.8 rad with the azimuth rate phi_dot = 3 rad/s, "
          "gravity only; the swirl keeps theta within [0.63, 0.8] rad, away from the pole (conservative)",
          (0.8, 0.0), (0.0, 3.0), 3.0, {"gravity"}),
    Scene("pushed", "Example 5.3, (5.78): the conical swing with the external force f^e = [-f_x^e, 0, 0] "
          "switched on at 1 s, f_x^e = 1.5 N", (0.8, 0.0), (0.0, 3.0), 3.0, {"gravity", "external"},
          inputs={f_xe: Step(1.0, 1.5)}),
]
