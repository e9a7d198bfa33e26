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

from harness.modeling.system import Coordinate, Gravity, Joint, Link, Parameter, System, WORLD

M = Parameter("M", 100.0, "kg", "mass of the counterweight (point mass)")
m = Parameter("m", 5.0, "kg", "mass of the projectile (point mass)")
L = Parameter("L", 2.0, "m", "length of the long (throwing) end of the arm")
l = Parameter("l", 0.5, "m", "length of the short end of the arm (counterweight side)")
h = Parameter("h", 0.6, "m", "length of the counterweight's pendulum rod")
r = Parameter("r", 3.0, "m", "length of the sling")
m_A = Parameter("m_A", 20.0, "kg", "mass of the throwing arm, at the pivot (it enters neither T nor V, see above)")
g = Parameter("g", 9.81, "m/s^2", "acceleration due to gravity")

theta = Coordinate("theta", "rad", "angle of the throwing arm (A.175)")
phi = Coordinate("phi", "rad", "absolute angle of the counterweight's rod from the downward vertical")
psi = Coordinate("psi", "rad", "absolute angle of the sling from the downward vertical")

# The mechanism, shared with phase 1 (models/trebuchet.py), which differs only in the sling's angle.
LINKS = (
    Link("arm", m_A.symbol, (0, 0, 0), description="throwing arm: mass at the pivot, no moment of inertia; "
                                                    "x from the long end towards the short end"),
    Link("counterweight", M.symbol, (0, 0, -h.symbol), description="point mass M on its rod"),
    Link("projectile", m.symbol, (0, 0, -r.symbol), description="point mass m on the sling"),
)


def mechanism_joints(psi_of_q) -> tuple:
    """Arm, counterweight rod and sling; the sling's absolute angle ``psi`` as a function of the coordinates."""
    return (
        Joint("theta", "revolute", WORLD, "arm", axis=(0, -1, 0)),
        Joint("weight", "revolute", "arm", "counterweight", axis=(0, 1, 0), origin=(l.symbol, 0, 0),
              phi=theta.symbol + phi.symbol),
        Joint("sling", "revolute", "arm", "projectile", axis=(0, -1, 0), origin=(-L.symbol, 0, 0),
              phi=psi_of_q - theta.symbol),
    )


SYSTEM = System(
    name="trebuchet_free",
    title="Trebuchet, phase 2 (projectile in the air)",
    lecture="Exercise A.15, phase 2; (A.175)-(A.189)",
    parameters=(M, m, L, l, h, r, m_A, g),
    coordinates=(theta, phi, psi),
    links=LINKS,
    joints=mechanism_joints(psi.symbol),
    gravity=Gravity(g.symbol, (0, 0, -1)),
    doc=__doc__,
)

# ----------------------------------------------------------------------------- the lecture's printed equations
import sympy as _sp  # noqa: E402

from harness.modeling.claims import Claim  # noqa: E402

_th, _ph, _ps = theta.symbol, phi.symbol, psi.symbol
_thd, _phd, _psd = theta.rate, phi.rate, psi.rate
_M, _m, _L, _l, _h, _r, _g = (x.symbol for x in (M, m, L, l, h, r, g))
_M_printed = _sp.Matrix([
    [_L**2 * _m + _l**2 * _M, _M * _l * _h * _sp.sin(_th + _ph), _m * _L * _r * _sp.sin(_th - _ps)],
    [_M * _l * _h * _sp.sin(_th + _ph), _M * _h**2, 0],
    [_m * _L * _r * _sp.sin(_th - _ps), 0, _m * _r**2]])                                   # (A.188)
_g_velocity = _sp.Matrix([                                                                  # (A.189), q̇ terms
    -_m * _L * _r * _sp.cos(_th - _ps) * _psd**2 + _M * _l * _h * _sp.cos(_th + _ph) * _phd**2,
    _M * _l * _h * _sp.cos(_th + _ph) * _thd**2,
    _m * _L * _r * _sp.cos(_th - _ps) * _thd**2])
_g_gravity = _sp.Matrix([                                                                   # (A.189), the rest
    -_g * (_m * _L - _M * _l) * _sp.cos(_th),
    _M * _g * _h * _sp.sin(_ph),
    _m * _g * _r * _sp.sin(_ps)])
_qdd = _sp.Matrix([c.accel for c in SYSTEM.coordinates])

CLAIMS = [
    Claim("(A.176a)", "position:counterweight",
          _sp.Matrix([_l * _sp.cos(_th) - _h * _sp.sin(_ph), 0, _l * _sp.sin(_th) - _h * _sp.cos(_ph)]),
          "position of the counterweight"),
    Claim("(A.176b)", "position:projectile",
          _sp.Matrix([-_L * _sp.cos(_th) + _r * _sp.sin(_ps), 0, -_L * _sp.sin(_th) - _r * _sp.cos(_ps)]),
          "position of the projectile"),
    Claim("(A.181b)", "T", _M * (_l**2 * _thd**2 + _h**2 * _phd**2 + 2 * _l * _h * _thd * _phd * _sp.sin(_th + _ph)) / 2
          + _m * (_L**2 * _thd**2 + _r**2 * _psd**2 + 2 * _L * _r * _thd * _psd * _sp.sin(_th - _ps)) / 2,
          "kinetic energy T_2"),
    Claim("(A.183), (A.184), (A.186)", "V", _M * _g * (_l * _sp.sin(_th) - _h * _sp.cos(_ph))
          + _m * _g * (-_L * _sp.sin(_th) - _r * _sp.cos(_ps)), "potential energy V_2 = V_M + V_m",
          note="the constants V_M,0 and V_m,0 read as 0 (reference level z = 0 through the pivot)"),
    Claim("(A.188)", "M", _M_printed, "mass matrix"),
    Claim("(A.189), q̇ terms", "Cqd", _g_velocity, "the terms of g(q, q̇) quadratic in q̇: C(q, q̇) q̇",
          note="(A.187) lumps C q̇ and the gravity terms into one vector g(q, q̇); split here by degree in q̇"),
    Claim("(A.189), gravity terms", "g", _g_gravity, "the terms of g(q, q̇) without q̇: ∂V/∂q (5.96)",
          note="(A.187) lumps C q̇ and the gravity terms into one vector g(q, q̇); split here by degree in q̇"),
    Claim("(A.187)-(A.189)", "eom", _M_printed * _qdd + _g_velocity + _g_gravity, "M(q) q̈ + g(q, q̇) = 0"),
]

# ----------------------------------------------------------------------------- scenes
from harness.modeling.scenes import Scene  # noqa: E402

SCENES = [
    Scene("swing", "Exercise A.15, phase 2 alone (A.187): from rest with the arm at 0.2 rad, the counterweight "
          "hanging and the sling horizontal; the full throw with its lift-off event is trebuchet/throw",
          (0.2, 0.0, 1.5708), (0.0, 0.0, 0.0), 1.0, frozenset({"gravity"})),
]
