"""Trebuchet, phase 2 (projectile off the ground), Exercise A.15 (Figure A.23), solution (A.175)-(A.189).

The machine moves in the x-z plane; gravity acts in ``-e_z`` (``V_M = M g (l sin theta - h cos phi)``, (A.183)).
The throwing arm turns about the pivot at the origin by ``theta``: its short end (length ``l``) is at
``l [cos theta, 0, sin theta]``, its long end (length ``L``) at ``-L [cos theta, 0, sin theta]`` (A.176), so
``theta`` turns ``e_x`` towards ``e_z``, i.e. about ``-e_y``. The counterweight ``M`` (a point mass) hangs on
a massless rod of length ``h`` from the short end; ``phi`` is its *absolute* angle from the downward vertical,
``p_0^M = [l cos theta - h sin phi, 0, l sin theta - h cos phi]`` (A.176a): ``phi`` turns about ``+e_y``. The
projectile ``m`` (a point mass) hangs on the massless sling of length ``r`` from the long end; ``psi`` is its
absolute angle from the downward vertical, ``p_0^m = [-L cos theta + r sin psi, 0, -L sin theta - r cos psi]``
(A.176b): ``psi`` turns about ``-e_y``. The moments of inertia of arm, counterweight and projectile are
neglected (exercise text), rod and sling are massless. The arm's moment of inertia about the pivot is neglected
too, which (Steiner) puts the arm's mass ``m_A`` at the pivot: it then enters neither ``T`` (A.181) nor ``V``
(A.183)-(A.186). The model keeps ``m_A`` as a point mass at the pivot because MuJoCo refuses a massless moving
body (``mass and inertia of moving bodies must be larger than mjMINVAL``) and the arm carries two bodies.

Phase 2 is free: three coordinates ``q = [theta, phi, psi]`` (A.175), no constraint, equations of motion
(A.187)-(A.189). Phase 1 (projectile on the ground, ``psi = psi(theta)`` (A.178)) is ``models/trebuchet.py``.

Tree and map (the lecture's angles are absolute, the tree's relative): world -(``theta``: revolute about
``-y``, ``theta``)-> arm -(``weight``: revolute about ``+y`` at ``[l, 0, 0]``, ``theta + phi``)-> counterweight,
arm -(``sling``: revolute about ``-y`` at ``[-L, 0, 0]``, ``psi - theta``)-> projectile. The point masses sit at
``[0, 0, -h]`` and ``[0, 0, -r]`` in their frames.

Singular configurations: ``det M = M m h² r² (m L² cos²(theta - psi) + M l² cos²(theta + phi))`` (from (A.188))
vanishes where the rod and the sling both lie along the arm's line (``cos(theta + phi) = cos(theta - psi) = 0``):
the arm can then turn while neither mass moves. That set has measure zero; the drawn states use the
full angle ranges, and the forward-dynamics tolerance scales with cond(M).
"""

from sympy import Matrix, cos, sin

from harness.modeling import WORLD, Claim, Coordinate, Gravity, Joint, Link, Parameter, Scene, System, standard_gravity

M = Parameter("M", 100.0, "kg", "mass of the counterweight (point mass)")
m = Parameter("m", 5.0, "kg", "mass of the projectile (point mass)")
L = Parameter("L", 2.0, "m", "length of the long (throwing) end of the arm")
l = Parameter("l", 0.5, "m", "length of the short end of the arm (counterweight side)")
h = Parameter("h", 0.6, "m", "length of the counterweight's pendulum rod")
r = Parameter("r", 3.0, "m", "length of the sling")
m_A = Parameter("m_A", 20.0, "kg", "mass of the throwing arm, at the pivot (it enters neither T nor V, see above)")
g = standard_gravity()

theta = Coordinate("theta", "rad", "angle of the throwing arm (A.175)")
phi = Coordinate("phi", "rad", "absolute angle of the counterweight's rod from the downward vertical")
psi = Coordinate("psi", "rad", "absolute angle of the sling from the downward vertical")

# The mechanism, shared with phase 1 (models/trebuchet.py), which differs only in the sling's angle.
LINKS = (
    Link("arm", m_A, (0, 0, 0), description="throwing arm: mass at the pivot, no moment of inertia; "
                                            "x from the long end towards the short end"),
    Link("counterweight", M, (0, 0, -h), description="point mass M on its rod"),
    Link("projectile", m, (0, 0, -r), description="point mass m on the sling"),
)


def mechanism_joints(psi_of_q) -> tuple:
    """Arm, counterweight rod and sling; the sling's absolute angle ``psi`` as a function of the coordinates."""
    return (
        Joint("theta", "revolute", WORLD, "arm", axis=(0, -1, 0)),
        Joint("weight", "revolute", "arm", "counterweight", axis=(0, 1, 0), origin=(l, 0, 0), phi=theta + phi),
        Joint("sling", "revolute", "arm", "projectile", axis=(0, -1, 0), origin=(-L, 0, 0), phi=psi_of_q - theta),
    )


SYSTEM = System(
    name="trebuchet_free",
    title="Trebuchet, phase 2 (projectile in the air)",
    lecture="Exercise A.15, phase 2; (A.175)-(A.189)",
    coordinates=(theta, phi, psi),
    links=LINKS,
    joints=mechanism_joints(psi),
    gravity=Gravity(g, (0, 0, -1)),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
w_th, w_ph, w_ps = theta.rate, phi.rate, psi.rate
M_printed = Matrix([
    [L**2 * m + l**2 * M, M * l * h * sin(theta + phi), m * L * r * sin(theta - psi)],
    [M * l * h * sin(theta + phi), M * h**2, 0],
    [m * L * r * sin(theta - psi), 0, m * r**2]])                                         # (A.188)
g_velocity = Matrix([                                                                     # (A.189), q̇ terms
    -m * L * r * cos(theta - psi) * w_ps**2 + M * l * h * cos(theta + phi) * w_ph**2,
    M * l * h * cos(theta + phi) * w_th**2,
    m * L * r * cos(theta - psi) * w_th**2])
g_gravity = Matrix([                                                                      # (A.189), the rest
    -g * (m * L - M * l) * cos(theta),
    M * g * h * sin(phi),
    m * g * r * sin(psi)])
qdd = Matrix([c.accel for c in SYSTEM.coordinates])
_split = "(A.187) lumps C q̇ and the gravity terms into one vector g(q, q̇); split here by degree in q̇"

CLAIMS = [
    Claim("(A.176a)", "position:counterweight",
          Matrix([l * cos(theta) - h * sin(phi), 0, l * sin(theta) - h * cos(phi)]),
          "position of the counterweight"),
    Claim("(A.176b)", "position:projectile",
          Matrix([-L * cos(theta) + r * sin(psi), 0, -L * sin(theta) - r * cos(psi)]),
          "position of the projectile"),
    Claim("(A.179a)", "v:counterweight", Matrix([-l * sin(theta) * w_th - h * cos(phi) * w_ph, 0,
                                                 l * cos(theta) * w_th + h * sin(phi) * w_ph]),
          "velocity of the counterweight"),
    Claim("(A.179b)", "v:projectile", Matrix([L * sin(theta) * w_th + r * cos(psi) * w_ps, 0,
                                              -L * cos(theta) * w_th + r * sin(psi) * w_ps]),
          "velocity of the projectile in phase 2"),
    Claim("(A.181b)", "T", M * (l**2 * w_th**2 + h**2 * w_ph**2 + 2 * l * h * w_th * w_ph * sin(theta + phi)) / 2
          + m * (L**2 * w_th**2 + r**2 * w_ps**2 + 2 * L * r * w_th * w_ps * sin(theta - psi)) / 2,
          "kinetic energy T_2"),
    Claim("(A.183), (A.184), (A.186)", "V", M * g * (l * sin(theta) - h * cos(phi))
          + m * g * (-L * sin(theta) - r * cos(psi)), "potential energy V_2 = V_M + V_m",
          note="the constants V_M,0 and V_m,0 read as 0 (reference level z = 0 through the pivot)"),
    Claim("(A.188)", "M", M_printed, "mass matrix"),
    Claim("(A.189), q̇ terms", "Cqd", g_velocity, "the terms of g(q, q̇) quadratic in q̇: C(q, q̇) q̇", note=_split),
    Claim("(A.189), gravity terms", "g", g_gravity, "the terms of g(q, q̇) without q̇: ∂V/∂q (5.96)", note=_split),
    Claim("(A.187)-(A.189)", "eom", M_printed * qdd + g_velocity + g_gravity, "M(q) q̈ + g(q, q̇) = 0"),
]

SCENES = [
    Scene("swing", "Exercise A.15, phase 2 alone (A.187): from rest with the arm at 0.2 rad, the counterweight "
          "hanging and the sling horizontal; the full throw with its lift-off event is trebuchet/throw",
          (0.2, 0.0, 1.5708), (0.0, 0.0, 0.0), 1.0, {"gravity"}),
]
