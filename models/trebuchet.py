"""Trebuchet, phase 1 (projectile sliding on the ground), Exercise A.15 (Figure A.23), solution (A.175)-(A.185).

Frames, masses and angles as in phase 2 (``models/trebuchet_free.py``): the machine moves in the x-z plane,
gravity acts in ``-e_z`` (A.183); the arm turns by ``theta`` about ``-e_y`` (short end ``l`` at
``l [cos theta, 0, sin theta]``, long end at ``-L [cos theta, 0, sin theta]``); the point mass ``M`` hangs on a
massless rod ``h`` at the absolute angle ``phi`` (about ``+e_y``), the point mass ``m`` on the massless sling
``r`` at the absolute angle ``psi`` (about ``-e_y``) (A.176). As there, the arm's mass ``m_A`` sits at the pivot
(its moment of inertia is neglected): it enters neither ``T`` nor ``V``; MuJoCo needs it (no massless moving body).

Phase 1: the projectile slides (without friction) on the ground at the height ``h_m = -L sin theta_0`` of its
start, ``theta = theta_0`` being the arm's initial angle. The constraint (A.177)
``L sin theta + r cos psi = L sin theta_0`` makes ``psi`` a function of ``theta`` (A.178):
``psi(theta) = arccos(L/r (sin theta_0 - sin theta))``. Lecture coordinates ``q = [theta, phi]``; the
projectile's potential is constant in this phase (A.185).

Tree and map: the tree of phase 2 with three joints and two lecture coordinates: ``theta`` (revolute about
``-y``, ``theta``), ``weight`` (revolute about ``+y`` at ``[l, 0, 0]``, ``theta + phi``), ``sling`` (revolute about
``-y`` at ``[-L, 0, 0]``, ``psi(theta) - theta``). The ground's normal force is the constraint force and does no
work; it never appears (the map is the constraint).

Singular points and drawn states: ``d psi/d theta = (L/r) cos theta / sqrt(1 - u²)`` with
``u = L/r (sin theta_0 - sin theta)`` blows up where ``|u| = 1`` (the sling vertical: the projectile would have
to leave the ground or the arm's tip to sink below it). Random parameters are drawn in ``[default/2, 2 default]``,
so ``L/r ≤ 4 · 2/3 = 8/3`` and ``theta_0 ∈ [0.1, 0.4]``; the drawn range ``theta ∈ [0.1, 0.4]`` keeps
``|sin theta_0 - sin theta| ≤ 0.29`` and so ``|u| ≤ 0.78`` (``psi`` at least 0.67 rad away from 0 and π).
States with ``theta > theta_0`` (the arm's tip below the ground: ``psi > π/2``) are drawn too; the equations
hold there as well. ``theta_0`` is small (0.2 rad) so that one fixed range of ``theta`` suits every drawn
``theta_0`` (a range cannot depend on the parameters).
"""

from sympy import Matrix, acos, cos, diff, sin

from harness.modeling import Claim, Closure, Coordinate, Gravity, LiftOff, Parameter, Point, Scene, System
from models.trebuchet_free import LINKS, L, M, g, h, l, m, m_A, mechanism_joints, r
from models.trebuchet_free import psi as psi_free

theta_0 = Parameter("theta_0", 0.2, "rad", "initial angle of the arm (projectile on the ground at -L sin theta_0)")

theta = Coordinate("theta", "rad", "angle of the throwing arm (A.175); drawn in [0.1, 0.4] (see above)",
                   range=(0.1, 0.4))
phi = Coordinate("phi", "rad", "absolute angle of the counterweight's rod from the downward vertical")

psi = acos(L / r * (sin(theta_0) - sin(theta)))  # (A.178)

SYSTEM = System(
    name="trebuchet",
    title="Trebuchet, phase 1 (projectile on the ground)",
    lecture="Exercise A.15, phase 1; (A.175)-(A.185)",
    parameters=(M, m, L, l, h, r, theta_0, m_A, g),  # all of them: theta_0 in this order (the draws of the checks)
    coordinates=(theta, phi),
    links=LINKS,
    joints=mechanism_joints(psi),
    gravity=Gravity(g, (0, 0, -1)),
    # (A.177): the ground holds the projectile at the height of its start
    closures=(Closure("ground", Point("projectile", (0, 0, -r), "projectile_centre"), (0, 0, 1), -L * sin(theta_0)),),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
w_th, w_ph = theta.rate, phi.rate
psi_printed = acos(L / r * (sin(theta_0) - sin(theta)))   # (A.178), as printed
w_ps = diff(psi_printed, theta) * w_th                    # (A.182)
V_1 = M * g * (l * sin(theta) - h * cos(phi))             # (A.183), (A.185)

CLAIMS = [
    Claim("(A.176a)", "position:counterweight",
          Matrix([l * cos(theta) - h * sin(phi), 0, l * sin(theta) - h * cos(phi)]),
          "position of the counterweight"),
    Claim("(A.176b), (A.178)", "position:projectile",
          Matrix([-L * cos(theta) + r * sin(psi_printed), 0, -L * sin(theta) - r * cos(psi_printed)]),
          "position of the projectile with psi = psi(theta); its z-component is the constraint (A.177)"),
    Claim("(A.179a)", "v:counterweight", Matrix([-l * sin(theta) * w_th - h * cos(phi) * w_ph, 0,
                                                 l * cos(theta) * w_th + h * sin(phi) * w_ph]),
          "velocity of the counterweight"),
    Claim("(A.180)", "v:projectile", Matrix([L * sin(theta) * w_th + r * cos(psi_printed) * w_ps, 0, 0]),
          "velocity of the projectile in phase 1 (on the ground)",
          note="psi = psi(theta) (A.178) and psi_dot = ∂psi/∂theta theta_dot (A.182), as in (A.181a)"),
    Claim("(A.181a), (A.182)", "T",
          M * (l**2 * w_th**2 + h**2 * w_ph**2 + 2 * l * h * w_th * w_ph * sin(theta + phi)) / 2
          + m * (L * sin(theta) * w_th + r * cos(psi_printed) * w_ps)**2 / 2,
          "kinetic energy T_1 with psi = psi(theta), psi_dot = ∂psi/∂theta theta_dot"),
    Claim("(A.183), (A.185)", "g", Matrix([diff(V_1, theta), diff(V_1, phi)]),
          "potential forces ∂V_1/∂q (5.96) of V_1 = V_M",
          note="V_1 is printed up to the constant V_M,0 and without the projectile's potential, which is constant "
               "in phase 1; compared as g = ∂V_1/∂q, which no constant changes"),
]

_lift_off = LiftOff("trebuchet_free", to_free=(theta, phi, psi),
                    height=L * sin(theta_0) - L * sin(theta) - r * cos(psi_free))

SCENES = [
    Scene("throw", "Exercise A.15: released from rest with the arm at theta_0 and the counterweight hanging; the "
          "projectile slides on the ground (phase 1, (A.185)) until the ground's normal force vanishes, then "
          "flies on its sling (phase 2, (A.187)-(A.189))", (0.2, 0.0), (0.0, 0.0), 1.0, {"gravity"},
          events=(_lift_off,)),
]
