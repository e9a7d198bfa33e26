"""Sphere rolling down an inclined plane, Exercise 3.17 (Figure 3.38).

A homogeneous sphere (mass ``m``, radius ``R``, inertia ``2/5 m R²`` about its centre, (3.16)) on a plane
inclined by ``alpha``; gravity acts in ``-e_z``. The plane frame is the world frame pitched by ``alpha`` about
``e_y`` (roll-pitch-yaw ``(0, alpha, 0)``), so its ``x`` axis points down the slope. The lecture coordinate is
the rolling angle ``phi`` about the plane's ``y`` axis; rolling without slipping ties the centre's position
along the slope to it, ``x = R phi`` (a map with two tree joints, slide and hinge, for one coordinate).

Printed result: ``phi'' = 5/(7R) g sin(alpha)`` for ``mu_H >= 2/7 tan(alpha)``. The rolling condition (the
friction the contact must transmit, and slipping below the threshold) is a contact phenomenon: it is checked
with the scenes, where MuJoCo simulates the sphere on the plane with friction on both sides of the threshold.
"""

from sympy import Rational, sin, tan

from harness.derivation.bodies import Ball, moment_of_inertia, solid_volume
from harness.modeling import (WORLD, Claim, Coordinate, Gravity, Inertia, Joint, Link, Parameter, RollSlip, Scene,
                              System, standard_gravity)

m = Parameter("m", 2.0, "kg", "mass of the sphere")
R = Parameter("R", 0.1, "m", "radius of the sphere")
alpha = Parameter("alpha", 0.35, "rad", "inclination of the plane")
g = standard_gravity()
phi = Coordinate("phi", "rad", "rolling angle of the sphere (positive rolling down the slope)")

I = Rational(2, 5) * m * R**2

SYSTEM = System(
    name="rolling_sphere",
    title="Sphere rolling down an inclined plane",
    lecture="Exercise 3.17; rolling condition mu_H >= 2/7 tan(alpha)",
    status="rolling branch; slipping below mu_H = 2/7 tan(alpha) left to the scenes",
    coordinates=(phi,),
    links=(Link("carrier", 0, description="massless frame at the sphere's centre, sliding along the slope"),
           Link("sphere", m, inertia=Inertia(I, I, I))),
    joints=(Joint("x", "prismatic", WORLD, "carrier", axis="x", rpy=(0, alpha, 0), phi=R * phi),
            Joint("roll", "revolute", "carrier", "sphere", axis="y", phi=phi)),
    gravity=Gravity(g, (0, 0, -1)),
    doc=__doc__,
)

_sphere = Ball(R)
CLAIMS = [
    Claim("(3.123)", "parameter", Rational(2, 5) * m * R**2, "I: a homogeneous ball's moment of inertia about its centre",
          reference=lambda: moment_of_inertia(_sphere, m / solid_volume(_sphere)),
          note="(3.123) prints I = 8/15 pi rho R^5 = 2/5 m R^2; the second form, in the model's m, R, is claimed (the "
               "model has no density rho); reference: the volume integral over the ball"),
    Claim("Exercise 3.17", "eom", phi.accel - Rational(5, 7) / R * g * sin(alpha),
          "phi'' = 5/(7R) g sin(alpha) while rolling"),
]


def _contact(factor: float) -> RollSlip:
    """MuJoCo's sphere on the plane with friction ``factor`` times the predicted threshold (default alpha)."""
    mu = factor * 2 / 7 * float(tan(alpha.default))
    return RollSlip("sphere", R, (0, alpha, 0), Rational(2, 7) * tan(alpha), mu, slide_joint="x", roll_joint="roll")


SCENES = [
    Scene("rolls", "Exercise 3.17: released from rest; with mu_H = 1.2 x 2/7 tan(alpha) the sphere rolls: "
          "phi'' = 5/(7R) g sin(alpha); MuJoCo's contact must produce the rolling itself, and its threshold "
          "between rolling and slipping must be 2/7 tan(alpha)", (0.0,), (0.0,), 1.0, {"gravity", "contact"},
          events=(_contact(1.2),)),
    Scene("slips", "Exercise 3.17: released from rest; with mu_H = 0.8 x 2/7 tan(alpha) the rolling solution "
          "does not hold: MuJoCo's sphere slips", (0.0,), (0.0,), 1.0, {"gravity", "contact"},
          events=(_contact(0.8),)),
]
