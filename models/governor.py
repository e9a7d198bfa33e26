"""Centrifugal governor, Exercise A.7 (Figure A.14), solution (A.59)-(A.69).

A massless linkage turns about the vertical ``e_z`` axis by the angle ``phi`` (``phi_dot = omega_phi``), driven
by the external torque ``tau`` about ``e_z`` ((A.65): ``f_phi = tau``, ``f_alpha = 0``). Two massless arms of
length ``l`` hang from a pin on the axis at height ``h``; each carries a point mass ``m`` at its end. ``alpha``
is the angle of the arms from the downward vertical, the same for both arms (symmetric structure). Gravity
acts in ``-e_z``. The mass in the plane of ``x`` rotated by ``phi`` sits at (A.59)
``p_0^m = [l sin(alpha) cos(phi), l sin(alpha) sin(phi), h - l cos(alpha)]``, the other one opposite to it,
``[-l sin(alpha) cos(phi), -l sin(alpha) sin(phi), h - l cos(alpha)]``. The sleeve ``A`` and its rods are
massless and add nothing to T, V (the lecture's own assumption).

Tree and map theta = phi(q) (symmetric arms): the joint ``phi`` turns the (massless) spindle about ``z`` at
the pin height ``h``; arm 1 hangs from the spindle by a revolute joint about the spindle's ``y`` axis with
``theta_alpha_1 = -alpha`` (a rotation by ``-alpha`` about ``y`` swings ``[0, 0, -l]`` towards ``+x``); arm 2 hangs
from arm 1 about the same pin axis with the *relative* angle ``theta_alpha_2 = 2 alpha`` (absolute ``+alpha``:
the mirror image). Arm 2 is a child of arm 1 rather than of the spindle because MuJoCo refuses a massless
moving body with two children ("mass and inertia of moving bodies must be larger than mjMINVAL"); the
massless spindle is merged with arm 1 into one MuJoCo body. The external torque is a torque on the joint
``phi`` (between the world and the turning linkage), which is the same generalized force as (A.65).

Singularity: ``M = diag(2 m l² sin²(alpha), 2 m l²)`` is singular at ``alpha = 0`` and ``alpha = pi`` (masses on
the axis, ``phi`` undefined). The drawn states keep ``alpha`` in ``[0.2, pi - 0.2]``, 0.2 rad away from both.

Steady state: (A.69) ``alpha_s = arccos(g / (l phi_dot_s²))`` is claimed as the value of ``alpha`` at which, with
``alpha_dot = 0`` and ``tau = 0``, every source's q̈ vanishes (kind ``steady:alpha``), on the states of its stated
condition ``phi_dot_s ≥ sqrt(g/l)`` (elsewhere the arccos is not real). The centrifugal force the text names after
(A.69), ``f_f = m omega_phi² l cos(alpha)``, is claimed against ``m phi_dot² r`` with ``r`` the point mass's
distance from the axis of rotation, from (A.59) of the model's kinematics. (A.68) is a condition (its left side
vanishes exactly at the steady states), not a value; (A.69) solves it and is claimed.
"""

import math

from sympy import Matrix, acos, cos, sin

from harness.derivation.bodies import centre_of_mass
from harness.modeling import (WORLD, Claim, Constant, Coordinate, Gravity, Input, Joint, JointInput, Link, Parameter,
                              Printed, Scene, System, standard_gravity)

m = Parameter("m", 2.0, "kg", "each of the two point masses")
l = Parameter("l", 0.5, "m", "length of an arm (pin to point mass)")
h = Parameter("h", 1.0, "m", "height of the arms' pin on the axis of rotation")
g = standard_gravity()

phi = Coordinate("phi", "rad", "angle of rotation about the vertical axis e_z")
alpha = Coordinate("alpha", "rad", "angle of the arms from the downward vertical", range=(0.2, math.pi - 0.2))
tau = Input("tau", "N m", "external torque about e_z driving the governor")

SYSTEM = System(
    name="governor",
    title="Centrifugal governor",
    lecture="Exercise A.7; (A.59)-(A.67)",
    coordinates=(phi, alpha),
    links=(
        Link("spindle", description="massless linkage turning about e_z (merged with arm_1 in MuJoCo)"),
        Link("arm_1", m, (0, 0, -l), description="point mass m at the end of arm 1"),
        Link("arm_2", m, (0, 0, -l), description="point mass m at the end of arm 2"),
    ),
    joints=(
        Joint("phi", "revolute", WORLD, "spindle", axis="z", origin=(0, 0, h)),
        Joint("alpha_1", "revolute", "spindle", "arm_1", axis="y", phi=-alpha),
        Joint("alpha_2", "revolute", "arm_1", "arm_2", axis="y", phi=2 * alpha),
    ),
    gravity=Gravity(g, (0, 0, -1)),
    forces=(JointInput("drive", "phi", tau),),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
w_p, w_a = phi.rate, alpha.rate
sa, ca = sin(alpha), cos(alpha)
_p_m = centre_of_mass(SYSTEM, "arm_1")   # the mass's position (A.59) from the model's own kinematics
# the velocity (A.60) as its claim defines it, and the vector (A.61) prints beside it
_p_dot_0m = Matrix([Printed(f"p_0m{x}_dot", "m/s", "the velocity (A.60) of the point mass") for x in "xyz"])
_p_dot_m = Matrix([Printed(f"p_m{x}_dot", "m/s", "printed in (A.61)") for x in "xyz"])
CLAIMS = [
    Claim("(A.59)", "position:arm_1", Matrix([l * sa * cos(phi), l * sa * sin(phi), h - l * ca]),
          "position of the point mass rotated by phi against the x axis"),
    Claim("(A.60)", "v:arm_1", l * Matrix([w_a * ca * cos(phi) - w_p * sa * sin(phi),
                                            w_a * ca * sin(phi) + w_p * sa * cos(phi), w_a * sa]),
          "velocity of the point mass", note="printed with omega_alpha, omega_phi: read as alpha_dot, phi_dot",
          defines=_p_dot_0m),
    Claim("(A.61)", "T", 2 * m * (_p_dot_0m.T * _p_dot_m)[0] / 2, "kinetic energy of both point masses, T = 2 ½ m "
          "(ṗ_0^m)ᵀ ṗ_m", ingredients=("(A.60)",)),
    Claim("(A.62)", "T", m * l**2 * (w_a**2 + w_p**2 * sa**2), "kinetic energy of both point masses",
          note="printed with omega_alpha, omega_phi: read as alpha_dot, phi_dot"),
    Claim("(A.63)", "V", 2 * m * g * (h - l * ca), "potential energy, zero at p_0z^m = 0"),
    Claim("(A.65)", "f_np", Matrix([tau, 0]), "generalized forces f_phi = tau, f_alpha = 0"),
    Claim("(A.66a)", "eom", 2 * m * l**2 * (phi.accel * sa**2 + 2 * w_p * w_a * sa * ca) - 0 - tau,
          "Euler-Lagrange equation of phi", index=(0,)),
    Claim("(A.66b)", "eom", 2 * m * l**2 * alpha.accel - 2 * m * l * sa * (l * w_p**2 * ca - g) - 0,
          "Euler-Lagrange equation of alpha", index=(1,)),
    Claim("(A.67a)", "eom", 2 * m * l**2 * sa**2 * phi.accel - (tau - 4 * m * l**2 * w_p * w_a * sa * ca),
          "phi_ddot solved", index=(0,),
          note="printed solved, phi_ddot = (tau - 4 m l² phi_dot alpha_dot sin cos)/(2 m l² sin²(alpha)); "
               "transcribed multiplied by the printed denominator (non-zero in the drawn states) so that the "
               "residual is a generalized force, the unit the claims core scales eom residuals in"),
    Claim("(A.67b)", "eom", alpha.accel - sa * (l * w_p**2 * ca - g) / l, "alpha_ddot solved", index=(1,)),
    Claim("(A.64)", "L", m * l**2 * (w_a**2 + w_p**2 * sa**2) - 2 * m * g * (h - l * ca), "Lagrange function T - V",
          note="printed with omega_alpha, omega_phi: read as alpha_dot, phi_dot"),
    Claim("(A.69)", "steady:alpha", acos(g / (l * w_p**2)),
          "steady-state angle at the constant angular velocity phi_dot_s (alpha_dot = 0, tau = 0)",
          note="printed with phi_dot_s: the drawn phi_dot; valid for phi_dot_s >= sqrt(g/l), as printed beside it"),
    Claim("f_f after (A.69)", "parameter", m * w_p**2 * l * ca,
          "centrifugal force on one point mass at the steady state (force balance of the freed mass)",
          reference=m * w_p**2 * (_p_m[0] * cos(phi) + _p_m[1] * sin(phi)),
          note="printed with omega_phi: read as phi_dot; reference m phi_dot² times the mass's distance from e_z "
               "in its plane of rotation (the plane at the angle phi, (A.59)), from the model's position of the mass"),
]

SCENES = [
    Scene("spin_up", "Exercise A.7, (A.67): spinning at 5 rad/s with the arms at alpha = 0.6 rad, the torque "
          "tau = 0.5 N m speeds the governor up; the arms rise towards the steady state (A.69)", (0.0, 0.6),
          (5.0, 0.0), 3.0, {"gravity", "inputs"}, inputs={tau: Constant(0.5)}),
    Scene("coast", "Exercise A.7, (A.67), (A.69): coasting (tau = 0) at 6 rad/s with the arms released at "
          "alpha = 0.8 rad, below the steady angle arccos(g/(l omega^2)) = 0.99 rad; they swing up to 0.91 rad and "
          "back while phi_dot drops to 5 rad/s (angular momentum about e_z is conserved) (conservative)",
          (0.0, 0.8), (6.0, 0.0), 3.0, {"gravity"}),
]
